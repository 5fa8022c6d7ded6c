// The labelling function lambda (conforming/label_function.hpp): the
// voxel's label at every voxel centre, 0 beyond the grid, and its changes
// found where the labels of two neighbouring centres differ.
#include "conforming/conforming_surface.hpp"
#include "conforming/label_function.hpp"
#include "image/narrow_labels.hpp"
#include "label_maps.hpp"
#include "wellcomposed/well_composed_partition.hpp"

#include <catch2/catch.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <random>

using namespace imgmesh;
using namespace imgmesh::test;

namespace {

// The point at t of segment [a, b].
Vec3 along(const Vec3& a, const Vec3& b, double t) {
  return {a[0] + t * (b[0] - a[0]), a[1] + t * (b[1] - a[1]), a[2] + t * (b[2] - a[2])};
}

// [a, b]'s length in voxels of the smallest spacing h (the walk's step's unit).
double voxels(const Vec3& a, const Vec3& b, double h) {
  double len = 0;
  for (int m = 0; m < 3; ++m) len += (b[m] - a[m]) * (b[m] - a[m]);
  return std::sqrt(len) / h;
}

// Every voxel centre carries its label; between face neighbours of
// different labels lambda changes, first from the first one's label, and
// the change lies between them; no change between two centres of one
// label within a pure stretch (both 4x4x4 neighbourhoods one label).
void check_centres(const LabelImage& x, const LabelFunction& f) {
  std::vector<LabelFunction::Change> ch;
  std::size_t pairs = 0;
  for (std::size_t z = 0; z < x.size[2]; ++z)
    for (std::size_t y = 0; y < x.size[1]; ++y)
      for (std::size_t i = 0; i < x.size[0]; ++i) {
        const Vec3 p = x.world(double(i), double(y), double(z));
        REQUIRE(f.label(p) == x(i, y, z));
        if (i + 1 == x.size[0] || x(i + 1, y, z) == x(i, y, z)) continue;
        f.changes(p, x.world(double(i + 1), double(y), double(z)), ch);
        REQUIRE(!ch.empty());
        CHECK(ch.front().before == x(i, y, z));
        CHECK(ch.back().after == x(i + 1, y, z));
        CHECK(ch.front().t > 0);
        CHECK(ch.back().t < 1);
        ++pairs;
      }
  CHECK(pairs > 0);
}

// A repaired Voronoi map of `count` labels on 12^3 anisotropic voxels, origin moved.
LabelImage anisotropic_map(std::mt19937_64& rng, int count) {
  LabelImage x = make_well_composed_partition(voronoi_map(rng, 12, count)).image;
  x.spacing = {0.8, 1.0, 1.3};
  x.origin = {3, -2, 1};
  return x;
}

} // namespace

TEST_CASE("lambda is the voxel's label at every voxel centre and changes between labels", "[conforming]") {
  for (const LabelImage& x : {nested_shells(), three_labels(), four_labels_around_an_edge()}) {
    const LabelFunction f(x, 0.3);
    check_centres(x, f);
    // Beyond the grid: 0.
    CHECK(f.label(x.world(-0.6, 2, 2)) == 0);
    CHECK(f.label(x.world(double(x.size[0]) + 3, 2, 2)) == 0);
  }
  std::mt19937_64 rng(7);
  for (int rep = 0; rep < 3; ++rep) {
    LabelImage x = make_well_composed_partition(voronoi_map(rng, 10, 4)).image;
    x.spacing = {0.8, 1.0, 1.3};
    x.origin = {3, -2, 1};
    const LabelFunction f(x, 0.3 * 0.8);
    check_centres(x, f);
  }
}

TEST_CASE("lambda refuses a map that is not well-composed", "[conforming]") {
  LabelImage x = label_grid(8, 8, 8);
  paint(x, {2, 2, 2}, {3, 3, 3}, 1);
  paint(x, {4, 4, 4}, {5, 5, 5}, 1);  // touches the first box along an edge: a C1 of label 1
  CHECK_THROWS_WITH(LabelFunction(x, 0.3), Catch::Contains("not well-composed"));
}

