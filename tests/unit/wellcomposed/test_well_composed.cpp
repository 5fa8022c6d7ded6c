// make_well_composed and count_critical_configurations against a brute-force
// counter written here from Definitions 4.2.1 and 4.2.2 (outside = background).
#include "wellcomposed/well_composed.hpp"

#include "util/error.hpp"

#include <catch2/catch.hpp>

#include <array>
#include <cstdint>
#include <random>

using namespace imgmesh;

namespace {

BinaryImage make_image(int dim, std::size_t nx, std::size_t ny, std::size_t nz) {
  Geometry g;
  g.dimension = dim;
  g.size = {nx, ny, nz};
  g.origin = {1.5, -2.0, 0.25};
  g.spacing = {0.5, 0.75, 1.25};
  return BinaryImage(g, 0);
}

BinaryImage random_image(std::mt19937_64& rng, int dim, double density) {
  std::uniform_int_distribution<int> side(1, dim == 2 ? 12 : 7);
  BinaryImage img = make_image(dim, side(rng), side(rng), dim == 2 ? 1 : side(rng));
  std::bernoulli_distribution fg(density);
  for (auto& v : img.data) v = fg(rng) ? 1 : 0;
  return img;
}

// Brute force: every 2x2 square of every orientation and every 2x2x2 cube
// that meets the grid, reading outside points as background.
CriticalCounts brute_force(const BinaryImage& img) {
  auto v = [&](long x, long y, long z) { return int(img.at(x, y, z, 0) != 0); };
  const long nx = long(img.size[0]), ny = long(img.size[1]), nz = long(img.size[2]);
  CriticalCounts c;
  auto square = [](int a, int b, int cc, int d) {  // a b / cc d, diagonals a-d and b-cc
    return a == d && b == cc && a != b;
  };
  const long z0 = img.dimension == 2 ? 0 : -1, z1 = img.dimension == 2 ? 0 : nz;
  for (long z = z0; z <= z1; ++z)
    for (long y = -1; y <= ny; ++y)
      for (long x = -1; x <= nx; ++x) {
        if (square(v(x, y, z), v(x + 1, y, z), v(x, y + 1, z), v(x + 1, y + 1, z))) ++c.c1;
        if (img.dimension == 2) continue;
        if (square(v(x, y, z), v(x, y + 1, z), v(x, y, z + 1), v(x, y + 1, z + 1))) ++c.c1;
        if (square(v(x, y, z), v(x + 1, y, z), v(x, y, z + 1), v(x + 1, y, z + 1))) ++c.c1;
        int ones = 0;
        for (int k = 0; k < 8; ++k) ones += v(x + (k & 1), y + (k >> 1 & 1), z + (k >> 2 & 1));
        for (int k = 0; k < 4; ++k) {  // the four corner-opposite pairs
          const int p = v(x + (k & 1), y + (k >> 1 & 1), z + (k >> 2 & 1));
          const int q = v(x + 1 - (k & 1), y + 1 - (k >> 1 & 1), z + 1 - (k >> 2 & 1));
          if ((ones == 2 && p && q) || (ones == 6 && !p && !q)) ++c.c2;
        }
      }
  return c;
}

// Input voxel (x, y, z) in the output's grid.
std::uint8_t out_at(const WellComposedResult& r, std::size_t x, std::size_t y, std::size_t z) {
  return r.image(x + r.padded_before[0], y + r.padded_before[1], z + r.padded_before[2]);
}

// Checks every property of a result against its input.
void check_result(const BinaryImage& in, const WellComposedResult& r, RepairMode mode) {
  const CriticalCounts bf_in = brute_force(in);
  REQUIRE(r.input.c1 == bf_in.c1);
  REQUIRE(r.input.c2 == bf_in.c2);
  const CriticalCounts bf_out = brute_force(r.image);
  REQUIRE(bf_out.total() == 0);
  // Geometry: same world coordinates for every input voxel.
  for (int a = 0; a < 3; ++a)
    REQUIRE(r.image.size[a] == in.size[a] + r.padded_before[a] + r.padded_after[a]);
  REQUIRE(r.image.dimension == in.dimension);
  const Vec3 w0 = in.world(0, 0, 0);
  const Vec3 w1 = r.image.world(double(r.padded_before[0]), double(r.padded_before[1]), double(r.padded_before[2]));
  for (int a = 0; a < 3; ++a) REQUIRE(w0[a] == Approx(w1[a]));
  // X subset of X' (add) or X' subset of X (remove); |P| = changed voxels;
  // the added border (if any) stays background.
  std::size_t diff = 0, out_fg = 0;
  std::array<std::size_t, 3> touches_before{0, 0, 0}, touches_after{0, 0, 0};
  for (std::size_t z = 0; z < in.size[2]; ++z)
    for (std::size_t y = 0; y < in.size[1]; ++y)
      for (std::size_t x = 0; x < in.size[0]; ++x) {
        const int a = in(x, y, z) != 0, b = out_at(r, x, y, z);
        REQUIRE(b <= 1);
        if (a != b) ++diff;
        if (r.mode_used == RepairMode::Add) REQUIRE(b >= a);
        if (r.mode_used == RepairMode::Remove) REQUIRE(b <= a);
        out_fg += b;
        const std::size_t p[3] = {x, y, z};
        for (int k = 0; k < 3; ++k)
          if (a && (in.dimension == 3 || k < 2)) {
            if (p[k] == 0) touches_before[k] = 1;
            if (p[k] + 1 == in.size[k]) touches_after[k] = 1;
          }
      }
  std::size_t total_fg = 0;
  for (auto v : r.image.data) total_fg += v;
  REQUIRE(total_fg == out_fg);
  REQUIRE(r.changed == diff);
  if (mode != RepairMode::Min) REQUIRE(r.mode_used == mode);
  if (bf_in.total() == 0) REQUIRE(diff == 0);
  // Padding exactly where the input's foreground touches the border (2D: x, y).
  REQUIRE(r.padded_before == touches_before);
  REQUIRE(r.padded_after == touches_after);
}

} // namespace

