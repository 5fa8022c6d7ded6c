// Untangling after smoothing (surface_nets.hpp): Frisken's relaxation keeps
// every vertex in its cell but may fold the mesh where a curve bends
// tightly (noisy maps: two triangles sharing a vertex overlapping), and the
// sheets of two interfaces may cross. The vertices of every crossing pair
// of triangles (any labels: crossings.cpp, exact predicates) go halfway
// back to their corners, and after kSnap halvings onto them. Why it ends:
// at the corners the mesh is K(X) with each face split in two, which is
// embedded (two faces meet only in a shared voxel edge or corner, a shared
// edge or vertex of their triangles), so every crossing pair has a vertex
// off its corner, and every round moves all of those; a vertex moves at
// most kSnap times, then sits at its corner for good: at most kSnap times
// the vertices rounds. After the first search, a round tests only the
// quads at a moved vertex: any other pair is as it was when last tested,
// and did not cross then (a crossing pair had a vertex moved, so a quad of
// it is tested again).
#include "surfacenets/surface_nets.hpp"

#include "surfacenets/surface_nets_detail.hpp"
#include "util/error.hpp"

namespace imgmesh {
namespace {
constexpr int kSnap = 6;
} // namespace

std::size_t untangle_interface_mesh(InterfaceMesh& m, const std::vector<Vec3>& rest, unsigned threads) {
  if (rest.size() != m.points.size()) throw Error("untangle_interface_mesh: one rest position a vertex is needed");
  surfacenets_detail::CrossingSearch search(m, threads);
  std::vector<std::uint8_t> halvings(m.points.size(), 0), marked(m.points.size(), 0);
  std::size_t moves = 0;
  for (auto pairs = search.all_pairs(); !pairs.empty();) {
    std::vector<std::size_t> moving;
    for (const auto& p : pairs) {
      bool movable = false;
      for (std::size_t t : p)
        for (int v : m.triangles[t]) {
          if (m.points[std::size_t(v)] == rest[std::size_t(v)]) continue;
          movable = true;
          if (!marked[std::size_t(v)]) moving.push_back(std::size_t(v));
          marked[std::size_t(v)] = 1;
        }
      if (!movable) throw Error("untangle_interface_mesh: triangles at their voxel corners cross (a bug)");
    }
    for (std::size_t v : moving) {
      if (++halvings[v] >= kSnap) {
        m.points[v] = rest[v];
        continue;
      }
      for (std::size_t a = 0; a < 3; ++a) m.points[v][a] = (m.points[v][a] + rest[v][a]) / 2;
    }
    moves += moving.size();
    std::vector<std::size_t> moved_quads;
    for (std::size_t f = 0; f < m.quads.size(); ++f) {
      const auto& q = m.quads[f];
      if (!(marked[std::size_t(q[0])] | marked[std::size_t(q[1])] | marked[std::size_t(q[2])] | marked[std::size_t(q[3])]))
        continue;
      moved_quads.push_back(f);
      surfacenets_detail::split_quad(m, f);
      search.update(f);
    }
    for (std::size_t v : moving) marked[v] = 0;
    pairs = search.pairs(moved_quads);
  }
  return moves;
}

} // namespace imgmesh
