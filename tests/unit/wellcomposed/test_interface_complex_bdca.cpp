// K(X)'s bdCA(L) against the binary code path (lib/mesh: voxel_boundary,
// mesh_topology; well_composed.hpp: count_critical_configurations) on each
// label's indicator.
#include "wellcomposed/interface_complex.hpp"

#include "label_images.hpp"
#include "mesh/topology.hpp"

#include <catch2/catch.hpp>

#include <algorithm>
#include <vector>

using namespace imgmesh;
using namespace imgmesh::test;

namespace {

// Every label: the same critical configurations as its indicator; when the
// partition is well-composed, the same components (faces and Euler
// characteristics) as bdCA of the indicator.
void check_binary_path(const LabelImage& img, const InterfaceComplex& k) {
  std::size_t total = 0;
  for (std::int32_t l : labels_of(img)) {
    const BinaryImage b = indicator(img, l);
    const InterfaceComplex::LabelBoundary* lb = k.find_label(l);
    const CriticalCounts c = count_critical_configurations(b);
    total += c.total();
    if (!lb) {  // no face: the whole grid one label, or empty
      CHECK(c.total() == 0);
      continue;
    }
    INFO("label " << l);
    CHECK(lb->critical.c1 == c.c1);
    CHECK(lb->critical.c2 == c.c2);
    if (c.total() || std::none_of(b.data.begin(), b.data.end(), [](std::uint8_t v) { return v; })) continue;
    const MeshTopology t = voxel_boundary_topology(b);
    std::vector<std::pair<std::size_t, long long>> expect, got;
    for (const auto& m : t.components) expect.emplace_back(img.dimension == 2 ? m.edges : m.faces, m.euler);
    for (const auto& m : lb->components) got.emplace_back(m.faces, m.euler);
    std::sort(expect.begin(), expect.end());
    std::sort(got.begin(), got.end());
    CHECK(got == expect);
  }
  CHECK(k.critical.total() == total);
}

} // namespace

TEST_CASE("interface complex: bdCA of every label as the binary code path counts it", "[interface_complex]") {
  std::mt19937_64 rng(36);
  for (int dim : {3, 2})
    for (int i = 0; i < 40; ++i) {
      const LabelImage img = random_well_composed(rng, dim, 1 + i % 7);
      const InterfaceComplex k = interface_complex(img);
      INFO("dimension " << dim << " case " << i << ": " << k.summary());
      REQUIRE(k.failed_guarantee().empty());
      check_binary_path(img, k);
    }
}

TEST_CASE("interface complex: critical configurations of random partitions as the binary counter's",
          "[interface_complex]") {
  std::mt19937_64 rng(3636);
  for (int dim : {3, 2})
    for (int i = 0; i < 40; ++i) {
      const LabelImage img = random_balls(rng, dim, 1 + i % 7);
      check_binary_path(img, interface_complex(img));
    }
}

TEST_CASE("interface complex: every 2x2x2 partition", "[interface_complex]") {
  // All set partitions of the eight voxels of a 2x2x2 grid (restricted growth
  // strings, 4140), labels 0.. in order: where every label is well-composed,
  // each label's bdCA is the binary path's; everywhere, the critical
  // configurations are the binary counter's and a patch pinches only at a
  // junction.
  std::size_t partitions = 0, well_composed = 0, pinched = 0;
  for_each_block_partition([&](const LabelImage& img) {
    const InterfaceComplex k = interface_complex(img);
    ++partitions;
    INFO("partition " << partitions);
    check_binary_path(img, k);
    if (k.critical.total()) return;
    ++well_composed;
    pinched += !k.pinches.empty();
    for (auto c : k.pinches) CHECK(std::binary_search(k.junctions.begin(), k.junctions.end(), c));
  });
  CHECK(partitions == 4140);
  WARN(well_composed << " well-composed partitions, " << pinched << " with a pinched patch");
  CHECK(well_composed > 0);
}