// lambda by its definition from the labels' f at random points: where
// some f is negative, the label of highest rank among those (0 lowest, then
// from the most voxels to the fewest, ties: the larger label higher), else
// argmin (ties: the lower label). Where the voxels f reads are all one
// label, label() answers without evaluating f, and elsewhere evaluates first
// the labels those voxels carry. Maps of 5 to 60 labels: the candidates'
// words of 1, 2, 4 and 8 bytes; of 90 and 200: more labels than bits, and
// (past 127) two bytes a voxel.
TEST_CASE("lambda at random points is its definition from the labels' f", "[conforming]") {
  std::mt19937_64 rng(11);
  std::size_t checked = 0, ranked = 0, gaps = 0, most = 0;
  for (int count : {5, 5, 12, 24, 60, 90, 200}) {
    const LabelImage x = anisotropic_map(rng, count);
    const LabelFunction f(x, 0.3 * 0.8);
    std::map<std::int32_t, std::size_t> voxels{{0, 0}};
    for (std::int32_t v : x.data) ++voxels[v];
    most = std::max(most, voxels.size());
    auto outranks = [&](std::int32_t a, std::int32_t b) {
      if (a == 0 || b == 0) return b == 0 && a != 0;
      return voxels[a] < voxels[b] || (voxels[a] == voxels[b] && a > b);
    };
    // Half the points anywhere, half between the zeros of f_a and f_b
    // along a segment across a face between a and b: where both are
    // negative (the rank decides) or both positive (argmin decides).
    std::uniform_real_distribution<double> u(0, 1);
    std::uniform_int_distribution<std::size_t> voxel(0, x.count() - 1);
    for (int n = 0; n < 4000; ++n) {
      Vec3 q{u(rng) * double(x.size[0] - 1), u(rng) * double(x.size[1] - 1), u(rng) * double(x.size[2] - 1)};
      for (int tries = 0; n % 2 == 1 && tries < 100; ++tries) {
        const std::size_t v = voxel(rng);
        const std::array<std::size_t, 3> w0{v % x.size[0], v / x.size[0] % x.size[1], v / x.size[0] / x.size[1]};
        const std::size_t ax = v % 3;
        std::array<std::size_t, 3> w1 = w0;
        if (++w1[ax] >= x.size[ax] || x(w0[0], w0[1], w0[2]) == x(w1[0], w1[1], w1[2])) continue;
        Vec3 q0, q1;
        for (std::size_t m = 0; m < 3; ++m) {
          const double off = m == ax ? 0 : std::clamp(double(w0[m]) + u(rng) - 0.5, 0.0, double(x.size[m] - 1)) - double(w0[m]);
          q0[m] = double(w0[m]) + off, q1[m] = double(w1[m]) + off;
        }
        auto zero = [&](std::int32_t l) {  // f_l's change of sign from q0 to q1
          double lo = 0, hi = 1;
          const double s0 = f.value(l, x.world(q0[0], q0[1], q0[2]));
          for (int it = 0; it < 40; ++it) {
            const double t = 0.5 * (lo + hi);
            const double s = f.value(l, x.world(q0[0] + t * (q1[0] - q0[0]), q0[1] + t * (q1[1] - q0[1]), q0[2] + t * (q1[2] - q0[2])));
            ((s < 0) == (s0 < 0) ? lo : hi) = t;
          }
          return lo;
        };
        const double t = 0.5 * (zero(x(w0[0], w0[1], w0[2])) + zero(x(w1[0], w1[1], w1[2])));
        for (std::size_t m = 0; m < 3; ++m) q[m] = q0[m] + t * (q1[m] - q0[m]);
        break;
      }
      const Vec3 p = x.world(q[0], q[1], q[2]);
      std::int32_t best = 0, negative = 0;
      double fbest = INFINITY;
      int negatives = 0;
      for (const auto& [l, count_l] : voxels) {
        const double v = f.value(l, p);
        if (v < 0 && (negatives++ == 0 || outranks(l, negative))) negative = l;
        if (v < fbest || (v == fbest && l < best)) fbest = v, best = l;
      }
      REQUIRE(f.label(p) == (negatives > 0 ? negative : best));
      ++checked;
      if (negatives > 1) ++ranked;
      if (negatives == 0) ++gaps;
    }
  }
  CHECK(checked == 28000);
  CHECK(ranked > 100);
  CHECK(gaps > 100);
  CHECK(most > 128);
}