TEST_CASE("counter agrees with brute force on random images", "[wellcomposed]") {
  std::mt19937_64 rng(12345);
  for (int dim : {2, 3})
    for (double density : {0.1, 0.3, 0.5, 0.7, 0.9})
      for (int i = 0; i < 300; ++i) {
        const BinaryImage img = random_image(rng, dim, density);
        const CriticalCounts a = count_critical_configurations(img), b = brute_force(img);
        REQUIRE(a.c1 == b.c1);
        REQUIRE(a.c2 == b.c2);
        REQUIRE(is_well_composed(img) == (b.total() == 0));
      }
}

TEST_CASE("repair leaves no critical configuration (2D and 3D, all modes)", "[wellcomposed]") {
  std::mt19937_64 rng(777);
  std::size_t configs = 0;
  for (int dim : {2, 3})
    for (double density : {0.05, 0.2, 0.5, 0.8, 0.95})
      for (int i = 0; i < 250; ++i) {
        const BinaryImage img = random_image(rng, dim, density);
        configs += brute_force(img).total();
        for (RepairMode mode : {RepairMode::Add, RepairMode::Remove, RepairMode::Min}) {
          WellComposedOptions opt;
          opt.mode = mode;
          opt.seed = rng();
          opt.greedy = i % 2 == 0;  // both the greedy draw and the thesis's literal rules
          const WellComposedResult r = make_well_composed(img, opt);
          check_result(img, r, mode);
        }
      }
  CHECK(configs > 5000);  // the test exercises the repair, not empty images
}

TEST_CASE("repair on larger random volumes (interior neighbourhoods)", "[wellcomposed]") {
  std::mt19937_64 rng(2024);
  for (double density : {0.15, 0.5, 0.85})
    for (int i = 0; i < 20; ++i) {
      BinaryImage img = make_image(3, 14, 13, 12);
      std::bernoulli_distribution fg(density);
      for (auto& v : img.data) v = fg(rng) ? 1 : 0;
      for (RepairMode mode : {RepairMode::Add, RepairMode::Remove}) {
        WellComposedOptions opt;
        opt.mode = mode;
        opt.seed = std::uint64_t(i);
        opt.greedy = i % 2 == 0;
        check_result(img, make_well_composed(img, opt), mode);
      }
    }
}

