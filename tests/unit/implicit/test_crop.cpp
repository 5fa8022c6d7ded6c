// A foreground cut to its box plus the margin (implicit/crop.hpp): the same
// repair, the same g, d and clamped samples as the scan's whole grid, and f
// placed back in the scan evaluating as the whole grid's to the last bit.
#include "helpers.hpp"
#include "implicit/crop.hpp"
#include "implicit/implicit_file.hpp"
#include "util/error.hpp"

#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <random>

using namespace imgmesh;
using namespace imgmesh::test;

namespace {

// Random balls and salt (not well-composed) in a corner region of a larger
// grid, or touching its border.
BinaryImage scattered(std::size_t n0, std::size_t n1, std::size_t n2, unsigned seed, Vec3 spacing, bool border) {
  BinaryImage im(grid(n0, n1, n2, spacing), 0);
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(0, 1);
  const double lo = border ? 0 : 0.45, hi = border ? 0.4 : 0.8;  // the region, as a fraction of each axis
  auto at = [&](std::size_t n) { return (lo + (hi - lo) * u(rng)) * double(n); };
  for (int k = 0; k < 5; ++k) {
    const double cx = at(n0), cy = at(n1), cz = at(n2), r = 1 + u(rng) * 3;
    for (std::size_t z = 0; z < n2; ++z)
      for (std::size_t y = 0; y < n1; ++y)
        for (std::size_t x = 0; x < n0; ++x)
          if ((x - cx) * (x - cx) + (y - cy) * (y - cy) + (z - cz) * (z - cz) <= r * r) im(x, y, z) = 1;
  }
  for (int k = 0; k < 12; ++k) im(std::size_t(at(n0)), std::size_t(at(n1)), std::size_t(at(n2))) = 1;
  return im;
}

WellComposedCrop crop_of(const BinaryImage& im, const WellComposedOptions& opt) {
  return well_composed_crop(im, foreground_box(im),
                            [&](std::size_t y, std::size_t z, std::size_t x0, std::size_t n, std::uint8_t* out) {
                              std::copy_n(&im(x0, y, z), n, out);
                            },
                            opt);
}

template <class A> bool same_bits(const A& a, const A& b) { return std::memcmp(&a, &b, sizeof a) == 0; }

// f's samples placed in the frame's scan as the meshers read a crop's file.
PartitionOfUnity function_in_scan(const PartitionOfUnity& f, const ScanFrame& frame, float clamp, bool* placed) {
  const SampleGrid& g = f.samples();
  std::size_t z = 0;
  return function_in_scan(g.geometry(), frame, f.d(), clamp, [&](float* slice) {
    for (std::size_t y = 0; y < g.size[1]; ++y)
      for (std::size_t x = 0; x < g.size[0]; ++x) *slice++ = g(x, y, z);
    ++z;
  }, placed);
}

} // namespace

TEST_CASE("a crop is repaired as the whole grid: the same voxels, counts and padding", "[crop]") {
  int repaired = 0;
  for (unsigned seed = 1; seed <= 9; ++seed) {
    const Vec3 sp = seed % 3 == 0 ? Vec3{0.6, 0.6, 1.3} : Vec3{1, 1, 1};
    BinaryImage im = scattered(40, 36, 30, seed, sp, seed % 4 == 0);
    if (seed % 5 == 0) rotate(im);
    WellComposedOptions opt;
    opt.mode = seed % 3 == 0 ? RepairMode::Add : seed % 3 == 1 ? RepairMode::Remove : RepairMode::Min;
    opt.seed = seed;
    opt.greedy = seed != 7;
    INFO("seed " << seed);
    const WellComposedResult whole = make_well_composed(im, opt);
    const WellComposedCrop c = crop_of(im, opt);
    repaired += whole.changed > 0;
    // The crop's frame is the whole grid's output grid, to the last bit.
    REQUIRE(c.frame.size == whole.image.size);
    REQUIRE(same_bits(c.frame.origin, whole.image.origin));
    REQUIRE(c.result.padded_before == whole.padded_before);
    REQUIRE(c.result.padded_after == whole.padded_after);
    CHECK(c.result.input.c1 == whole.input.c1);
    CHECK(c.result.input.c2 == whole.input.c2);
    CHECK(c.result.changed == whole.changed);
    CHECK(c.result.created == whole.created);
    CHECK(c.result.mode_used == whole.mode_used);
    CHECK(c.result.output.total() == 0);
    // The same voxels: the crop's, and background all around it.
    const BinaryImage& out = c.result.image;
    const Vec3 at = whole.image.world(double(c.frame.index[0]), double(c.frame.index[1]), double(c.frame.index[2]));
    for (int a = 0; a < 3; ++a) CHECK(std::abs(at[a] - out.origin[a]) <= 1e-12 * (1 + std::abs(at[a])));
    std::size_t inside = 0;
    for (std::size_t z = 0; z < whole.image.size[2]; ++z)
      for (std::size_t y = 0; y < whole.image.size[1]; ++y)
        for (std::size_t x = 0; x < whole.image.size[0]; ++x) {
          const long cx = long(x) - c.frame.index[0], cy = long(y) - c.frame.index[1], cz = long(z) - c.frame.index[2];
          const std::uint8_t v = out.at(cx, cy, cz, 0);
          if (out.inside(cx, cy, cz)) ++inside;
          if (v != whole.image(x, y, z)) FAIL("voxel " << x << " " << y << " " << z << " differs");
        }
    REQUIRE(inside == out.count());
    // The margin is kept wherever the crop's side lies inside the scan.
    const VoxelBox fg = foreground_box(out);
    REQUIRE(c.frame.foreground.lo == fg.lo);
    REQUIRE(c.frame.foreground.hi == fg.hi);
    const auto m = crop_margin(out);
    for (int a = 0; a < 3; ++a) {
      if (c.frame.index[a] > 0) CHECK(fg.lo[a] == long(m[a]));
      if (std::size_t(c.frame.index[a]) + out.size[a] < c.frame.size[a]) CHECK(long(out.size[a]) - 1 - fg.hi[a] == long(m[a]));
    }
  }
  CHECK(repaired >= 6);  // the repair had work to do
}

