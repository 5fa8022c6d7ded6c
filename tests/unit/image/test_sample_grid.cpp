// g's samples in blocks (image/sample_grid.hpp), clamped or not.
#include "image/sample_grid.hpp"
#include "util/error.hpp"

#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>

using namespace imgmesh;

namespace {

// Distance-like samples: |g| grows away from a sphere, sizes not multiples
// of the block side.
FloatImage sphere_samples(std::size_t nx, std::size_t ny, std::size_t nz) {
  Geometry geo;
  geo.size = {nx, ny, nz};
  geo.spacing = {0.7, 1.0, 1.3};
  FloatImage g(geo);
  const double c[3] = {nx / 3.0, ny / 2.0, nz / 2.0};
  for (std::size_t z = 0; z < nz; ++z)
    for (std::size_t y = 0; y < ny; ++y)
      for (std::size_t x = 0; x < nx; ++x) {
        const double d = std::hypot((x - c[0]) * 0.7, (y - c[1]) * 1.0, (z - c[2]) * 1.3) - 4.1;
        g(x, y, z) = float(d);
      }
  return g;
}

} // namespace

TEST_CASE("SampleGrid without a clamp holds every sample, dense or in blocks", "[samples]") {
  const FloatImage g = sphere_samples(13, 10, 7);
  const auto storage = GENERATE(SampleGrid::Storage::dense, SampleGrid::Storage::blocks, SampleGrid::Storage::automatic);
  const SampleGrid s(g, std::numeric_limits<float>::infinity(), storage);
  REQUIRE(s.same_grid(g));
  CHECK(s.dense() == (storage != SampleGrid::Storage::blocks));  // automatic: small grids stay dense
  if (!s.dense()) CHECK(s.stored_blocks() == s.blocks());
  CHECK(s.to_image().data == g.data);
  // cube(): the 8 corners, also across block faces, edges and corners.
  for (long z = 0; z + 1 < 7; ++z)
    for (long y = 0; y + 1 < 10; ++y)
      for (long x = 0; x + 1 < 13; ++x) {
        double c[8];
        s.cube(x, y, z, c);
        for (int m = 0; m < 8; ++m)
          REQUIRE(c[m] == g(std::size_t(x + (m & 1)), std::size_t(y + ((m >> 1) & 1)), std::size_t(z + ((m >> 2) & 1))));
      }
}

TEST_CASE("SampleGrid with a clamp T holds g clamped to [-T, T] and stores only blocks with |g| < T", "[samples]") {
  const FloatImage g = sphere_samples(40, 30, 21);
  const float t = 2.5f;
  const SampleGrid s(g, t, SampleGrid::Storage::blocks), d(g, t, SampleGrid::Storage::dense);
  CHECK(s.stored_blocks() < s.blocks() / 2);
  CHECK(s.coded());  // fewer than kCodes values
  CHECK(d.to_image().data == s.to_image().data);
  for (std::size_t z = 0; z < g.size[2]; ++z)
    for (std::size_t y = 0; y < g.size[1]; ++y)
      for (std::size_t x = 0; x < g.size[0]; ++x)
        REQUIRE(s(x, y, z) == std::clamp(g(x, y, z), -t, t));
  // Every block with a sample under T in absolute value is stored: count them.
  std::size_t near = 0;
  const long b = SampleGrid::kB;
  for (long bz = 0; bz * b < 21; ++bz)
    for (long by = 0; by * b < 30; ++by)
      for (long bx = 0; bx * b < 40; ++bx) {
        bool any = false;
        for (long z = bz * b; z < std::min(21L, (bz + 1) * b); ++z)
          for (long y = by * b; y < std::min(30L, (by + 1) * b); ++y)
            for (long x = bx * b; x < std::min(40L, (bx + 1) * b); ++x) any = any || std::fabs(g(x, y, z)) < t;
        near += any;
      }
  CHECK(s.stored_blocks() == near);
  CHECK(s.finite());
  FloatImage bad = g;
  bad(3, 4, 5) = std::nanf("");
  CHECK_FALSE(SampleGrid(bad).finite());
  CHECK_THROWS_AS(SampleGrid(g, 0.0f), Error);
}