TEST_CASE("min keeps the smaller change", "[wellcomposed]") {
  std::mt19937_64 rng(99);
  for (int i = 0; i < 200; ++i) {
    const BinaryImage img = random_image(rng, 3, 0.5);
    WellComposedOptions opt;
    opt.seed = 5;
    opt.mode = RepairMode::Add;
    const auto add = make_well_composed(img, opt);
    opt.mode = RepairMode::Remove;
    const auto rem = make_well_composed(img, opt);
    opt.mode = RepairMode::Min;
    const auto min = make_well_composed(img, opt);
    REQUIRE(min.changed == std::min(add.changed, rem.changed));
  }
}

TEST_CASE("same seed, same output; outputs differ across seeds somewhere", "[wellcomposed]") {
  std::mt19937_64 rng(4242);
  bool some_difference = false;
  for (int i = 0; i < 100; ++i) {
    const BinaryImage img = random_image(rng, 3, 0.4);
    WellComposedOptions a, b;
    a.seed = b.seed = 17;
    const auto r1 = make_well_composed(img, a), r2 = make_well_composed(img, b);
    REQUIRE(r1.image.data == r2.image.data);
    REQUIRE(r1.changed == r2.changed);
    REQUIRE(r1.created == r2.created);
    b.seed = 18;
    if (make_well_composed(img, b).image.data != r1.image.data) some_difference = true;
  }
  CHECK(some_difference);  // rules (2) and (3) do use the seed
}

TEST_CASE("padding only where foreground touches the border", "[wellcomposed]") {
  BinaryImage img = make_image(3, 5, 6, 7);
  img(2, 3, 3) = 1;
  img(3, 4, 4) = 1;  // corner-adjacent: a (C2) away from the border
  auto r = make_well_composed(img);
  CHECK(r.padded_before == std::array<std::size_t, 3>{0, 0, 0});
  CHECK(r.padded_after == std::array<std::size_t, 3>{0, 0, 0});
  CHECK(r.image.same_grid(img));
  img(4, 0, 6) = 1;  // touches x = max, y = 0, z = max
  r = make_well_composed(img);
  CHECK(r.padded_before == std::array<std::size_t, 3>{0, 1, 0});
  CHECK(r.padded_after == std::array<std::size_t, 3>{1, 0, 1});
  check_result(img, r, RepairMode::Add);
  // 2D: never padded along z.
  BinaryImage flat = make_image(2, 4, 4, 1);
  flat(0, 0) = 1;
  flat(1, 1) = 1;
  r = make_well_composed(flat);
  CHECK(r.image.size[2] == 1);
  CHECK(r.padded_before == std::array<std::size_t, 3>{1, 1, 0});
  check_result(flat, r, RepairMode::Add);
  CHECK(r.changed == 1);
}

TEST_CASE("rule (1): the only choice that creates nothing is taken", "[wellcomposed]") {
  // (C1) in N_z(r), r = (2,2,2): foreground (2,2,2), (3,3,2); background
  // a = (3,2,2), b = (2,3,2). The foreground (1,4,2) makes b a bad choice:
  // inserting b creates the (C1) {(2,3,2),(1,4,2)} / {(1,3,2),(2,4,2)};
  // inserting a creates nothing, so B1(r) = {{a}}.
  BinaryImage img = make_image(3, 7, 7, 5);
  img(2, 2, 2) = img(3, 3, 2) = 1;
  img(1, 4, 2) = 1;
  REQUIRE(brute_force(img).c1 == 1);
  REQUIRE(brute_force(img).c2 == 0);
  for (std::uint64_t seed = 0; seed < 20; ++seed) {
    WellComposedOptions opt;
    opt.seed = seed;
    const auto r = make_well_composed(img, opt);
    check_result(img, r, RepairMode::Add);
    CHECK(r.created == 0);
    CHECK(r.changed == 1);
    CHECK(out_at(r, 3, 2, 2) == 1);
    CHECK(out_at(r, 2, 3, 2) == 0);
  }
}

