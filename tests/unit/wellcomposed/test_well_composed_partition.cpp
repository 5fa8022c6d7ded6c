// The multi-label count and repair (issue 36) against the binary counter
// (itself tested against brute force in test_well_composed.cpp), applied to
// each label's indicator and to the background's: no configuration left for
// any of them, every voxel's label one of the input's, every input label
// kept, the reported changes the actual ones, the same output twice.
#include "wellcomposed/well_composed_partition.hpp"

#include "util/error.hpp"
#include "wellcomposed/interface_complex.hpp"

#include <catch2/catch.hpp>

#include <algorithm>
#include <cstdint>
#include <iostream>
#include <map>
#include <random>
#include <set>

using namespace imgmesh;

namespace {

LabelImage make_image(int dim, std::size_t nx, std::size_t ny, std::size_t nz) {
  Geometry g;
  g.dimension = dim;
  g.size = {nx, ny, dim == 2 ? 1 : nz};
  g.origin = {1.5, -2.0, 0.25};
  g.spacing = {0.5, 0.75, 1.25};
  return LabelImage(g, 0);
}

// Label values: 0 and `k` others, spread (negative and large ones too).
std::vector<std::int32_t> label_set(std::mt19937_64& rng, int k) {
  std::set<std::int32_t> s;
  std::uniform_int_distribution<int> wide(-5, 70000);
  while (int(s.size()) < k) {
    const int v = rng() % 4 == 0 ? wide(rng) : int(rng() % 300) + 1;
    if (v != 0) s.insert(v);
  }
  return {s.begin(), s.end()};
}

// Random partitions: Voronoi cells of `k` labels (some cells background)
// with noise, plus one-voxel structures; sides of 1 to `side` voxels, labels
// touching the faces wherever they fall.
LabelImage random_partition(std::mt19937_64& rng, int dim, int side, int k, double noise) {
  std::uniform_int_distribution<int> sz(1, side);
  LabelImage img = make_image(dim, std::size_t(sz(rng)), std::size_t(sz(rng)), std::size_t(sz(rng)));
  const std::vector<std::int32_t> labels = label_set(rng, k);
  struct Seed { double p[3]; std::int32_t label; };
  std::vector<Seed> seeds(std::size_t(k) + 2);
  std::uniform_real_distribution<double> u(0, 1);
  for (std::size_t s = 0; s < seeds.size(); ++s) {
    for (int a = 0; a < 3; ++a) seeds[s].p[a] = u(rng) * double(img.size[a]);
    seeds[s].label = s < labels.size() ? labels[s] : 0;
  }
  for (std::size_t z = 0; z < img.size[2]; ++z)
    for (std::size_t y = 0; y < img.size[1]; ++y)
      for (std::size_t x = 0; x < img.size[0]; ++x) {
        double best = 1e30;
        for (const Seed& s : seeds) {
          const double d = (s.p[0] - double(x)) * (s.p[0] - double(x)) + (s.p[1] - double(y)) * (s.p[1] - double(y)) +
                           (s.p[2] - double(z)) * (s.p[2] - double(z));
          if (d < best) { best = d; img(x, y, z) = s.label; }
        }
        if (u(rng) < noise) img(x, y, z) = rng() % 5 == 0 ? 0 : labels[rng() % labels.size()];
      }
  // One-voxel structures of labels of their own.
  for (int i = 0; i < 3; ++i)
    img.data[rng() % img.data.size()] = 100001 + i;
  return img;
}

BinaryImage indicator(const LabelImage& img, std::int32_t l) {
  BinaryImage b(img.geometry(), 0);
  for (std::size_t i = 0; i < img.data.size(); ++i) b.data[i] = img.data[i] == l;
  return b;
}
// The background's indicator's complement (the same configurations).
BinaryImage foreground(const LabelImage& img) {
  BinaryImage b(img.geometry(), 0);
  for (std::size_t i = 0; i < img.data.size(); ++i) b.data[i] = img.data[i] != 0;
  return b;
}

std::set<std::int32_t> values_of(const LabelImage& img) { return {img.data.begin(), img.data.end()}; }

// Every property of a result, checked through the binary counter.
void check_result(const LabelImage& in, const PartitionResult& r) {
  const LabelImage& out = r.image;
  REQUIRE(out.dimension == in.dimension);
  for (int a = 0; a < 3; ++a) REQUIRE(out.size[a] == in.size[a] + r.padded_before[a] + r.padded_after[a]);
  const Vec3 w0 = in.world(0, 0, 0);
  const Vec3 w1 = out.world(double(r.padded_before[0]), double(r.padded_before[1]), double(r.padded_before[2]));
  for (int a = 0; a < 3; ++a) REQUIRE(w0[a] == Approx(w1[a]));
  // No configuration left, for every label and the background.
  const std::set<std::int32_t> in_labels = values_of(in), out_labels = values_of(out);
  for (std::int32_t l : out_labels)
    if (l != 0) REQUIRE(count_critical_configurations(indicator(out, l)).total() == 0);
  REQUIRE(count_critical_configurations(foreground(out)).total() == 0);
  REQUIRE(r.output.total() == 0);
  REQUIRE(r.failed_guarantee().empty());
  // Labels: only the input's (and the grown border's 0); every input label kept.
  for (std::int32_t l : out_labels) REQUIRE((l == 0 || in_labels.count(l)));
  for (std::int32_t l : in_labels) REQUIRE((l == 0 || out_labels.count(l)));
  REQUIRE(r.lost.empty());
  // The changes are the differences; the grown border is background.
  std::map<std::pair<std::int32_t, std::int32_t>, std::size_t> diff;
  std::size_t n = 0;
  for (std::size_t z = 0; z < in.size[2]; ++z)
    for (std::size_t y = 0; y < in.size[1]; ++y)
      for (std::size_t x = 0; x < in.size[0]; ++x) {
        const std::int32_t a = in(x, y, z), b = out(x + r.padded_before[0], y + r.padded_before[1], z + r.padded_before[2]);
        if (a != b) ++diff[{a, b}], ++n;
      }
  REQUIRE(diff == r.changes);
  REQUIRE(n == r.changed);
  // Labels only grow into the background (the binary add mode's rule).
  for (const auto& [ab, count] : r.changes) REQUIRE(ab.second != 0);
  std::size_t border = 0;
  for (std::int32_t v : out.data) border += v != 0;
  std::size_t inner = 0;
  for (std::size_t z = 0; z < in.size[2]; ++z)
    for (std::size_t y = 0; y < in.size[1]; ++y)
      for (std::size_t x = 0; x < in.size[0]; ++x)
        inner += out(x + r.padded_before[0], y + r.padded_before[1], z + r.padded_before[2]) != 0;
  REQUIRE(border == inner);
  // The per-label input counts are the binary counter's.
  for (std::size_t i = 0; i < r.input.labels.size(); ++i) {
    const CriticalCounts c = r.input.labels[i] == 0 ? count_critical_configurations(foreground(in))
                                                     : count_critical_configurations(indicator(in, r.input.labels[i]));
    REQUIRE(r.input.counts[i].c1 == c.c1);
    REQUIRE(r.input.counts[i].c2 == c.c2);
  }
}

// Changes of the binary add-mode repairs of each nonzero label, summed.
std::size_t binary_sum(const LabelImage& in) {
  std::size_t s = 0;
  for (std::int32_t l : values_of(in))
    if (l != 0) s += make_well_composed(indicator(in, l)).changed;
  return s;
}

} // namespace

