// util/parse.hpp accepts exactly what strtod / strtoll do; util/coordinates.hpp
// takes exactly the documented range (the man pages): finite,
// at most 1e30 in magnitude, a mesh 0 or at least 1e-30 across.
#include "util/coordinates.hpp"
#include "util/parse.hpp"

#include <catch2/catch.hpp>

#include <array>
#include <cerrno>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <limits>
#include <random>
#include <string>
#include <vector>

using namespace imgmesh;

namespace {
std::uint64_t bits(double v) {
  std::uint64_t b;
  std::memcpy(&b, &v, sizeof b);
  return b;
}
} // namespace

TEST_CASE("parse_real and parse_integer accept what strtod and strtoll accept") {
  const char* reals[] = {"0", "-0", "+1.5", "1e308", "1e400", "-1e400", "1e-400", "4.9406564584124654e-324",
                         "2.4e-324", ".5", "5.", "-.5e-3", "1e", "1e+", "0x1p3", "0x10", "nan", "-nan",
                         "inf", "infinity", "1x", "x", "-", "+", ".", "1.2.3", "1e5e5", "12345678901234567890123",
                         "0.30000000000000004", "00012", "1E3", "-1E-3"};
  for (const char* s : reals) {
    INFO(s);
    char* e = nullptr;
    const double want = std::strtod(s, &e);
    const bool ok = e != s && *e == '\0';
    double v = -7;
    CHECK(parse_real(s, v) == ok);
    if (ok && !std::isnan(want)) CHECK(bits(v) == bits(want));
    if (ok && std::isnan(want)) CHECK(std::isnan(v));
  }
  const char* integers[] = {"0", "-0", "+3", "-12", "007", "9223372036854775807", "9223372036854775808",
                            "-9223372036854775808", "-9223372036854775809", "99999999999999999999", "1.0",
                            "1e3", "0x10", "", "-", "+", "12a"};
  for (const char* s : integers) {
    INFO(s);
    char* e = nullptr;
    errno = 0;
    const long long want = std::strtoll(s, &e, 10);
    const bool ok = e != s && *e == '\0' && errno != ERANGE;
    long long v = -7;
    CHECK(parse_integer(s, v) == ok);
    if (ok) CHECK(v == want);
  }
}

TEST_CASE("parse_real agrees with strtod on random decimal and bit-pattern doubles") {
  std::mt19937_64 rng(6);
  char buf[64];
  for (int i = 0; i < 200000; ++i) {
    const std::uint64_t b = rng();
    double x;
    std::memcpy(&x, &b, sizeof x);
    if (!std::isfinite(x)) continue;
    // Shortest-ish, %.17g and few-digit forms.
    std::snprintf(buf, sizeof buf, i % 3 == 0 ? "%.17g" : i % 3 == 1 ? "%.6e" : "%.3f", x);
    double v = 0;
    REQUIRE(parse_real(buf, v));
    REQUIRE(bits(v) == bits(std::strtod(buf, nullptr)));
  }
}

TEST_CASE("parse_coordinate takes finite numbers up to 1e30 in magnitude, nothing else") {
  const char* good[] = {"0", "-0", "1e30", "-1e30", "1e-30", "1e-300", "5e-320", "1e-400", "1.5", "+2", "0x1p3",
                        "999999999999999999999999999999", "1.0000000000000000e+30"};
  for (const char* s : good) {
    INFO(s);
    double v = -7;
    CHECK(parse_coordinate(s, v));
    CHECK(bits(v) == bits(std::strtod(s, nullptr)));
  }
  const char* bad[] = {"nan", "-nan", "inf", "-infinity", "1e400", "-1e400", "1.0000000000000002e30", "1e31",
                       "-1e31", "1e308", "", "x", "1e", "0x"};
  for (const char* s : bad) {
    INFO(s);
    double v = 0;
    CHECK_FALSE(parse_coordinate(s, v));
  }
  CHECK(valid_coordinate(-1e30));
  CHECK_FALSE(valid_coordinate(std::nextafter(1e30, 2e30)));
  CHECK(valid_coordinate(std::numeric_limits<double>::denorm_min()));
  CHECK_FALSE(valid_coordinate(std::numeric_limits<double>::quiet_NaN()));
  CHECK_FALSE(valid_coordinate(-std::numeric_limits<double>::infinity()));
  // As floats (binary STL, PLY): the float nearest 1e30 is the end.
  CHECK(valid_coordinate(1e30f));
  CHECK(valid_coordinate(std::numeric_limits<float>::denorm_min()));
  CHECK_FALSE(valid_coordinate(std::nextafter(1e30f, 2e30f)));
  CHECK_FALSE(valid_coordinate(std::numeric_limits<float>::infinity()));
  CHECK(coordinate_error("1e400") == "coordinate '1e400' is out of range (finite, at most 1e30 in magnitude)");
  CHECK(coordinate_error("1x") == "'1x' is not a number");
  CHECK(coordinate_error(1e300) ==
        "coordinate '1.0000000000000001e+300' is out of range (finite, at most 1e30 in magnitude)");
  CHECK(coordinate_error(std::string(100, '9')).size() < 120);  // one short line whatever the field
}

TEST_CASE("check_extent refuses a mesh less than 1e-30 across, not one at a point") {
  using P2 = std::array<double, 2>;
  using P3 = std::array<double, 3>;
  CHECK(extent(std::vector<P3>{{0, 0, 0}, {1, -2, 0.5}}) == 2);
  CHECK(extent(std::vector<P2>{}) == 0);
  CHECK_NOTHROW(check_extent(std::vector<P2>{{1e-31, 1e-31}, {1e-31, 1e-31}}, "a"));  // all equal
  CHECK_NOTHROW(check_extent(std::vector<P2>{{0, 0}, {1e-30, 0}, {5e-320, 1}}, "a"));
  CHECK_NOTHROW(check_extent(std::vector<P3>{{1e30, 0, 0}, {-1e30, 0, 5e-324}}, "a"));
  try {
    check_extent(std::vector<P3>{{0, 0, 0}, {0, 1e-300, 0}, {0, 0, 5e-301}}, "m.off");
    FAIL("a mesh 1e-300 across accepted");
  } catch (const Error& e) {
    CHECK(e.message() == "m.off: the coordinates span only 1e-300: under 1e-30, too small for double arithmetic "
                         "(scale the mesh)");
  }
  CHECK_NOTHROW(check_extent(std::vector<P2>{{1, 1}, {std::nextafter(1.0, 2.0), 1}}, "a"));  // 2.2e-16 across
}
