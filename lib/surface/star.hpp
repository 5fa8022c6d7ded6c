// The star of a vertex of W: the cells and the vertices around it, listed
// as CGAL's incident_cells, incident_cells_threadsafe, adjacent_vertices
// and adjacent_vertices_threadsafe list them, in the same order (restricted
// facets' ties and V(p)'s half-spaces, which HandleDetection clips by in
// turn, follow it), without their heap work: a stack and a vector per call,
// and in the thread-safe forms a hash-set node per cell and per vertex
// (on the bunny 326,000 allocations; on the elephant these walks were 13%
// of the CPU samples).
#pragma once
#include "mesh/located_cells.hpp"
#include "mesh/star_walk.hpp"
#include "surface/delaunay_types.hpp"

#include <cstdint>
#include <iterator>
#include <vector>

namespace imgmesh::surface_detail {

// A set of nonzero keys (addresses of cells and vertices, cube keys + 1)
// for one walk at a time: open addressing, at most a quarter full;
// clear() forgets only what went in.
class KeySet {
public:
  // True if key was not in the set.
  bool insert(std::uint64_t key) {
    if (4 * (used_.size() + 1) > slots_.size()) grow();
    std::size_t h = slot(key);
    while (slots_[h] != 0) {
      if (slots_[h] == key) return false;
      h = (h + 1) & (slots_.size() - 1);
    }
    slots_[h] = key;
    used_.push_back(h);
    return true;
  }
  bool insert(const void* p) { return insert(std::uint64_t(reinterpret_cast<std::uintptr_t>(p))); }
  void clear() {
    for (std::size_t h : used_) slots_[h] = 0;
    used_.clear();
  }

private:
  std::size_t slot(std::uint64_t key) const { return std::size_t((key * 0x9E3779B97F4A7C15ull) >> shift_); }
  void grow() {
    std::vector<std::uint64_t> old;
    old.reserve(used_.size());
    for (std::size_t h : used_) old.push_back(slots_[h]);
    slots_.assign(slots_.empty() ? 256 : 2 * slots_.size(), 0);
    shift_ = 64;
    for (std::size_t n = slots_.size(); n > 1; n >>= 1) --shift_;
    used_.clear();
    for (std::uint64_t key : old) insert(key);
  }
  std::vector<std::uint64_t> slots_;
  std::vector<std::size_t> used_;
  int shift_ = 64;
};

// tr.incident_cells(v, out): depth first from v->cell(), the cells marked
// in the triangulation as CGAL marks them (one thread at a time).
inline void star_cells(const Tr& tr, Vh v, std::vector<Ch>& out) {
  if (tr.dimension() < 3) {
    tr.incident_cells(v, std::back_inserter(out));
    return;
  }
  thread_local std::vector<Ch> stack;
  star_walk(v, out, stack, [](Ch) { return false; });
}

// tr.incident_cells_threadsafe(v, out): breadth first from v->cell(),
// nothing written to the triangulation (HandleDetection's threads).
inline void star_cells_threadsafe(const Tr& tr, Vh v, std::vector<Ch>& out) {
  if (tr.dimension() < 3) {
    tr.incident_cells_threadsafe(v, std::back_inserter(out));
    return;
  }
  thread_local KeySet seen;
  seen.clear();
  const std::size_t first = out.size();
  out.push_back(v->cell());
  seen.insert(&*v->cell());
  for (std::size_t head = first; head < out.size(); ++head) {
    const Ch c = out[head];
    for (int i = 0; i < 4; ++i) {
      if (c->vertex(i) == v) continue;
      const Ch n = c->neighbor(i);
      if (seen.insert(&*n)) out.push_back(n);
    }
  }
}

// Each vertex of `cells` but v (the infinite one too), once, where it
// first appears: CGAL's Vertex_extractor.
inline void star_vertices_of(Vh v, const std::vector<Ch>& cells, std::vector<Vh>& out) {
  thread_local KeySet seen;
  seen.clear();
  for (Ch c : cells)
    for (int j = 0; j < 4; ++j) {
      const Vh w = c->vertex(j);
      if (w != v && seen.insert(&*w)) out.push_back(w);
    }
}

// tr.adjacent_vertices(v, out) (one thread at a time): the vertices
// marked while listed, not kept in a set.
inline void star_vertices(const Tr& tr, Vh v, std::vector<Vh>& out) {
  if (tr.dimension() < 3) {
    tr.adjacent_vertices(v, std::back_inserter(out));
    return;
  }
  thread_local std::vector<Ch> cells;
  cells.clear();
  star_cells(tr, v, cells);
  const std::size_t first = out.size();
  for (Ch c : cells)
    for (int j = 0; j < 4; ++j) {
      const Vh w = c->vertex(j);
      if (w == v || w->info().listed) continue;
      w->info().listed = 1;
      out.push_back(w);
    }
  for (std::size_t k = first; k < out.size(); ++k) out[k]->info().listed = 0;
}

// tr.adjacent_vertices_threadsafe(v, out).
inline void star_vertices_threadsafe(const Tr& tr, Vh v, std::vector<Vh>& out) {
  if (tr.dimension() < 3) {
    tr.adjacent_vertices_threadsafe(v, std::back_inserter(out));
    return;
  }
  thread_local std::vector<Ch> cells;
  cells.clear();
  star_cells_threadsafe(tr, v, cells);
  star_vertices_of(v, cells, out);
}

// tr.nearest_vertex(p, start) (one thread at a time): the vertex of p's
// cell nearest to p, then while one is nearer, the nearest of its
// neighbours (ties: the vertex held). The walk to p's cell goes in floating
// point first (locate_from); from `start`, as CGAL's, when p is not
// inside one cell.
inline Vh nearest_vertex(const Tr& tr, const Point& p, Ch start) {
  if (tr.dimension() < 3) return tr.nearest_vertex(p, start);
  Tr::Locate_type lt;
  int li, lj;
  const Ch c = locate_from(tr, p, lt, li, lj, start);
  if (lt == Tr::VERTEX) return c->vertex(li);
  const auto compare = tr.geom_traits().compare_distance_3_object();
  const auto nearer = [&](Vh v, Vh w) {  // CGAL's nearest_vertex(p, v, w)
    if (tr.is_infinite(v)) return w;
    if (tr.is_infinite(w)) return v;
    return compare(p, w->point(), v->point()) == CGAL::SMALLER ? w : v;
  };
  Vh nearest = nearer(nearer(nearer(c->vertex(0), c->vertex(1)), c->vertex(2)), c->vertex(3));
  thread_local std::vector<Vh> around;
  for (;;) {
    around.clear();
    star_vertices(tr, nearest, around);
    Vh next = nearest;
    for (Vh w : around) next = nearer(next, w);
    if (next == nearest) return nearest;
    nearest = next;
  }
}

} // namespace imgmesh::surface_detail