TEST_CASE("label counter agrees with the binary counter on every indicator", "[wellcomposed][labels]") {
  std::mt19937_64 rng(36);
  for (int dim : {2, 3})
    for (int k : {1, 2, 5, 20, 50})
      for (int i = 0; i < 40; ++i) {
        const LabelImage img = random_partition(rng, dim, dim == 2 ? 14 : 8, k, 0.2 * (i % 4));
        const LabelCriticalCounts c = count_label_critical_configurations(img);
        REQUIRE(c.labels.front() == 0);
        REQUIRE(std::is_sorted(c.labels.begin() + 1, c.labels.end()));
        std::set<std::int32_t> present = values_of(img);
        present.insert(0);
        REQUIRE(std::set<std::int32_t>(c.labels.begin(), c.labels.end()) == present);
        for (std::size_t j = 0; j < c.labels.size(); ++j) {
          const CriticalCounts b = c.labels[j] == 0 ? count_critical_configurations(foreground(img))
                                                     : count_critical_configurations(indicator(img, c.labels[j]));
          REQUIRE(c.counts[j].c1 == b.c1);
          REQUIRE(c.counts[j].c2 == b.c2);
        }
      }
}

TEST_CASE("partition repair: every label well-composed, labels kept, changes reported", "[wellcomposed][labels]") {
  std::mt19937_64 rng(3636);
  std::size_t changed = 0, binary = 0, configs = 0, images = 0, promotions = 0;
  for (auto priority : {PartitionOptions::Priority::Smaller, PartitionOptions::Priority::Larger})
  for (int dim : {2, 3})
    for (int k : {2, 3, 8, 20, 50})
      for (double noise : {0.0, 0.1, 0.3, 0.6})
        for (int i = 0; i < 12; ++i) {
          const LabelImage img = random_partition(rng, dim, dim == 2 ? 16 : 9, k, noise);
          PartitionOptions opt;
          opt.priority = priority;
          const PartitionResult r = make_well_composed_partition(img, opt);
          check_result(img, r);
          // Same input, same output.
          REQUIRE(make_well_composed_partition(img, opt).image.data == r.image.data);
          promotions += r.promotions;
          changed += r.changed;
          configs += r.input.total();
          binary += binary_sum(img);
          ++images;
        }
  REQUIRE(configs > 1000);  // the cases hold configurations to repair
  std::cout << "partition repair on " << images << " random label images: " << changed << " voxels changed, "
            << binary << " by the per-label binary add repairs (sum), ratio "
            << double(changed) / double(std::max<std::size_t>(binary, 1)) << "; " << promotions
            << " labels raised to keep their last voxel\n";
}

