// Untangling after smoothing (surface_nets.hpp): Frisken's relaxation keeps
// every vertex in its cell but may fold a label's surface onto itself where
// a curve bends tightly (noisy maps: two triangles sharing a vertex
// overlapping). The vertices of every intersecting pair, per label surface
// (exact predicates, lib/mesh), go halfway back to their corners, and after
// kSnap halvings onto them. At the corners the mesh is bdCA(L) per label,
// which is embedded; every round moves some vertex that is not at its
// corner (a pair of triangles all at their corners cannot intersect), so
// the loop ends.
#include "surfacenets/surface_nets.hpp"

#include "mesh/embedding.hpp"
#include "util/error.hpp"

#include <algorithm>
#include <set>

namespace imgmesh {
namespace {
constexpr int kSnap = 6;
constexpr std::size_t kPairsCap = 1u << 20;
} // namespace

std::size_t untangle_interface_mesh(InterfaceMesh& m, const std::vector<Vec3>& rest) {
  if (rest.size() != m.points.size()) throw Error("untangle_interface_mesh: one rest position a vertex is needed");
  std::set<std::int32_t> labels;
  for (const auto& l : m.labels) labels.insert(l.begin(), l.end());
  std::vector<std::uint8_t> halvings(m.points.size(), 0), marked(m.points.size(), 0);
  // Labels to test this round: all at first, then those with a triangle at
  // a vertex moved last round (the others' triangles and splits are as when
  // they tested clean).
  std::set<std::int32_t> dirty = labels;
  std::size_t moved_total = 0;
  for (;;) {
    std::size_t pairs = 0, moved = 0;
    std::fill(marked.begin(), marked.end(), 0);
    for (std::int32_t l : dirty) {
      const auto tris = label_triangles(m, l);
      if (tris.empty()) continue;
      const SurfaceGeometry g(m.points, tris, std::vector<int>(tris.size(), 0), 1);
      for (const auto& p : g.intersecting_pairs(kPairsCap)) {
        ++pairs;
        for (std::size_t t : p)
          for (int v : tris[t]) marked[std::size_t(v)] |= m.points[std::size_t(v)] != rest[std::size_t(v)];
      }
    }
    if (pairs == 0) return moved_total;
    for (std::size_t v = 0; v < m.points.size(); ++v) {
      if (!marked[v]) continue;
      ++moved;
      if (++halvings[v] >= kSnap) {
        m.points[v] = rest[v];
        continue;
      }
      for (int a = 0; a < 3; ++a) m.points[v][std::size_t(a)] = (m.points[v][std::size_t(a)] + rest[v][std::size_t(a)]) / 2;
    }
    if (moved == 0) throw Error("untangle_interface_mesh: triangles at their voxel corners intersect (a bug)");
    moved_total += moved;
    dirty.clear();
    for (std::size_t f = 0; f < m.quads.size(); ++f)
      for (int v : m.quads[f])
        if (marked[std::size_t(v)]) dirty.insert(m.labels[f].begin(), m.labels[f].end());
    split_quads(m);
  }
}

} // namespace imgmesh