TEST_CASE("SampleGrid streamed a slice at a time from a box of the grid: the box's samples, +T beyond", "[samples]") {
  Geometry geo;
  geo.size = {41, 30, 22};
  geo.spacing = {0.7, 1.0, 1.3};
  const Index3 lo{9, 6, 5};
  const std::array<std::size_t, 3> box{19, 14, 11};
  const float t = 3.5f;
  // Distance-like samples of a sphere inside the box: beyond it g >= T.
  auto g = [&](long x, long y, long z) {
    return float(std::hypot((x - 18.5) * 0.7, (y - 13.0) * 1.0, (z - 10.5) * 1.3) - 3.1);
  };
  for (const auto storage : {SampleGrid::Storage::dense, SampleGrid::Storage::blocks}) {
    long z = lo[2];
    const SampleGrid s(geo, lo, box, t, storage, [&](float* slice) {
      for (std::size_t y = 0; y < box[1]; ++y)
        for (std::size_t x = 0; x < box[0]; ++x) *slice++ = g(lo[0] + long(x), lo[1] + long(y), z);
      ++z;
    });
    REQUIRE(z == lo[2] + long(box[2]));
    REQUIRE(s.same_grid(geo));
    CHECK(s.dense() == (storage == SampleGrid::Storage::dense));
    CHECK(s.box_lo() == lo);
    CHECK(s.box_hi() == Index3{lo[0] + 18, lo[1] + 13, lo[2] + 10});
    std::size_t near = 0;
    for (long bz = 0; bz < 6 && !s.dense(); ++bz)  // the grid's blocks
      for (long by = 0; by < 8; ++by)
        for (long bx = 0; bx < 11; ++bx) {
          bool any = false;
          for (long k = bz * 4; k < std::min(22L, bz * 4 + 4); ++k)
            for (long j = by * 4; j < std::min(30L, by * 4 + 4); ++j)
              for (long i = bx * 4; i < std::min(41L, bx * 4 + 4); ++i) {
                const bool in = i >= lo[0] && i < lo[0] + 19 && j >= lo[1] && j < lo[1] + 14 && k >= lo[2] && k < lo[2] + 11;
                any = any || (in && std::fabs(g(i, j, k)) < t);
              }
          near += any;
        }
    if (!s.dense()) CHECK(s.stored_blocks() == near);
    for (long k = 0; k < 22; ++k)
      for (long j = 0; j < 30; ++j)
        for (long i = 0; i < 41; ++i) {
          const bool in = i >= lo[0] && i < lo[0] + 19 && j >= lo[1] && j < lo[1] + 14 && k >= lo[2] && k < lo[2] + 11;
          REQUIRE(s(i, j, k) == (in ? std::clamp(g(i, j, k), -t, t) : t));
        }
  }
  // An unclamped box smaller than the grid would leave its outside unknown.
  CHECK_THROWS_AS(SampleGrid(geo, lo, box, std::numeric_limits<float>::infinity(), SampleGrid::Storage::automatic,
                             [](float*) {}),
                  Error);
}