TEST_CASE("rule (3): a (C2) with six background points always creates (C1)", "[wellcomposed]") {
  BinaryImage img = make_image(3, 6, 6, 6);
  img(2, 2, 2) = img(3, 3, 3) = 1;
  REQUIRE(brute_force(img).c2 == 1);
  REQUIRE(brute_force(img).c1 == 0);
  for (std::uint64_t seed = 0; seed < 10; ++seed) {
    WellComposedOptions opt;
    opt.seed = seed;
    const auto r = make_well_composed(img, opt);
    check_result(img, r, RepairMode::Add);
    CHECK(r.input.c2 == 1);
    CHECK(r.created >= 1);  // Fig. 5.5: any of the six creates a (C1)
    CHECK(r.changed == 2);  // one for the (C2), one for the new (C1)
  }
}

TEST_CASE("two (C1) sharing a background point take one voxel", "[wellcomposed]") {
  // N_x(r), N_y(r) critical at r = (2,2,2) (the B(r) = {{a},{b,c}} case);
  // rule (1)/(2) prefer sets that create nothing, and {a} = r creates nothing here.
  BinaryImage img = make_image(3, 6, 6, 6);
  img(2, 2, 3) = img(2, 3, 2) = img(3, 2, 2) = img(3, 3, 2) = 1;
  REQUIRE(brute_force(img).c1 >= 2);
  for (std::uint64_t seed = 0; seed < 10; ++seed) {
    WellComposedOptions opt;
    opt.seed = seed;
    const auto r = make_well_composed(img, opt);
    check_result(img, r, RepairMode::Add);
    CHECK(r.changed == 1);
    CHECK(r.created == 0);
    CHECK(out_at(r, 2, 2, 2) == 1);
  }
}

TEST_CASE("bad images are refused", "[wellcomposed]") {
  BinaryImage img = make_image(3, 3, 3, 3);
  img.dimension = 4;
  CHECK_THROWS_AS(make_well_composed(img), Error);
  BinaryImage empty = make_image(3, 3, 3, 3);
  empty.size = {0, 3, 3};
  empty.data.clear();
  CHECK_THROWS_AS(count_critical_configurations(empty), Error);
  BinaryImage wrong = make_image(3, 3, 3, 3);
  wrong.data.resize(5);
  CHECK_THROWS_AS(make_well_composed(wrong), Error);
}

TEST_CASE("the result's report: counts of the input and of the output, the guarantee", "[wellcomposed][stats]") {
  std::mt19937_64 rng(99);
  BinaryImage in;
  do in = random_image(rng, 3, 0.4);
  while (brute_force(in).total() == 0);
  const CriticalCounts before = brute_force(in);
  WellComposedOptions opt;
  opt.seed = 5;
  opt.mode = RepairMode::Min;
  const WellComposedResult r = make_well_composed(in, opt);
  CHECK(r.output.total() == 0);
  CHECK(brute_force(r.image).total() == 0);
  CHECK(r.failed_guarantee().empty());
  const Json j = r.to_json();
  CHECK(j.at("c1").integer() == long(before.c1));
  CHECK(j.at("c2").integer() == long(before.c2));
  CHECK(j.at("voxels").integer() == long(in.count()));
  CHECK(j.at("mode").string() == "min");
  CHECK(j.at("seed").integer() == 5);
  CHECK(j.at("ratio").number() == Approx(double(r.changed) / double(before.total())));
  CHECK(j.at("well_composed").boolean());

  const WellComposedCheck c = check_well_composed(in);
  CHECK(c.counts.c1 == before.c1);
  CHECK(c.counts.c2 == before.c2);
  CHECK_FALSE(c.to_json().at("well_composed").boolean());
  CHECK(check_well_composed(r.image).to_json().at("well_composed").boolean());
}
