// Locating a point in a CGAL 3D triangulation (locate_from), and the cells
// that hold it once located at (c, lt, li, lj): c alone, or every cell
// around the facet, edge or vertex the point lies on (VoxelSides,
// seg2mesh --conforming and seg2tet check each voxel centre's side
// against all of them).
#pragma once
#include <iterator>
#include <vector>

namespace imgmesh {

// tr.locate(p, lt, li, lj, start), walking in floating point first
// (CGAL's inexact_locate, which its locate runs first only for the plain
// Epick kernel, not for the meshers' traits): a walk of many cells costs
// a plain orientation each, not a filtered one and a random draw. The
// exact walk from where it stops finds the same cell when one cell holds
// p strictly inside; else (p on a facet, edge or vertex, or outside the
// hull, where the walk decides which cell it finds) the exact walk from
// start, as locate alone would. near: where the floating-point walk starts
// instead of start (a cell nearer p), with the same answers.
template <class Tr>
typename Tr::Cell_handle locate_from(const Tr& tr, const typename Tr::Point& p, typename Tr::Locate_type& lt, int& li,
                                     int& lj, typename Tr::Cell_handle start,
                                     typename Tr::Cell_handle near = typename Tr::Cell_handle()) {
  typename Tr::Cell_handle c = tr.locate(p, lt, li, lj, tr.inexact_locate(p, near != typename Tr::Cell_handle() ? near : start));
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
