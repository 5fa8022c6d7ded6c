// Test helper for tests/e2e/implicit2mesh.sh (not installed): checks a
// surface mesh against the voxel boundary of a well-composed image.
//   surface_check MESH IMAGE MAX_RATIO
// Prints one line and exits 0 when the mesh is a closed oriented 2-manifold
// without self-intersections (CGAL's exact test) whose components' Euler
// characteristics equal those of bdCA(X) (X = the image's nonzero voxels)
// and every radius-edge ratio is <= MAX_RATIO.
#include "image/io.hpp"
#include "mesh/surface_io.hpp"
#include "surface/topology.hpp"

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
    FloatImage signs(img.geometry(), 1.0f);
    for (std::size_t k = 0; k < img.data.size(); ++k) signs.data[k] = img.data[k] ? -1.0f : 1.0f;
    const SurfaceTopology expected = voxel_boundary_topology(signs), got = mesh_topology(mesh);
    const TriangleQuality q = triangle_quality(mesh);
    const double bound = std::atof(argv[3]);
    std::cout << "triangles " << mesh.triangles.size() << " manifold " << got.manifold << " oriented " << got.oriented
              << " euler";
    for (int e : got.euler) std::cout << ' ' << e;
    std::cout << " expected";
    for (int e : expected.euler) std::cout << ' ' << e;
    const bool crossing = got.manifold && self_intersects(mesh);
    std::cout << " max_ratio " << q.max_ratio << " min_angle_deg " << q.min_angle * 180 / M_PI << " self_intersecting "
              << crossing << '\n';
    const bool ok = got.manifold && got.oriented && !crossing && expected.manifold && got.euler == expected.euler &&
                    q.max_ratio <= bound * (1 + 1e-9) && !mesh.triangles.empty();
    return ok ? 0 : 1;
  } catch (const std::exception& e) {
    std::cerr << "surface_check: " << e.what() << '\n';
    return 1;
  }
}
