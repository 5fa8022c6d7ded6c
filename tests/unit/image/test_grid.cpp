#include "image/grid.hpp"

#include <catch2/catch.hpp>
#include <cmath>

using namespace imgmesh;

TEST_CASE("world and continuous_index are inverse under a rotated, anisotropic grid") {
  Geometry g;
  g.size = {4, 5, 6};
  g.origin = {10, -3, 2.5};
  g.spacing = {0.6, 0.6, 1.3};
  const double c = std::cos(0.3), s = std::sin(0.3);
  g.direction = {c, -s, 0, s, c, 0, 0, 0, 1};
  const Vec3 w = g.world(1.5, 2.25, -0.5);
  const Vec3 i = g.continuous_index(w);
  CHECK(i[0] == Approx(1.5));
  CHECK(i[1] == Approx(2.25));
  CHECK(i[2] == Approx(-0.5));
  // ITK's convention, by hand: world = origin + D diag(spacing) index, so
  // (1.5, 2.25, -0.5) is origin + D (0.9, 1.35, -0.65) (D is not symmetric:
  // using D^T in both functions would still pass the inverse check above).
  CHECK(w[0] == Approx(10 + c * 0.9 - s * 1.35));
  CHECK(w[1] == Approx(-3 + s * 0.9 + c * 1.35));
  CHECK(w[2] == Approx(2.5 - 0.65));
  // A step of one index along x moves by spacing[0] along the first column
  // (c, s, 0), along y by spacing[1] along the second (-s, c, 0).
  const Vec3 a = g.world(0, 0, 0), b = g.world(1, 0, 0), d = g.world(0, 1, 0);
  CHECK(a == g.origin);
  CHECK(b[0] - a[0] == Approx(0.6 * c));
  CHECK(b[1] - a[1] == Approx(0.6 * s));
  CHECK(b[2] - a[2] == Approx(0).margin(1e-12));
  CHECK(d[0] - a[0] == Approx(-0.6 * s));
  CHECK(d[1] - a[1] == Approx(0.6 * c));
}

TEST_CASE("pad keeps the world position of every voxel") {
  Geometry g;
  g.size = {3, 2, 2};
  g.origin = {1, 2, 3};
  g.spacing = {0.5, 2, 1};
  BinaryImage img(g, 0);
  img(2, 1, 1) = 1;
  BinaryImage p = pad(img, {1, 0, 2}, {0, 1, 0});
  CHECK(p.size == std::array<std::size_t, 3>{4, 3, 4});
  CHECK(p(3, 1, 3) == 1);
  const Vec3 before = img.world(2, 1, 1), after = p.world(3, 1, 3);
  for (int k = 0; k < 3; ++k) CHECK(after[k] == Approx(before[k]));
  CHECK(p.at(-1, 0, 0, 7) == 7);
}
