// The mesher's bounds as the tools give them (mesher_options.hpp): angles in
// their units, the distance's default from the voxel spacing, and the one
// check's messages, which name the option and quote it as written.
#include "surface/mesher_options.hpp"
#include "util/error.hpp"

#include <catch2/catch.hpp>

#include <cmath>
#include <string>

using namespace imgmesh;

namespace {

// The UsageError resolve() throws, or "" if none.
std::string refusal(const MesherBounds& b) {
  try {
    b.resolve({1, 1, 1});
  } catch (const UsageError& e) {
    return e.what();
  }
  return "";
}

} // namespace

TEST_CASE("parse_angle: degrees, radians and multiples of pi") {
  CHECK(parse_angle("90") == Approx(M_PI / 2));
  CHECK(parse_angle(" 90 deg") == Approx(M_PI / 2));
  CHECK(parse_angle("1.5rad") == Approx(1.5));
  CHECK(parse_angle("pi/3") == Approx(M_PI / 3));
  CHECK(parse_angle("2pi/3") == Approx(2 * M_PI / 3));
  CHECK(parse_angle("2*pi") == Approx(2 * M_PI));
  CHECK(parse_angle("0.5pi") == Approx(M_PI / 2));
  for (const char* bad : {"", "abc", "rad", "90x", "pi3", "pi/", "inf", "nan", "1e999"})
    CHECK(std::isnan(parse_angle(bad)));
}

TEST_CASE("MesherBounds::resolve: units, the distance's default, the other fields") {
  MesherBounds b;
  RestrictedDelaunayOptions o = b.resolve({0.5, 2, 0.8});
  CHECK(o.ratio == 1.2);
  CHECK(o.roughness == Approx(2 * M_PI / 3));
  CHECK(o.max_distance == Approx(0.2));  // 0.4 of the smallest spacing, with VoxelSides
  CHECK(b.resolve({0.5, 2, 0.8}, MesherBounds::Mesher::kConforming).max_distance == Approx(0.15));  // 0.3
  b.voxel_sides = false;
  CHECK(b.resolve({0.5, 2, 0.8}).max_distance == Approx(0.15));  // 0.3 without it
  CHECK(!b.resolve({0.5, 2, 0.8}).voxel_sides);
  CHECK(o.max_points == RestrictedDelaunayOptions().max_points);
  CHECK(o.seed == 0);
  b.roughness = "pi/3";
  b.max_distance = "0.25";
  b.max_points = 100;
  b.fallback_rounds = 2;
  o = b.resolve({0.5, 2, 0.8});
  CHECK(o.roughness == Approx(M_PI / 3));
  CHECK(o.max_distance == 0.25);
  CHECK(o.max_points == 100);
  CHECK(o.fallback_rounds == 2);
}

TEST_CASE("MesherBounds::check: each option named, in the tools' words") {
  MesherBounds b;
  CHECK(refusal(b).empty());
  b.ratio = 1;
  CHECK(refusal(b) == "--ratio 1.000000 is below the termination limit (1+k)^2 = 1.1236");
  b = MesherBounds();
  b.roughness = "abc";
  CHECK(refusal(b) == "--roughness abc: not an angle (degrees, or radians as pi/3 or 1.05rad)");
  b.roughness = "10";
  CHECK(refusal(b) == "--roughness 10 is below the termination limit 2(arcsin k + arcsin(2k/sqrt 3)) = 14.8 "
                      "degrees (0.2587 rad; a number without unit is in degrees)");
  b = MesherBounds();
  for (const char* bad : {"-1", "", "1x", "inf", "nan"}) {
    b.max_distance = bad;
    CHECK(refusal(b) == "--max-distance must be a finite number >= 0");
  }
  b = MesherBounds();
  b.max_points = 3;
  CHECK(refusal(b) == "--max-points must be at least 4");
  // The first bad option is the one named.
  b.ratio = 1;
  b.roughness = "abc";
  CHECK(refusal(b).rfind("--ratio", 0) == 0);
  CHECK_THROWS_AS(b.check(), UsageError);
}

TEST_CASE("check_options: the library's guard quotes g in radians") {
  RestrictedDelaunayOptions o;
  CHECK_NOTHROW(check_options(o));
  o.roughness = 0.25;
  CHECK_THROWS_WITH(check_options(o), Catch::Contains("--roughness 0.250000rad is below the termination limit"));
}
