// Constrained smoothing of the surface-nets mesh (surface_nets.hpp):
// Frisken's relaxation, each vertex clamped into its voxel-corner cell.
// Done in continuous index coordinates, where a cell is an axis-aligned
// unit cube; the mean of the neighbours commutes with the affine map to
// world coordinates, so the result is the same as relaxing in world space
// and clamping to the (possibly rotated, anisotropic) cell.
#include "surfacenets/surface_nets.hpp"

#include "util/error.hpp"

#include <algorithm>

namespace imgmesh {

namespace {

// The rounds of relaxation; their two arrays of positions freed before the
// untangling's search is built (they would share its peak).
void relax(InterfaceMesh& m, const SmoothingOptions& o) {
  const std::size_t n = m.points.size();
  std::vector<Vec3> p(n), next(n);
  for (std::size_t v = 0; v < n; ++v) p[v] = m.grid.continuous_index(m.points[v]);
  for (int round = 0; round < o.rounds; ++round) {
    for (std::size_t v = 0; v < n; ++v) {
      next[v] = p[v];
      const std::size_t b = m.neighbour_offsets[v], e = m.neighbour_offsets[v + 1];
      if (m.kind[v] == InterfaceMesh::kJunction || b == e) continue;
      Vec3 mean{0, 0, 0};
      for (std::size_t i = b; i < e; ++i)
        for (int a = 0; a < 3; ++a) mean[std::size_t(a)] += p[std::size_t(m.neighbours[i])][std::size_t(a)];
      const auto c = m.corner(v);
      for (int a = 0; a < 3; ++a) {
        const double lo = double(c[std::size_t(a)]) - 1 + o.margin, hi = double(c[std::size_t(a)]) - o.margin;
        next[v][std::size_t(a)] = std::clamp(mean[std::size_t(a)] / double(e - b), lo, hi);
      }
    }
    p.swap(next);
  }
  for (std::size_t v = 0; v < n; ++v) m.points[v] = m.grid.world(p[v][0], p[v][1], p[v][2]);
}

} // namespace

void smooth_interface_mesh(InterfaceMesh& m, const SmoothingOptions& o) {
  if (!(o.margin >= 0 && o.margin < 0.5)) throw Error("smooth_interface_mesh: the margin must be in [0, 0.5)");
  relax(m, o);
  split_quads(m);
  if (o.untangle) untangle_interface_mesh(m, corner_points(m), o.threads);
}

} // namespace imgmesh