TEST_CASE("partition repair of a well-composed partition changes nothing", "[wellcomposed][labels]") {
  std::mt19937_64 rng(99);
  for (int dim : {2, 3})
    for (int i = 0; i < 20; ++i) {
      const LabelImage img = random_partition(rng, dim, 10, 6, 0.2);
      const PartitionResult once = make_well_composed_partition(img);
      LabelImage again_in = once.image;
      const PartitionResult again = make_well_composed_partition(again_in);
      REQUIRE(again.changed == 0);
      REQUIRE(again.image.data == once.image.data);  // no side touched: no growth
    }
}

TEST_CASE("one-voxel labels and labels on every face", "[wellcomposed][labels]") {
  // Two labels in a checkerboard with single voxels of labels of their own:
  // every 2x2 square a C1 for both.
  for (int dim : {2, 3}) {
    LabelImage img = make_image(dim, 6, 5, 4);
    for (std::size_t z = 0; z < img.size[2]; ++z)
      for (std::size_t y = 0; y < img.size[1]; ++y)
        for (std::size_t x = 0; x < img.size[0]; ++x) img(x, y, z) = (x + y + z) % 2 ? 7 : 3;
    img(2, 2, 0) = 40;
    img(3, 2, 0) = 41;
    img(0, 0, 0) = 42;
    const PartitionResult r = make_well_composed_partition(img);
    check_result(img, r);
    for (int a = 0; a < (dim == 2 ? 2 : 3); ++a) REQUIRE((r.padded_before[a] == 1 && r.padded_after[a] == 1));
  }
}

TEST_CASE("min_voxels lets small labels go; none is lost without it", "[wellcomposed][labels]") {
  std::mt19937_64 rng(5);
  std::size_t lost = 0;
  for (int i = 0; i < 60; ++i) {
    const LabelImage img = random_partition(rng, 3, 8, 30, 0.6);
    PartitionOptions opt;
    opt.min_voxels = 1000;  // none is kept
    const PartitionResult r = make_well_composed_partition(img, opt);
    REQUIRE(r.output.total() == 0);
    REQUIRE(r.lost_protected.empty());
    REQUIRE(r.failed_guarantee().empty());
    lost += r.lost.size();
    for (std::int32_t l : r.lost) REQUIRE(values_of(r.image).count(l) == 0);
  }
  std::cout << "min_voxels 1000: " << lost << " labels lost over 60 noisy images\n";
}