// Each change changes() reports lies within 1e-4 voxel of lambda's: a
// fine scan within half that before it finds its `before`, after it another
// label, nearly always its `after` (else a third label lies between, closer
// than the walk's step). Random segments through interfaces of noisy,
// anisotropic maps: overlaps, gaps, ties on the voxel faces, three labels.
// brackets() gives the same changes unplaced, each between its two
// samples, and place() each one's t, bit for bit (the mesher decides on
// the bracket where that suffices).
TEST_CASE("lambda's changes are placed within 1e-4 voxel", "[conforming]") {
  std::mt19937_64 rng(5);
  std::size_t changes = 0, afters = 0, segments = 0;
  for (int count : {4, 12, 30}) {
    const LabelImage x = anisotropic_map(rng, count);
    const LabelFunction f(x, 0.3 * 0.8);
    std::uniform_real_distribution<double> u(0, 1);
    std::vector<LabelFunction::Change> ch;
    std::vector<LabelFunction::Bracket> br;
    for (int n = 0; n < 1500; ++n) {
      // Half the segments from a voxel centre to a face neighbour's (the
      // seeds' and VoxelSides' walks), half between random points.
      Vec3 a, b;
      if (n % 2 == 0) {
        const std::array<std::size_t, 3> w{std::size_t(u(rng) * double(x.size[0] - 1)),
                                           std::size_t(u(rng) * double(x.size[1] - 1)),
                                           std::size_t(u(rng) * double(x.size[2] - 1))};
        const int ax = n / 2 % 3;
        a = x.world(double(w[0]), double(w[1]), double(w[2]));
        b = x.world(double(w[0] + (ax == 0)), double(w[1] + (ax == 1)), double(w[2] + (ax == 2)));
      } else {
        const Vec3 c{u(rng) * double(x.size[0] - 1), u(rng) * double(x.size[1] - 1), u(rng) * double(x.size[2] - 1)};
        a = x.world(c[0], c[1], c[2]);
        b = x.world(c[0] + 3 * u(rng) - 1.5, c[1] + 3 * u(rng) - 1.5, c[2] + 3 * u(rng) - 1.5);
      }
      f.changes(a, b, ch);
      f.brackets(a, b, br);
      REQUIRE(br.size() == ch.size());
      for (std::size_t k = 0; k < ch.size(); ++k) {
        CHECK(br[k].before == ch[k].before);
        CHECK(br[k].after == ch[k].after);
        REQUIRE(br[k].t0 < br[k].t1);
        REQUIRE(br[k].t0 <= ch[k].t);
        REQUIRE(ch[k].t <= br[k].t1);
        REQUIRE(f.place(a, b, br[k]) == ch[k].t);
        // The samples' labels: no change between them is missed.
        CHECK(f.label(along(a, b, br[k].t0)) == br[k].before);
        CHECK(f.label(along(a, b, br[k].t1)) == br[k].after);
      }
      ++segments;
      const double dt = 0.5e-4 / voxels(a, b, 0.8);
      auto at = [&](double t) { return along(a, b, t); };
      for (const auto& c : ch) {
        bool before = false, other = false, after = false;
        for (int j = 1; j <= 20; ++j) {
          before = before || f.label(at(std::max(0.0, c.t - dt * j / 20))) == c.before;
          const std::int32_t l = f.label(at(std::min(1.0, c.t + dt * j / 20)));
          other = other || l != c.before;
          after = after || l == c.after;
        }
        REQUIRE(before);
        REQUIRE(other);
        ++changes;
        if (after) ++afters;
      }
    }
  }
  CHECK(segments == 4500);
  CHECK(changes > 1000);
  CHECK(afters >= changes * 98 / 100);
}

// The walk's promise at the mesher's step (ConformingOptions::step): every
// run of one label along a segment longer than the step holds a sample, so
// the labels of those runs are among the changes', in order (a shorter run,
// a corner cut, may be missed). Random segments through noisy, anisotropic
// maps, scanned every 1/100 voxel; runs of less than twice the step between
// two others make sure a walk of a coarser step fails.
TEST_CASE("lambda's walk finds every run of one label longer than its step", "[conforming]") {
  const double step = ConformingOptions().step;
  std::mt19937_64 rng(17);
  std::size_t runs = 0, close = 0, segments = 0;
  for (int count : {12, 30, 60}) {
    const LabelImage x = anisotropic_map(rng, count);
    const LabelFunction f(x, 0.3 * 0.8);
    std::uniform_real_distribution<double> u(0, 1);
    std::vector<LabelFunction::Change> ch;
    for (int n = 0; n < 2500; ++n) {
      const Vec3 c{u(rng) * double(x.size[0] - 1), u(rng) * double(x.size[1] - 1), u(rng) * double(x.size[2] - 1)};
      Vec3 e;
      for (int m = 0; m < 3; ++m) e[m] = std::clamp(c[m] + 6 * u(rng) - 3, 0.0, double(x.size[m] - 1));
      const Vec3 a = x.world(c[0], c[1], c[2]), b = x.world(e[0], e[1], e[2]);
      const double len = voxels(a, b, 0.8);  // as the step
      if (len < 1) continue;
      ++segments;
      f.changes(a, b, ch, step);
      std::vector<std::int32_t> found{f.label(a)};
      for (const auto& h : ch) found.push_back(h.after);
      // The fine scan's runs; those longer than the step (their samples'
      // extent, a lower bound), consecutive repeats merged.
      const std::size_t m = std::size_t(std::ceil(len / 0.01));
      auto at = [&](std::size_t j) {
        return f.label(along(a, b, double(j) / double(m)));
      };
      std::vector<std::int32_t> long_runs;
      std::size_t start = 0;
      std::int32_t l = at(0);
      for (std::size_t j = 1; j <= m + 1; ++j) {
        const std::int32_t next = j <= m ? at(j) : l + 1;
        if (next == l) continue;
        const double extent = double(j - 1 - start) * len / double(m);
        if (extent > step) {
          ++runs;
          if (start > 0 && j <= m && extent < 2 * step) ++close;
          if (long_runs.empty() || long_runs.back() != l) long_runs.push_back(l);
        }
        start = j, l = next;
      }
      // A subsequence of the labels found.
      std::size_t k = 0;
      for (std::int32_t r : long_runs) {
        while (k < found.size() && found[k] != r) ++k;
        INFO("segment " << n << " of the map of " << count << " labels");
        REQUIRE(k < found.size());
      }
    }
  }
  CHECK(segments > 7000);
  CHECK(runs > 10000);
  CHECK(close > 100);
}

