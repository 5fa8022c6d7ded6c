// Hand-built blocks: the (C1)/(C2) flags and every case of B(r) in 5.2.4.
#include "wellcomposed/critical_configuration.hpp"

#include <catch2/catch.hpp>

#include <set>

using namespace imgmesh::wellcomposed_detail;

namespace {
// Block bit of the point r + (dx, dy, dz).
unsigned at(int dx, int dy, int dz) { return 1u << (dx + 2 * dy + 4 * dz); }

std::set<unsigned> sets_of(std::uint8_t code) {
  const CandidateSets& b = candidate_sets(code);
  return std::set<unsigned>(b.sets.begin(), b.sets.begin() + b.count);
}
} // namespace

TEST_CASE("critical configurations of single blocks", "[wellcomposed]") {
  CHECK(critical_configurations(0) == 0);
  CHECK(critical_configurations(0xff) == 0);
  // One voxel, a full face, a straight pair: never critical.
  CHECK(critical_configurations(std::uint8_t(at(0, 0, 0))) == 0);
  CHECK(critical_configurations(std::uint8_t(at(0, 0, 0) | at(1, 0, 0) | at(0, 1, 0) | at(1, 1, 0))) == 0);
  CHECK(critical_configurations(std::uint8_t(at(0, 0, 0) | at(1, 0, 0))) == 0);
  // The x-diagonal pair on the face x = 0 is (C1) in N_x(r).
  CHECK(critical_configurations(std::uint8_t(at(0, 0, 0) | at(0, 1, 1))) == kC1x);
  CHECK(critical_configurations(std::uint8_t(at(0, 1, 0) | at(0, 0, 1))) == kC1x);
  CHECK(critical_configurations(std::uint8_t(at(0, 0, 0) | at(1, 0, 1))) == kC1y);
  CHECK(critical_configurations(std::uint8_t(at(1, 0, 0) | at(0, 1, 0))) == kC1z);
  // A diagonal on the far face x = 1 belongs to N_x(r + e_x), not to r.
  CHECK(critical_configurations(std::uint8_t(at(1, 0, 0) | at(1, 1, 1))) == 0);
  // (C2): two corner-adjacent voxels of one colour, six of the other.
  CHECK(critical_configurations(std::uint8_t(at(0, 0, 0) | at(1, 1, 1))) == kC2);
  CHECK(critical_configurations(std::uint8_t(at(1, 0, 0) | at(0, 1, 1))) == kC2);
  CHECK(critical_configurations(std::uint8_t(0xff & ~(at(0, 1, 0) | at(1, 0, 1)))) == kC2);
  // Three voxels are not (C2) even with a corner-adjacent pair.
  CHECK((critical_configurations(std::uint8_t(at(0, 0, 0) | at(1, 1, 1) | at(1, 0, 0))) & kC2) == 0);
  // The complement of a configuration is the same configuration.
  for (unsigned code = 0; code < 256; ++code)
    CHECK(critical_configurations(std::uint8_t(code)) == critical_configurations(std::uint8_t(~code)));
}

TEST_CASE("(C1) and (C2) exclude each other in one block", "[wellcomposed]") {
  int c2 = 0, c1 = 0;
  for (unsigned code = 0; code < 256; ++code) {
    const std::uint8_t f = critical_configurations(std::uint8_t(code));
    if (f & kC2) {
      ++c2;
      CHECK((f & (kC1x | kC1y | kC1z)) == 0);
    } else if (f) {
      ++c1;
    }
  }
  CHECK(c2 == 8);  // 4 corner pairs, either colour
  // Section 5.4: 84 colourings of N(r) hold at least one critical configuration.
  CHECK(c1 + c2 == 84);
}

TEST_CASE("B(r): exactly one (C1)", "[wellcomposed]") {
  // N_z(r) = x-diagonal (0,0,0),(1,1,0) foreground; background a, b = (1,0,0), (0,1,0).
  const auto code = std::uint8_t(at(0, 0, 0) | at(1, 1, 0));
  REQUIRE(critical_configurations(code) == kC1z);
  CHECK(sets_of(code) == std::set<unsigned>{at(1, 0, 0), at(0, 1, 0)});
}

TEST_CASE("B(r): two (C1) sharing a background point", "[wellcomposed]") {
  // N_x and N_y both (C1): foreground (0,0,1), (0,1,0), (1,0,0); r background.
  // N_x: fg (0,1,0),(0,0,1), bg (0,0,0),(0,1,1). N_y: fg (1,0,0),(0,0,1), bg (0,0,0),(1,0,1).
  // N_z: fg (1,0,0),(0,1,0), bg (0,0,0),(1,1,0) -> also (C1); make (1,1,0) foreground.
  const auto code = std::uint8_t(at(0, 0, 1) | at(0, 1, 0) | at(1, 0, 0) | at(1, 1, 0));
  REQUIRE(critical_configurations(code) == (kC1x | kC1y));
  CHECK(sets_of(code) == std::set<unsigned>{at(0, 0, 0), at(0, 1, 1) | at(1, 0, 1)});
}

TEST_CASE("B(r): three (C1), common point background", "[wellcomposed]") {
  const auto code = std::uint8_t(at(1, 0, 0) | at(0, 1, 0) | at(0, 0, 1));
  REQUIRE(critical_configurations(code) == (kC1x | kC1y | kC1z));
  CHECK(sets_of(code) == std::set<unsigned>{at(0, 0, 0), at(1, 1, 0) | at(1, 0, 1) | at(0, 1, 1)});
}

TEST_CASE("B(r): three (C1), common point foreground", "[wellcomposed]") {
  const auto code = std::uint8_t(at(0, 0, 0) | at(1, 1, 0) | at(1, 0, 1) | at(0, 1, 1));
  REQUIRE(critical_configurations(code) == (kC1x | kC1y | kC1z));
  const unsigned b = at(1, 0, 0), c = at(0, 1, 0), d = at(0, 0, 1);
  CHECK(sets_of(code) == std::set<unsigned>{b | c, b | d, c | d});
}

TEST_CASE("B(r): (C2) with two and with six background points", "[wellcomposed]") {
  const auto six_bg = std::uint8_t(at(0, 0, 0) | at(1, 1, 1));
  REQUIRE(critical_configurations(six_bg) == kC2);
  CHECK(candidate_sets(six_bg).count == 6);
  const auto two_bg = std::uint8_t(~six_bg);
  REQUIRE(critical_configurations(two_bg) == kC2);
  CHECK(sets_of(two_bg) == std::set<unsigned>{at(0, 0, 0), at(1, 1, 1)});
}

TEST_CASE("every set of B(r) eliminates the block's configurations and is background", "[wellcomposed]") {
  for (unsigned code = 0; code < 256; ++code) {
    const std::uint8_t f = critical_configurations(std::uint8_t(code));
    const CandidateSets& b = candidate_sets(std::uint8_t(code));
    if (!f) {
      CHECK(b.count == 0);
      continue;
    }
    REQUIRE(b.count >= 2);
    for (int i = 0; i < b.count; ++i) {
      CHECK(b.sets[i] != 0);
      CHECK((b.sets[i] & code) == 0);  // only background points change
      CHECK((critical_configurations(std::uint8_t(code | b.sets[i])) & f) == 0);
    }
  }
}
