// Test helper for tests/e2e/implicit2mesh.sh (not installed): checks a
// surface mesh against the voxel boundary of a well-composed image.
//   surface_check MESH IMAGE MAX_RATIO
// Prints one line and exits 0 when the mesh is a closed oriented 2-manifold
// without self-intersections (CGAL's exact test) whose components' Euler
// characteristics equal those of bdCA(X) (X = the image's nonzero voxels)
// and every radius-edge ratio is <= MAX_RATIO.
#include "image/io.hpp"
#include "mesh/surface_io.hpp"
#include "mesh/topology.hpp"
#include "mesh/triangle_quality.hpp"

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Polygon_mesh_processing/self_intersections.h>
#include <CGAL/Surface_mesh.h>

#include <cmath>
#include <cstdlib>
#include <exception>
#include <iostream>

using namespace imgmesh;

namespace {

bool self_intersects(const SurfaceMesh& mesh) {
  using Point = CGAL::Exact_predicates_inexact_constructions_kernel::Point_3;
  CGAL::Surface_mesh<Point> sm;
  std::vector<CGAL::Surface_mesh<Point>::Vertex_index> v;
  for (const Vec3& p : mesh.points) v.push_back(sm.add_vertex(Point(p[0], p[1], p[2])));
  for (const auto& t : mesh.triangles)
    if (sm.add_face(v[std::size_t(t[0])], v[std::size_t(t[1])], v[std::size_t(t[2])]) == sm.null_face()) return true;
  return CGAL::Polygon_mesh_processing::does_self_intersect(sm);
}

} // namespace

int main(int argc, char** argv) {
  if (argc != 4) {
    std::cerr << "usage: surface_check MESH IMAGE MAX_RATIO\n";
    return 2;
  }
  try {
    const SurfaceMesh mesh = read_surface(argv[1]);
    const BinaryImage img = read_foreground(argv[2], Selection{});
    const MeshTopology expected = mesh_topology(voxel_boundary(img));
    const MeshTopology got = mesh_topology(mesh.points.size(), mesh.triangles);
    const TriangleQualityReport q = triangle_quality_report(mesh);
    const double bound = std::atof(argv[3]);
    const bool closed_manifold = got.closed && got.manifold;
    std::cout << "triangles " << mesh.triangles.size() << " manifold " << closed_manifold << " oriented "
              << (got.inconsistent_edges == 0) << " euler";
    for (long long e : got.euler_list()) std::cout << ' ' << e;
    std::cout << " expected";
    for (long long e : expected.euler_list()) std::cout << ' ' << e;
    const bool crossing = closed_manifold && self_intersects(mesh);
    std::cout << " max_ratio " << q.largest_radius_edge_ratio() << " min_angle_deg " << q.smallest_angle()
              << " self_intersecting " << crossing << '\n';
    const bool ok = closed_manifold && got.oriented && !crossing && expected.manifold && same_topology(got, expected) &&
                    q.largest_radius_edge_ratio() <= bound * (1 + 1e-9) && !mesh.triangles.empty();
    return ok ? 0 : 1;
  } catch (const std::exception& e) {
    std::cerr << "surface_check: " << e.what() << '\n';
    return 1;
  }
}