TEST_CASE("crop_margin covers the clamp and the cells d is taken over, and no more", "[crop]") {
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(0.2, 3);
  for (int trial = 0; trial < 200; ++trial) {
    const Vec3 sp{u(rng), u(rng), u(rng)};
    const double t = trial % 2 ? u(rng) * 10 : 0;
    const auto m = crop_margin(sp, t), w = PartitionOfUnity::weight_margin(sp);
    const double r = PartitionOfUnity::near_radius(sp);
    for (int a = 0; a < 3; ++a) {
      // A vertex k voxels beyond the foreground's box is at least (k - 1/2)
      // spacings from bdCA(X): one w voxels beyond is not near S, so a cell
      // with a vertex nearer than R lies within w; w - 1 would not do.
      REQUIRE((double(w[a]) - 0.5) * sp[a] >= r);
      REQUIRE((double(w[a]) - 1.5) * sp[a] <= r);
      REQUIRE(m[a] >= w[a]);
      REQUIRE((double(m[a]) + 0.5) * sp[a] >= t);
      if (m[a] > w[a]) REQUIRE((double(m[a]) - 0.5) * sp[a] < t);
    }
  }
}

TEST_CASE("a crop's f placed in its scan is the whole grid's f, bit for bit", "[crop]") {
  for (unsigned seed = 1; seed <= 6; ++seed) {
    const Vec3 sp = seed % 2 ? Vec3{1, 1, 1} : Vec3{0.617, 0.617, 1.333};
    BinaryImage im = scattered(44, 40, 34, seed + 10, sp, seed == 4);
    if (seed == 3) rotate(im);
    INFO("seed " << seed);
    const WellComposedCrop c = crop_of(im, WellComposedOptions());
    // The whole grid: img2wc --full-grid | wc2implicit | the mesher's read.
    const WellComposedResult whole = make_well_composed(im, WellComposedOptions());
    const PartitionOfUnity fw = implicit_from_well_composed(whole.image);
    const float t = PartitionOfUnity::clamp_for(fw.samples(), 0.3 * std::min({sp[0], sp[1], sp[2]}));
    const PartitionOfUnity mw(fw.samples().to_image(), fw.d(), 1, t);
    // The crop: img2wc | wc2implicit | the mesher's read.
    ImplicitReport rep;
    const PartitionOfUnity fc = implicit_from_well_composed(c.result.image, &rep);
    ScanFrame frame = c.frame;  // as wc2implicit carries it
    REQUIRE(frame.grow(rep.padded_before, rep.padded_after, c.result.image));
    REQUIRE(same_bits(fc.d(), fw.d()));
    REQUIRE(fc.g_min() == fw.g_min());
    REQUIRE(fc.l_max() == fw.l_max());
    bool placed = false;
    const PartitionOfUnity mc = function_in_scan(fc, frame, t, &placed);
    REQUIRE(placed);
    const SampleGrid &a = mw.samples(), &b = mc.samples();
    REQUIRE(b.size == a.size);
    REQUIRE(same_bits(b.origin, a.origin));
    REQUIRE(same_bits(b.spacing, a.spacing));
    REQUIRE(same_bits(b.direction, a.direction));
    REQUIRE(same_bits(mc.d(), mw.d()));
    for (std::size_t z = 0; z < a.size[2]; ++z)
      for (std::size_t y = 0; y < a.size[1]; ++y)
        for (std::size_t x = 0; x < a.size[0]; ++x)
          if (!same_bits(a(x, y, z), b(x, y, z))) FAIL("sample " << x << " " << y << " " << z << " differs");
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> u(0, 1);
    for (int i = 0; i < 20000; ++i) {
      const Vec3 p = a.world(u(rng) * double(a.size[0] - 1), u(rng) * double(a.size[1] - 1), u(rng) * double(a.size[2] - 1));
      Vec3 ga, gb;
      const double va = mw.value_gradient(p, ga), vb = mc.value_gradient(p, gb);
      if (!same_bits(va, vb) || !same_bits(ga, gb)) FAIL("f differs at " << p[0] << " " << p[1] << " " << p[2]);
    }
    // A clamp beyond the margin: the crop stays on its own grid.
    const PartitionOfUnity alone = function_in_scan(fc, frame, 4 * t, &placed);
    CHECK_FALSE(placed);
    CHECK(alone.samples().size == fc.samples().size);
  }
}