TEST_CASE("SampleGrid from bands of x is SampleGrid from slices: the same samples, blocks in the same order",
          "[samples]") {
  // Random distance-like samples with noise, a box placed at odd and at
  // block-aligned indices of a larger grid, or the whole grid; bands of 1
  // block and more, and the default (one band).
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(0, 1);
  for (int trial = 0; trial < 12; ++trial) {
    Geometry geo;
    geo.size = {std::size_t(20 + rng() % 30), std::size_t(9 + rng() % 20), std::size_t(6 + rng() % 14)};
    geo.spacing = {0.5 + u(rng), 0.5 + u(rng), 0.5 + 2 * u(rng)};
    const bool whole = trial % 4 == 0;
    Index3 lo{0, 0, 0};
    std::array<std::size_t, 3> box = geo.size;
    for (int a = 0; a < 3 && !whole; ++a) {
      lo[a] = trial % 3 == 1 ? 4 * std::ptrdiff_t(rng() % 2) : std::ptrdiff_t(rng() % 5);
      box[a] = 2 + rng() % (geo.size[a] - std::size_t(lo[a]) - 1);
    }
    const double c[3] = {box[0] * u(rng), box[1] * u(rng), box[2] * u(rng)}, r = 1 + 4 * u(rng);
    Geometry gb = geo;
    gb.size = box;
    FloatImage g(gb);
    for (std::size_t z = 0; z < box[2]; ++z)
      for (std::size_t y = 0; y < box[1]; ++y)
        for (std::size_t x = 0; x < box[0]; ++x)
          g(x, y, z) = float(std::hypot((x - c[0]) * geo.spacing[0], (y - c[1]) * geo.spacing[1], (z - c[2]) * geo.spacing[2]) -
                             r + 0.3 * (u(rng) - 0.5));
    const float t = float(1 + 2 * u(rng));
    const std::size_t column = box[1] * box[2] * sizeof(float);
    const std::size_t bytes = trial % 3 == 2 ? SampleGrid::kBandBytes : column * (1 + rng() % 9);
    INFO("trial " << trial << " band bytes " << bytes);
    for (const auto storage : {SampleGrid::Storage::dense, SampleGrid::Storage::blocks, SampleGrid::Storage::automatic}) {
      std::size_t z = 0;
      const SampleGrid slices(geo, lo, box, t, storage, [&](float* slice) {
        std::copy_n(g.data.data() + z++ * box[0] * box[1], box[0] * box[1], slice);
      });
      std::size_t next = 0, bands = 0;
      const SampleGrid banded(geo, lo, box, t, storage, [&](std::size_t x0, std::size_t x1, float* band) {
        REQUIRE(x0 == next);  // in order, each x once, bands ending at blocks of the grid but at the box's sides
        REQUIRE(x0 < x1);
        REQUIRE((x1 == box[0] || (std::size_t(lo[0]) + x1) % SampleGrid::kB == 0));
        next = x1;
        ++bands;
        for (std::size_t zz = 0; zz < box[2]; ++zz)
          for (std::size_t y = 0; y < box[1]; ++y)
            for (std::size_t x = x0; x < x1; ++x) *band++ = g(x, y, zz);
      }, bytes);
      REQUIRE(next == box[0]);
      if (bytes < column * box[0] / 2) CHECK(bands > 1);
      REQUIRE(banded.dense() == slices.dense());
      REQUIRE(banded.stored_blocks() == slices.stored_blocks());
      REQUIRE(banded.box_lo() == slices.box_lo());
      REQUIRE(banded.box_hi() == slices.box_hi());
      for (std::size_t zz = 0; zz < geo.size[2]; ++zz)
        for (std::size_t y = 0; y < geo.size[1]; ++y)
          for (std::size_t x = 0; x < geo.size[0]; ++x)
            if (banded(x, y, zz) != slices(x, y, zz)) FAIL("sample " << x << " " << y << " " << zz << " differs");
      REQUIRE(banded.coded() == slices.coded());
      if (banded.coded())
        for (long b = 0; b < long(banded.blocks()); ++b)
          if (banded.code_block_at(b) - banded.code_block_at(0) != slices.code_block_at(b) - slices.code_block_at(0))
            FAIL("block " << b << " is elsewhere in the pool");
      if (!banded.dense() && !banded.coded())
        for (long b = 0; b < long(banded.blocks()); ++b)
          if (banded.block_at(b) - banded.block_at(0) != slices.block_at(b) - slices.block_at(0))
            FAIL("block " << b << " is elsewhere in the pool");
    }
  }
}