TEST_CASE("a configuration is resolved by a relabelling that creates none where one exists", "[wellcomposed][labels]") {
  // 2D, label 1 everywhere but nine voxels (rows y = 0..6; digits are labels).
  // The first critical square in scan order, S at (2,2): a C1 of 1 (1 at
  // (2,2) and (3,3), 2 at (3,2), 3 at (2,3)). Labels 2 and 3 have fewer
  // voxels, so they rank above 1: the up moves give (2,2) or (3,3) label 2
  // or 3, and each creates a configuration (a C1 of 1 with the 6 at (1,1);
  // of 2 with the 2 at (2,4); of 3 with the 3 at (4,2)), those of (3,3)
  // while also removing the C1 of 1 in the square at (3,3) (4 and 5 on its
  // other diagonal). The down moves (3,2) or (2,3) -> 1 remove S alone and
  // create nothing: the one to take (the thesis's rule (1)), though it
  // removes fewer.
  const char* rows[] = {"1111111", "1611111", "1112311", "1131411", "1125111", "1111111", "1111111"};
  LabelImage img = make_image(2, 7, 7, 1);
  for (std::size_t y = 0; y < 7; ++y)
    for (std::size_t x = 0; x < 7; ++x) img(x, y, 0) = rows[y][x] - '0';
  PartitionOptions one;
  one.max_steps = 1;
  one.prune = false;
  const PartitionResult r = make_well_composed_partition(img, one);
  REQUIRE(r.input.total() == 2);
  REQUIRE(r.steps == 1);
  REQUIRE(r.changed == 1);
  // The relabelling created no configuration: no label has more than before.
  for (std::size_t i = 0; i < r.input.counts.size(); ++i) REQUIRE(r.output.counts[i].total() <= r.input.counts[i].total());
  REQUIRE(r.output.total() == 1);
  check_result(img, make_well_composed_partition(img));
}

TEST_CASE("a small label is not thinned at its own configuration, even where that would create none", "[wellcomposed][labels]") {
  // 2D, label 1 everywhere but four voxels of label 2 (the fewest voxels:
  // the higher priority): a diagonal pair at (2,2), (3,3), a C1 of 1 and of
  // 2. Taking a voxel of the pair (2 -> 1) creates nothing; the up moves
  // ((3,2) or (2,3) -> 2) each create a C1 of 2 with the 2 at (4,1) or
  // (1,4). The pair must still grow: every voxel of 2 stays 2.
  const char* rows[] = {"111111", "111121", "112111", "111211", "121111", "111111"};
  LabelImage img = make_image(2, 6, 6, 1);
  for (std::size_t y = 0; y < 6; ++y)
    for (std::size_t x = 0; x < 6; ++x) img(x, y, 0) = rows[y][x] - '0';
  const PartitionResult r = make_well_composed_partition(img);
  check_result(img, r);
  for (std::size_t y = 0; y < 6; ++y)
    for (std::size_t x = 0; x < 6; ++x)
      if (img(x, y, 0) == 2) REQUIRE(r.image(x + r.padded_before[0], y + r.padded_before[1], 0) == 2);
}

TEST_CASE("a partition with one configuration left is refused", "[wellcomposed][labels]") {
  // Labels 1 and 2 well apart, plus one C1 of label 5 (two voxels sharing an
  // edge only, in a square whose other two are 1 and 2).
  LabelImage img = make_image(3, 6, 6, 6);
  for (std::size_t z = 1; z < 5; ++z)
    for (std::size_t y = 1; y < 5; ++y)
      for (std::size_t x = 1; x < 5; ++x) img(x, y, z) = x < 3 ? 1 : 2;
  img(2, 2, 2) = 5;
  img(3, 3, 2) = 5;
  const LabelCriticalCounts c = count_label_critical_configurations(img);
  REQUIRE(c.total() == 1);
  REQUIRE(c.labels_with_configurations() == 1);
  REQUIRE(c.counts[std::size_t(std::find(c.labels.begin(), c.labels.end(), 5) - c.labels.begin())].c1 == 1);
  PartitionOptions skip;
  skip.repair = false;
  const PartitionResult r = make_well_composed_partition(img, skip);
  REQUIRE(r.output.total() == 1);
  REQUIRE(r.failed_guarantee().find("NOT a well-composed partition") != std::string::npos);
  check_result(img, make_well_composed_partition(img));
}

