// Seeds (8.1) alone, on the cube grid of analytic surfaces: points of S on
// mixed grid edges, at least two on every component.
#include "shapes.hpp"
#include "surface/seeds.hpp"

#include <catch2/catch.hpp>

#include <algorithm>
#include <map>
#include <vector>

using namespace imgmesh;
using namespace imgmesh::surface_detail;

// A ball (centre kBall, radius 3.6) and a thin torus beside it (centre
// kTorus, radii 4.1 and 1.1): two components of S.
namespace {
const Vec3 kBall{6.3, 7.1, 7.4}, kTorus{17.2, 7.6, 7.9};
FunctionSurface ball_and_torus() {
  return FunctionSurface(test::box(26, 16, 16), [](const Vec3& p) {
    return std::min(test::sphere_f(p, kBall, 3.6), test::torus_f(p, kTorus, 4.1, 1.1));
  });
}
} // namespace

TEST_CASE("seeds: on S, on mixed grid edges, at least two per component, shuffled by the seed") {
  FunctionSurface s = ball_and_torus();
  CubeGrid grid(s.samples());
  grid.label();
  REQUIRE(grid.components == 2);
  SurfaceSampler f(s, grid);
  Seeds seeds(f);
  const std::vector<Vec3> pts = seeds.points(0);
  std::map<int, int> per_component;
  for (const Vec3& x : pts) {
    CHECK(std::abs(s.value(x)) < 1e-9);
    // On a grid edge: two coordinates are voxel-centre coordinates.
    int on_grid = 0;
    for (int i = 0; i < 3; ++i) on_grid += std::abs(x[i] - std::round(x[i])) < 1e-12;
    CHECK(on_grid >= 2);
    ++per_component[grid.comp_at(x)];
  }
  CHECK(per_component.size() == 2);
  CHECK(per_component.count(-1) == 0);
  for (const auto& [comp, count] : per_component) CHECK(count >= 2);
  // Each point once; another seed gives the same points in another order.
  std::vector<Vec3> sorted = pts;
  std::sort(sorted.begin(), sorted.end());
  CHECK(std::adjacent_find(sorted.begin(), sorted.end()) == sorted.end());
  std::vector<Vec3> other = seeds.points(1);
  CHECK(other != pts);
  std::sort(other.begin(), other.end());
  CHECK(other == sorted);
}

TEST_CASE("seeds: crossing() finds the which-th mixed edge of a cube, and next_extra() walks the others") {
  // A small ball around voxel centre (6,6,6): the only inside sample.
  const Vec3 v{6, 6, 6};
  FunctionSurface t(test::box(13, 13, 13), [&](const Vec3& p) { return test::sphere_f(p, v, 0.5); });
  CubeGrid tg(t.samples());
  tg.label();
  REQUIRE(tg.components == 1);
  SurfaceSampler tf(t, tg);
  Seeds ts(tf);
  // Cube (6,6,6) has one inside corner (6,6,6): three mixed edges, on the
  // axes from it, each crossing at distance 0.5.
  Vec3 x;
  for (int which = 0; which < 3; ++which) {
    REQUIRE(ts.crossing(6, 6, 6, x, which));
    CHECK(std::sqrt(test::dist2(x, v)) == Approx(0.5).margin(1e-9));
  }
  CHECK_FALSE(ts.crossing(6, 6, 6, x, 3));
  // The eight cubes around (6,6,6) hold 24 mixed edges, 6 distinct
  // crossings; next_extra() walks them all and then stops.
  std::vector<Vec3> extra;
  while (ts.next_extra(x)) extra.push_back(x);
  CHECK(extra.size() == 24);
  std::sort(extra.begin(), extra.end());
  extra.erase(std::unique(extra.begin(), extra.end()), extra.end());
  CHECK(extra.size() == 6);
}

