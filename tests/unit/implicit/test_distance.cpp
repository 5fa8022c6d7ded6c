// g: exact distance from voxel centres to the voxel-face boundary bdCA(X).
#include "helpers.hpp"
#include "implicit/implicit_file.hpp"
#include "util/error.hpp"

#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <random>
#include <vector>

using namespace imgmesh;
using namespace imgmesh::test;

TEST_CASE("distance to the faces of a box is the analytic box distance", "[distance]") {
  const Vec3 sp = GENERATE(Vec3{1, 1, 1}, Vec3{0.6, 0.9, 1.7});
  BinaryImage im(grid(17, 13, 11, sp), 0);
  const long lo[3] = {3, 4, 2}, hi[3] = {12, 8, 7};  // inclusive voxel ranges
  for (long z = lo[2]; z <= hi[2]; ++z)
    for (long y = lo[1]; y <= hi[1]; ++y)
      for (long x = lo[0]; x <= hi[0]; ++x) im(x, y, z) = 1;
  const FloatImage g = signed_distance_to_boundary(im, 2);
  for (long z = 0; z < 11; ++z)
    for (long y = 0; y < 13; ++y)
      for (long x = 0; x < 17; ++x) {
        const long p[3] = {x, y, z};
        // The box is [lo - 1/2, hi + 1/2] in index units on every axis.
        double inside = 1e300, out2 = 0;
        bool in = true;
        for (int i = 0; i < 3; ++i) {
          const double a = (lo[i] - 0.5) * sp[i], b = (hi[i] + 0.5) * sp[i], c = p[i] * sp[i];
          if (c < a || c > b) in = false;
          inside = std::min({inside, c - a, b - c});
          const double e = std::max({0.0, a - c, c - b});
          out2 += e * e;
        }
        const double expect = in ? -inside : std::sqrt(out2);
        INFO(x << " " << y << " " << z);
        REQUIRE(g(x, y, z) == Approx(expect).margin(1e-5));
      }
}

TEST_CASE("distance on a voxelised ball: exact against brute force, close to the sphere", "[distance]") {
  const Vec3 sp = GENERATE(Vec3{1, 1, 1}, Vec3{0.8, 1.1, 1.4});
  const std::size_t n = 19;
  BinaryImage im(grid(n, n, n, sp), 0);
  const double c = 9, R = 6.3;  // physical radius in units of the coordinates below
  auto sdf = [&](long x, long y, long z) {
    const double dx = (x - c) * sp[0], dy = (y - c) * sp[1], dz = (z - c) * sp[2];
    return std::sqrt(dx * dx + dy * dy + dz * dz) - R;
  };
  for (long z = 0; z < long(n); ++z)
    for (long y = 0; y < long(n); ++y)
      for (long x = 0; x < long(n); ++x) im(x, y, z) = sdf(x, y, z) <= 0;
  const FloatImage g = signed_distance_to_boundary(im, 1);
  // The voxel boundary lies within half a voxel diagonal of the sphere, so
  // the two signed distances differ by at most that much.
  const double half_diag = 0.5 * std::sqrt(sp[0] * sp[0] + sp[1] * sp[1] + sp[2] * sp[2]);
  for (long z = 0; z < long(n); ++z)
    for (long y = 0; y < long(n); ++y)
      for (long x = 0; x < long(n); ++x) {
        INFO(x << " " << y << " " << z);
        REQUIRE(g(x, y, z) == Approx(brute_distance(im, x, y, z)).margin(1e-5));
        REQUIRE(std::abs(g(x, y, z) - sdf(x, y, z)) <= half_diag + 1e-9);
      }
}

TEST_CASE("distance on random images equals brute force, foreground touching the border", "[distance]") {
  for (unsigned seed = 1; seed <= 4; ++seed) {
    const Vec3 sp = seed % 2 ? Vec3{1, 1, 1} : Vec3{0.5, 1.25, 2.0};
    BinaryImage im(grid(9, 7, 8, sp), 0);
    std::mt19937 rng(seed);
    for (auto& v : im.data) v = rng() % 3 == 0;
    const FloatImage g = signed_distance_to_boundary(im, seed % 2 + 1);
    for (long z = 0; z < 8; ++z)
      for (long y = 0; y < 7; ++y)
        for (long x = 0; x < 9; ++x) {
          INFO(seed << ": " << x << " " << y << " " << z);
          REQUIRE(g(x, y, z) == Approx(brute_distance(im, x, y, z)).margin(1e-5));
          REQUIRE((g(x, y, z) < 0) == (im(x, y, z) != 0));
        }
  }
}