TEST_CASE("the scan frame travels in key/value fields and is checked", "[crop]") {
  const BinaryImage im = scattered(30, 28, 26, 5, {0.7, 0.8, 1.1}, false);
  const WellComposedCrop c = crop_of(im, WellComposedOptions());
  const Geometry& g = c.result.image;
  const ScanFrame back = ScanFrame::from_keys(c.frame.keys(), g, "x.nrrd");
  CHECK(back.size == c.frame.size);
  CHECK(back.index == c.frame.index);
  CHECK(same_bits(back.origin, c.frame.origin));
  CHECK(back.foreground.lo == c.frame.foreground.lo);
  CHECK(back.foreground.hi == c.frame.foreground.hi);
  CHECK_FALSE(ScanFrame::from_keys({{"imgmesh_kind", "pu-implicit"}}, g, "x.nrrd").present());
  // One key changed (or, value empty, removed): refused, naming the file.
  auto refused = [&](const std::string& key, const std::string& value, const std::string& why) {
    auto keys = c.frame.keys();
    if (value.empty()) keys.erase(key);
    else keys[key] = value;
    try {
      ScanFrame::from_keys(keys, g, "x.nrrd");
      FAIL("accepted: " << why);
    } catch (const Error& e) {
      CHECK(std::string(e.what()).find(why) != std::string::npos);
      CHECK(e.path() == "x.nrrd");
    }
  };
  refused("imgmesh_scan_origin", "", "incomplete");
  refused("imgmesh_scan_index", "1 2 3", "origin is not where");
  refused("imgmesh_scan_size", "5 5 5", "does not lie inside");
  refused("imgmesh_foreground_box", "0 0 0 999 1 1", "imgmesh_foreground_box");
  refused("imgmesh_scan_origin", "1 2", "bad imgmesh_scan_origin");
}

TEST_CASE("seg2mesh's f built a band at a time is the crop's f placed in its scan, bit for bit", "[crop]") {
  // implicit_in_scan against implicit_from_well_composed then
  // function_in_scan: anisotropic grids, foreground touching the scan's
  // side (the grid grows), a clamp beyond the margin (not placed), bands
  // of one block and more.
  for (unsigned seed = 1; seed <= 6; ++seed) {
    const Vec3 sp = seed % 2 ? Vec3{1, 1, 1} : seed == 4 ? Vec3{0.617, 0.617, 1.333} : Vec3{1.4, 0.5, 0.9};
    BinaryImage im = scattered(44, 40, 34, seed + 20, sp, seed >= 4);
    if (seed == 3) rotate(im);
    INFO("seed " << seed);
    WellComposedCrop c = crop_of(im, WellComposedOptions());
    c.frame.foreground = foreground_box(c.result.image);
    const float t = PartitionOfUnity::clamp_for(c.result.image, 0.3 * std::min({sp[0], sp[1], sp[2]}));
    for (const float clamp : {t, 4 * t}) {
      ImplicitReport rep;
      const PartitionOfUnity whole = implicit_from_well_composed(c.result.image, &rep);
      ScanFrame frame = c.frame;
      if (!frame.grow(rep.padded_before, rep.padded_after, c.result.image)) frame = ScanFrame();
      bool placed = false, placed_bands = true;
      const PartitionOfUnity a = function_in_scan(whole, frame, clamp, &placed);
      const std::size_t column = whole.samples().size[1] * whole.samples().size[2] * sizeof(float);
      const PartitionOfUnity b = implicit_in_scan(c.result.image, c.frame, clamp, 2, &placed_bands,
                                                  seed % 2 ? column * 5 : SampleGrid::kBandBytes);
      REQUIRE(placed_bands == placed);
      CHECK(placed == (clamp == t));
      REQUIRE(same_bits(b.d(), a.d()));
      REQUIRE(b.g_min() == a.g_min());
      REQUIRE(b.l_max() == a.l_max());
      const SampleGrid &ga = a.samples(), &gb = b.samples();
      REQUIRE(gb.size == ga.size);
      REQUIRE(same_bits(gb.origin, ga.origin));
      REQUIRE(gb.box_lo() == ga.box_lo());
      REQUIRE(gb.dense() == ga.dense());
      REQUIRE(gb.stored_blocks() == ga.stored_blocks());
      for (std::size_t z = 0; z < ga.size[2]; ++z)
        for (std::size_t y = 0; y < ga.size[1]; ++y)
          for (std::size_t x = 0; x < ga.size[0]; ++x)
            if (!same_bits(ga(x, y, z), gb(x, y, z))) FAIL("sample " << x << " " << y << " " << z << " differs");
    }
  }
}
