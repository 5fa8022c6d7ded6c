// Locating a point in a CGAL 3D triangulation (locate_from), and the cells
// that hold it once located at (c, lt, li, lj): c alone, or every cell
// around the facet, edge or vertex the point lies on (VoxelSides,
// seg2mesh --conforming and seg2tet check each voxel centre's side
// against all of them).
#pragma once
#include <CGAL/enum.h>

#include <iterator>
#include <vector>

namespace imgmesh {

// CGAL's inexact_locate (its remembering visibility walk in floating
// point, the same cells in the same order, at most 2,500 of them), each
// cell's four neighbours asked for from memory on arrival: the next cell
// is one of them, and its first read was the walk's cost (a chain of
// cache misses, cells lying scattered).
template <class Tr>
typename Tr::Cell_handle inexact_walk(const Tr& tr, const typename Tr::Point& p, typename Tr::Cell_handle c) {
  using Ch = typename Tr::Cell_handle;
  if (tr.dimension() < 3) return c;
  if (c == Ch()) c = tr.infinite_cell();
  int infinite;
  if (c->has_vertex(tr.infinite_vertex(), infinite)) c = c->neighbor(infinite);
  Ch previous;
  for (int turns = 2500; turns > 0; --turns) {
    for (int i = 0; i < 4; ++i) __builtin_prefetch(&*c->neighbor(i));
    const typename Tr::Point* pts[4] = {&c->vertex(0)->point(), &c->vertex(1)->point(), &c->vertex(2)->point(),
                                        &c->vertex(3)->point()};
    int i = 0;
    for (; i < 4; ++i) {
      const Ch next = c->neighbor(i);
      if (next == previous) continue;
      // p in place of vertex i: negative when p lies beyond facet i.
      const typename Tr::Point* own = pts[i];
      pts[i] = &p;
      const bool beyond = tr.inexact_orientation(*pts[0], *pts[1], *pts[2], *pts[3]) == CGAL::NEGATIVE;
      pts[i] = own;
      if (!beyond) continue;
      if (next->has_vertex(tr.infinite_vertex())) return next;  // outside the hull
      previous = c;
      c = next;
      break;
    }
    if (i == 4) return c;
  }
  return c;
}

// tr.locate(p, lt, li, lj, start), walking in floating point first
// (inexact_walk; CGAL's locate runs its inexact_locate first only for the
// plain Epick kernel, not for the meshers' traits): a walk of many cells
// costs a plain orientation each, not a filtered one and a random draw.
// The exact walk from where it stops finds the same cell when one cell
// holds p strictly inside; else (p on a facet, edge or vertex, or outside
// the hull, where the walk decides which cell it finds) the exact walk
// from start, as locate alone would. near: where the floating-point walk
// starts instead of start (a cell nearer p), with the same answers.
template <class Tr>
typename Tr::Cell_handle locate_from(const Tr& tr, const typename Tr::Point& p, typename Tr::Locate_type& lt, int& li,
                                     int& lj, typename Tr::Cell_handle start,
                                     typename Tr::Cell_handle near = typename Tr::Cell_handle()) {
  typename Tr::Cell_handle c = tr.locate(p, lt, li, lj, inexact_walk(tr, p, near != typename Tr::Cell_handle() ? near : start));
  if (lt != Tr::CELL) c = tr.locate(p, lt, li, lj, start);
  return c;
}

template <class Tr>
void located_cells(const Tr& tr, typename Tr::Cell_handle c, typename Tr::Locate_type lt, int li, int lj,
                   std::vector<typename Tr::Cell_handle>& out) {
  out.assign(1, c);
  if (lt == Tr::FACET) {
    out.push_back(c->neighbor(li));
  } else if (lt == Tr::EDGE) {
    out.clear();
    auto cc = tr.incident_cells(c, li, lj), done = cc;
    do out.push_back(cc); while (++cc != done);
  } else if (lt == Tr::VERTEX) {
    out.clear();
    tr.incident_cells(c->vertex(li), std::back_inserter(out));
  }
}

} // namespace imgmesh
