// Test helper for tests/e2e/implicit2mesh.sh (not installed): checks a
// surface mesh against the voxel boundary of a well-composed image.
//   surface_check MESH IMAGE MAX_RATIO
// Prints one line and exits 0 when the mesh is a closed oriented 2-manifold
// whose components' Euler characteristics equal those of bdCA(X) (X = the
// image's nonzero voxels) and every radius-edge ratio is <= MAX_RATIO.
#include "image/io.hpp"
#include "mesh/surface_io.hpp"
#include "surface/topology.hpp"

#include <cmath>
#include <cstdlib>
#include <exception>
#include <iostream>

using namespace imgmesh;

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
    std::cout << " max_ratio " << q.max_ratio << " min_angle_deg " << q.min_angle * 180 / M_PI << '\n';
    const bool ok = got.manifold && got.oriented && expected.manifold && got.euler == expected.euler &&
                    q.max_ratio <= bound * (1 + 1e-9) && !mesh.triangles.empty();
    return ok ? 0 : 1;
  } catch (const std::exception& e) {
    std::cerr << "surface_check: " << e.what() << '\n';
    return 1;
  }
}
