// The mesher's view of lib/mesh's topology and triangle quality, until it
// uses MeshTopology and TriangleQualityReport itself.
#include "surface/topology.hpp"

#include "mesh/topology.hpp"
#include "mesh/triangle_quality.hpp"

#include <algorithm>
#include <cmath>

namespace imgmesh {
namespace {

std::vector<int> sorted_euler(const MeshTopology& t) {
  std::vector<int> e;
  for (long long x : t.euler_list()) e.push_back(int(x));
  std::sort(e.begin(), e.end());
  return e;
}

} // namespace

SurfaceTopology voxel_boundary_topology(const FloatImage& g) {
  const MeshTopology t = mesh_topology(voxel_boundary(g));
  SurfaceTopology s;
  s.euler = sorted_euler(t);
  s.manifold = t.nonmanifold_edges == 0 && t.nonmanifold_vertices == 0;
  return s;
}

SurfaceTopology mesh_topology(const SurfaceMesh& m) {
  const MeshTopology t = mesh_topology(m.points.size(), m.triangles);
  SurfaceTopology s;
  s.euler = sorted_euler(t);
  s.manifold = t.boundary_edges == 0 && t.nonmanifold_edges == 0 && t.nonmanifold_vertices == 0;
  s.oriented = t.inconsistent_edges == 0;
  return s;
}

TriangleQuality triangle_quality(const SurfaceMesh& m) {
  const TriangleQualityReport r = triangle_quality_report(m);
  return {r.smallest_angle() * M_PI / 180, r.largest_radius_edge_ratio()};
}

} // namespace imgmesh