TEST_CASE("more than 255 labels: two bytes a voxel, same guarantees", "[wellcomposed][labels]") {
  std::mt19937_64 rng(256);
  LabelImage img = make_image(3, 12, 12, 12);
  for (auto& v : img.data) v = std::int32_t(rng() % 400);
  const PartitionResult r = make_well_composed_partition(img);
  REQUIRE(r.input.labels.size() > 256);
  check_result(img, r);
}

namespace {
// K(X)'s configurations no smooth partition has: voxel edges with four
// labels around them (edges of curves of four labels) and pinched patches.
std::size_t generic_left(const LabelImage& x) {
  const InterfaceComplex k = interface_complex(x);
  std::size_t n = k.pinched_vertices();
  for (const auto& c : k.curves) n += c.label_count == 4 ? c.edges : 0;
  return n;
}
} // namespace

TEST_CASE("the repair leaves no edge of four labels and no pinched patch", "[wellcomposed][labels]") {
  // Four labels around an edge along z, and the pinch of interface_complex.hpp
  // (block 0 0 0 1 2 0 3 3: patch {3, 0} two fans at its centre).
  LabelImage four = make_image(3, 6, 6, 6);
  for (std::size_t z = 1; z < 5; ++z)
    for (std::size_t y = 1; y < 5; ++y)
      for (std::size_t x = 1; x < 5; ++x) four(x, y, z) = 1 + std::int32_t(x >= 3) + 2 * std::int32_t(y >= 3);
  LabelImage pinch = make_image(3, 6, 6, 6);
  const std::int32_t block[8] = {0, 0, 0, 1, 2, 0, 3, 3};
  for (int b = 0; b < 8; ++b)
    for (std::size_t z = 0; z < 2; ++z)  // each voxel of the block a 2x2x2 cube: the same K(X) up to scale
      for (std::size_t y = 0; y < 2; ++y)
        for (std::size_t x = 0; x < 2; ++x) pinch(1 + 2 * (b & 1) + x, 1 + 2 * (b >> 1 & 1) + y, 1 + 2 * (b >> 2 & 1) + z) = block[b];
  for (const LabelImage* x : {&four, &pinch}) {
    REQUIRE(generic_left(*x) > 0);
    REQUIRE(count_label_critical_configurations(*x).total() == 0);
    const PartitionResult r = make_well_composed_partition(*x);
    check_result(*x, r);
    REQUIRE(r.changed > 0);
    REQUIRE(generic_left(r.image) == 0);
    PartitionOptions plain;
    plain.generic = false;
    REQUIRE(make_well_composed_partition(*x, plain).changed == 0);
  }
  // Random maps: nearly all of them gone (a move that takes a label's last
  // voxel is not made, nor one whose drain does: some may stay; without
  // the lenient retries, which let a move create a C1 or C2 and drain it,
  // 16 of these maps' 996 stay).
  std::mt19937_64 rng(4040);
  std::size_t before = 0, after = 0;
  for (int k : {3, 8, 20})
    for (double noise : {0.0, 0.1, 0.3})
      for (int i = 0; i < 6; ++i) {
        const LabelImage img = random_partition(rng, 3, 12, k, noise);
        PartitionOptions plain;
        plain.generic = false;
        before += generic_left(make_well_composed_partition(img, plain).image);
        const PartitionResult r = make_well_composed_partition(img);
        check_result(img, r);
        after += generic_left(r.image);
      }
  std::cout << "generic configurations: " << before << " after the plain repair, " << after << " after the generic one\n";
  REQUIRE(before > 100);
  REQUIRE(after * 100 <= before);
}