TEST_CASE("distance on a crop with background around the foreground is the whole grid's, bit for bit", "[distance]") {
  // Far from the grid's origin, spacings that do not round alike: a crop's
  // lines start elsewhere, and must give the same values (crop.hpp).
  for (unsigned seed = 1; seed <= 4; ++seed) {
    const Vec3 sp = seed % 2 ? Vec3{0.617188, 0.617188, 1.33333} : Vec3{0.1, 0.3, 0.7};
    BinaryImage crop(grid(14, 13, 12, sp), 0);
    std::mt19937 rng(seed);
    for (std::size_t z = 2; z + 2 < 12; ++z)
      for (std::size_t y = 2; y + 2 < 13; ++y)
        for (std::size_t x = 2; x + 2 < 14; ++x) crop(x, y, z) = rng() % 3 == 0;
    const std::array<std::size_t, 3> at{700 + seed, 40 + 3 * seed, 50};
    BinaryImage whole(grid(at[0] + 14 + 9, at[1] + 13 + 5, at[2] + 12 + 3, sp), 0);
    for (std::size_t z = 0; z < 12; ++z)
      for (std::size_t y = 0; y < 13; ++y)
        for (std::size_t x = 0; x < 14; ++x) whole(at[0] + x, at[1] + y, at[2] + z) = crop(x, y, z);
    const FloatImage gc = signed_distance_to_boundary(crop), gw = signed_distance_to_boundary(whole, 2);
    for (std::size_t z = 0; z < 12; ++z)
      for (std::size_t y = 0; y < 13; ++y)
        for (std::size_t x = 0; x < 14; ++x) {
          const float a = gc(x, y, z), b = gw(at[0] + x, at[1] + y, at[2] + z);
          if (std::memcmp(&a, &b, sizeof a) != 0) FAIL(seed << ": " << x << " " << y << " " << z << ": " << a << " " << b);
        }
  }
}

TEST_CASE("distance rejects empty foreground and 2D grids", "[distance]") {
  BinaryImage empty(grid(4, 4, 4), 0);
  REQUIRE_THROWS_AS(signed_distance_to_boundary(empty), Error);
  Geometry g2 = grid(4, 4, 1);
  g2.dimension = 2;
  BinaryImage flat(g2, 1);
  REQUIRE_THROWS_AS(signed_distance_to_boundary(flat), Error);
}

TEST_CASE("g a band of x at a time is g, to the last bit", "[distance]") {
  std::mt19937 rng(11);
  for (int trial = 0; trial < 8; ++trial) {
    const Vec3 sp = trial % 2 ? Vec3{1, 1, 1} : Vec3{0.6, 1.1, 2.3};
    const std::size_t n0 = 5 + rng() % 30, n1 = 4 + rng() % 20, n2 = 3 + rng() % 15;
    BinaryImage im(grid(n0, n1, n2, sp), 0);
    for (auto& v : im.data) v = rng() % 7 == 0;  // touching every side too
    const FloatImage g = signed_distance_to_boundary(im);
    std::size_t compared = 0;
    for (std::size_t x0 = 0, x1; x0 < n0; x0 = x1) {
      x1 = std::min(n0, x0 + 1 + rng() % 6);
      std::vector<float> band((x1 - x0) * n1 * n2);
      signed_distance_band(im, x0, x1, band.data(), 1 + trial % 2);
      for (std::size_t z = 0; z < n2; ++z)
        for (std::size_t y = 0; y < n1; ++y)
          for (std::size_t x = x0; x < x1; ++x)
            if (std::memcmp(&band[(x - x0) + (x1 - x0) * (y + n1 * z)], &g(x, y, z), sizeof(float)) != 0)
              FAIL("trial " << trial << ": voxel " << x << " " << y << " " << z << " differs");
      compared += band.size();
    }
    REQUIRE(compared == im.count());
  }
}
