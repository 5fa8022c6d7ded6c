#include "surface/topology.hpp"

#include <catch2/catch.hpp>

using namespace imgmesh;

namespace {
FloatImage image(std::size_t n) {
  Geometry g;
  g.size = {n, n, n};
  return FloatImage(g, 1.0f);
}
void block(FloatImage& img, int x0, int x1, int y0, int y1, int z0, int z1, float v = -1) {
  for (int z = z0; z < z1; ++z)
    for (int y = y0; y < y1; ++y)
      for (int x = x0; x < x1; ++x) img(x, y, z) = v;
}
} // namespace

TEST_CASE("voxel boundary topology of blocks, rings and shells") {
  auto img = image(12);
  block(img, 2, 5, 2, 5, 2, 5);
  CHECK(voxel_boundary_topology(img).euler == std::vector<int>{2});
  block(img, 7, 10, 7, 10, 7, 10);
  CHECK(voxel_boundary_topology(img).euler == std::vector<int>{2, 2});

  auto ring = image(12);
  block(ring, 2, 9, 2, 9, 4, 6);
  block(ring, 4, 7, 4, 7, 4, 6, 1);  // a hole through it: genus 1
  auto t = voxel_boundary_topology(ring);
  CHECK(t.euler == std::vector<int>{0});
  CHECK(t.manifold);

  auto shell = image(12);
  block(shell, 1, 11, 1, 11, 1, 11);
  block(shell, 4, 8, 4, 8, 4, 8, 1);  // cavity: two boundary components
  CHECK(voxel_boundary_topology(shell).euler == std::vector<int>{2, 2});

  auto pinch = image(8);  // two voxels sharing only an edge: not well-composed
  block(pinch, 2, 3, 2, 3, 2, 3);
  block(pinch, 3, 4, 3, 4, 2, 3);
  CHECK_FALSE(voxel_boundary_topology(pinch).manifold);
}

TEST_CASE("mesh topology: tetrahedron, orientation, open surfaces") {
  SurfaceMesh m;
  m.points = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  m.triangles = {{0, 2, 1}, {0, 1, 3}, {0, 3, 2}, {1, 2, 3}};
  auto t = mesh_topology(m);
  CHECK(t.euler == std::vector<int>{2});
  CHECK(t.manifold);
  CHECK(t.oriented);
  m.triangles[3] = {1, 3, 2};
  CHECK_FALSE(mesh_topology(m).oriented);
  m.triangles.pop_back();
  CHECK_FALSE(mesh_topology(m).manifold);

  auto q = triangle_quality(SurfaceMesh{{{0, 0, 0}, {1, 0, 0}, {0.5, std::sqrt(3.0) / 2, 0}}, {{0, 1, 2}}, {}});
  CHECK(q.max_ratio == Approx(1 / std::sqrt(3.0)));
  CHECK(q.min_angle == Approx(M_PI / 3));
}
