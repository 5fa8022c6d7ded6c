// The labelling function lambda (conforming/label_function.hpp): the
// voxel's label at every voxel centre, 0 beyond the grid, and its changes
// found where the labels of two neighbouring centres differ.
#include "conforming/label_function.hpp"
#include "label_maps.hpp"
#include "wellcomposed/well_composed_partition.hpp"

#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <random>

using namespace imgmesh;
using namespace imgmesh::test;

namespace {

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

// lambda by its definition from the labels' f at random points (those where
// at most one f is negative: the rank decides the others): where the voxels
// f reads are all one label, label() answers without evaluating f. Maps of
// 5 to 60 labels: the candidates' words of 1, 2, 4 and 8 bytes.
TEST_CASE("lambda at random points is its definition from the labels' f", "[conforming]") {
  std::mt19937_64 rng(11);
  std::size_t checked = 0;
  for (int count : {5, 5, 12, 24, 60}) {
    LabelImage x = make_well_composed_partition(voronoi_map(rng, 12, count)).image;
    x.spacing = {0.8, 1.0, 1.3};
    x.origin = {3, -2, 1};
    const LabelFunction f(x, 0.3 * 0.8);
    std::vector<std::int32_t> labels{0};
    for (std::int32_t v : x.data)
      if (std::find(labels.begin(), labels.end(), v) == labels.end()) labels.push_back(v);
    std::uniform_real_distribution<double> u(0, 1);
    for (int n = 0; n < 4000; ++n) {
      const Vec3 p = x.world(u(rng) * double(x.size[0] - 1), u(rng) * double(x.size[1] - 1), u(rng) * double(x.size[2] - 1));
      std::int32_t best = 0, negative = 0;
      double fbest = INFINITY;
      int negatives = 0;
      for (std::int32_t l : labels) {
        const double v = f.value(l, p);
        if (v < 0) ++negatives, negative = l;
        if (v < fbest || (v == fbest && l < best)) fbest = v, best = l;
      }
      if (negatives > 1) continue;
      REQUIRE(f.label(p) == (negatives == 1 ? negative : best));
      ++checked;
    }
  }
  CHECK(checked > 15000);
}