TEST_CASE("cube grid: active cubes are the mixed ones, each in one component, listed once in key order") {
  FunctionSurface s = ball_and_torus();
  CubeGrid grid(s.samples());
  grid.label();
  REQUIRE(grid.components == 2);
  long active = 0;
  for (long z = -1; z < grid.n[2]; ++z)
    for (long y = -1; y < grid.n[1]; ++y)
      for (long x = -1; x < grid.n[0]; ++x) {
        bool mixed = false;
        if (x >= 0 && y >= 0 && z >= 0 && x + 1 < grid.n[0] && y + 1 < grid.n[1] && z + 1 < grid.n[2])
          for (int k = 1; k < 8; ++k)
            mixed = mixed || grid.neg(x + (k & 1), y + ((k >> 1) & 1), z + ((k >> 2) & 1)) != grid.neg(x, y, z);
        CHECK(grid.active(x, y, z) == mixed);
        if (x >= 0 && y >= 0 && z >= 0 && x + 1 < grid.n[0] && y + 1 < grid.n[1] && z + 1 < grid.n[2]) {
          const int c = grid.comp_of(x, y, z);
          CHECK((c >= 0) == mixed);
          CHECK(c < grid.components);
        }
        active += mixed;
      }
  // The lines' active cubes (a block's brick at a time) and the blocks'
  // activity are active()'s, from every start to every end of a line.
  for (long z = 0; z + 1 < grid.n[2]; ++z)
    for (long y = 0; y + 1 < grid.n[1]; ++y)
      for (long x0 = 0; x0 + 1 < grid.n[0]; x0 += 3)
        for (long x1 = x0; x1 + 1 < grid.n[0]; x1 += 5) {
          std::vector<long> seen, expected;
          grid.for_active_on_line(x0, x1, y, z, [&](long x) { seen.push_back(x); });
          for (long x = x0; x <= x1; ++x)
            if (grid.active(x, y, z)) expected.push_back(x);
          REQUIRE(seen == expected);
        }
  long active_blocks = 0;
  for (long bz = 0; bz < grid.nb[2]; ++bz)
    for (long by = 0; by < grid.nb[1]; ++by)
      for (long bx = 0; bx < grid.nb[0]; ++bx) {
        bool any = false;
        for (long z = bz * CubeGrid::kBlock; z < (bz + 1) * CubeGrid::kBlock; ++z)
          for (long y = by * CubeGrid::kBlock; y < (by + 1) * CubeGrid::kBlock; ++y)
            for (long x = bx * CubeGrid::kBlock; x < (bx + 1) * CubeGrid::kBlock; ++x) any = any || grid.active(x, y, z);
        CHECK(grid.block(bx, by, bz) == any);
        active_blocks += any;
      }
  CHECK(active_blocks > 1);
  CHECK(active_blocks < grid.nb[0] * grid.nb[1] * grid.nb[2]);
  const auto& cubes = grid.sorted_cubes();
  CHECK(long(cubes.size()) == active);
  for (std::size_t i = 1; i < cubes.size(); ++i) CHECK(cubes[i - 1].key() < cubes[i].key());
  // The ball's cubes and the torus's: two components.
  CHECK(grid.comp_at(Vec3{kBall[0] + 3.6, kBall[1], kBall[2]}) !=
        grid.comp_at(Vec3{kTorus[0] + 4.1 + 1.1, kTorus[1], kTorus[2]}));
}

// From blocks, a line's cubes are skipped a sample block at a time where
// every block their corners lie in is one of the constant ones (+T or -T):
// the active cubes must still be the mixed ones, with -T blocks inside a
// large ball, +T blocks outside it, and stored blocks at a thin shell. g is
// 8-Lipschitz, so a constant block may meet a mixed cube.
TEST_CASE("cube grid from clamped blocks: the active cubes are the mixed ones") {
  const Geometry box = test::box(37, 30, 27);
  FloatImage g(box);
  for (std::size_t z = 0; z < box.size[2]; ++z)
    for (std::size_t y = 0; y < box.size[1]; ++y)
      for (std::size_t x = 0; x < box.size[0]; ++x) {
        const Vec3 p{double(x), double(y), double(z)};
        const double ball = test::sphere_f(p, {14.2, 13.7, 12.9}, 10.3);
        const double shell = std::abs(test::sphere_f(p, {29.1, 19.6, 15.2}, 4.4)) - 0.8;
        g(x, y, z) = float(8 * std::min(ball, shell));  // steep: clamped samples next to a change of sign
      }
  const SampleGrid samples(g, 2.5f, SampleGrid::Storage::blocks);
  int plus = 0, minus = 0, stored = 0;
  constexpr long kB = SampleGrid::kB;  // the grid's blocks, not the table's
  const long blocks[3] = {(long(box.size[0]) + kB - 1) / kB, (long(box.size[1]) + kB - 1) / kB, (long(box.size[2]) + kB - 1) / kB};
  for (long bz = 0; bz < blocks[2]; ++bz)
    for (long by = 0; by < blocks[1]; ++by)
      for (long bx = 0; bx < blocks[0]; ++bx) {
        const int c = samples.constant_block(bx, by, bz);
        (c > 0 ? plus : c < 0 ? minus : stored) += 1;
      }
  REQUIRE(plus > 0);
  REQUIRE(minus > 0);
  REQUIRE(stored > 0);
  CubeGrid grid(samples);
  long active = 0;
  for (long z = 0; z + 1 < grid.n[2]; ++z)
    for (long y = 0; y + 1 < grid.n[1]; ++y)
      for (long x = 0; x + 1 < grid.n[0]; ++x) {
        bool mixed = false;
        for (int k = 1; k < 8; ++k)
          mixed = mixed || (samples(x + (k & 1), y + ((k >> 1) & 1), z + ((k >> 2) & 1)) < 0) != (samples(x, y, z) < 0);
        REQUIRE(grid.active(x, y, z) == mixed);
        active += mixed;
      }
  REQUIRE(active == grid.active_cubes);
}