// The slope bound the walk's margins rest on (label_function.hpp): |f_L(p)
// - f_L(q)| <= kLipschitz sum_m |p_m - q_m| delta_m (continuous indices),
// for every label and the union, on noisy anisotropic maps; pairs 0.01 to
// 0.5 voxel apart, half near the planes of voxel centres (where cells
// blend and f is steepest), most along an axis. The steepest pair seen
// (1.45) is near the bound: a bound of 1.4 fails.
TEST_CASE("every label's f keeps the slope bound of lambda's walk", "[conforming]") {
  std::mt19937_64 rng(23);
  double steepest = 0;
  std::size_t pairs = 0;
  for (int count : {4, 12, 30}) {
    const LabelImage x = anisotropic_map(rng, count);
    const LabelFunction f(x, 0.3 * 0.8);
    std::vector<std::int32_t> labels{0};
    for (std::int32_t v : x.data)
      if (std::find(labels.begin(), labels.end(), v) == labels.end()) labels.push_back(v);
    std::uniform_real_distribution<double> u(0, 1);
    for (int n = 0; n < 3000; ++n) {
      Vec3 q, r;
      const double len = n % 3 == 0 ? 0.01 : n % 3 == 1 ? 0.1 : 0.5;
      const int axis = n % 4;  // 3: any direction, else along that axis
      for (int m = 0; m < 3; ++m) {
        // Half the points within 0.2 of a plane of centres.
        const double c = u(rng) * double(x.size[m] - 2) + 0.5;
        q[m] = n % 2 == 0 ? std::round(c) + 0.4 * u(rng) - 0.2 : c;
        r[m] = axis == 3 || axis == m ? q[m] + len * (2 * u(rng) - 1) : q[m];
      }
      double bound = 0;
      for (int m = 0; m < 3; ++m) bound += std::fabs(r[m] - q[m]) * x.spacing[m];
      const Vec3 p = x.world(q[0], q[1], q[2]), s = x.world(r[0], r[1], r[2]);
      for (std::int32_t l : labels) {
        const double diff = std::fabs(f.value(l, p) - f.value(l, s));
        REQUIRE(diff <= LabelFunction::kLipschitz * bound);
        steepest = std::max(steepest, diff / bound);
        ++pairs;
      }
    }
  }
  CHECK(pairs > 50000);
  CHECK(steepest > 1.4);
}

// seg2mesh holds X in the narrowest type its labels fit: the same lambda
// from one byte a voxel and from two (labels past 255), everywhere, as
// from the int32 map of the same labels.
TEST_CASE("lambda from a map held in one or two bytes a voxel is the int32 map's", "[conforming]") {
  std::mt19937_64 rng(5);
  const LabelImage x = anisotropic_map(rng, 40);
  LabelImage wide = x;  // the labels past 255, their order kept
  for (std::int32_t& v : wide.data)
    if (v != 0) v += 1000;
  const NarrowLabelImage bytes1 = narrow_labels(x), bytes2 = narrow_labels(wide);
  REQUIRE(bytes1.bytes == 1);
  REQUIRE(bytes2.bytes == 2);
  const LabelFunction f(x, 0.3 * 0.8), f1(bytes1, 0.3 * 0.8), f2(bytes2, 0.3 * 0.8);
  check_centres(x, f1);
  check_centres(wide, f2);
  std::uniform_real_distribution<double> u(-1.5, 12.5);
  for (int n = 0; n < 3000; ++n) {
    const Vec3 p = x.world(u(rng), u(rng), u(rng));
    const std::int32_t l = f.label(p);
    REQUIRE(f1.label(p) == l);
    REQUIRE(f2.label(p) == (l == 0 ? 0 : l + 1000));
  }
}
