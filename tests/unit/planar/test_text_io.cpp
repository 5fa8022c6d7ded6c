// Fast number text: TextOutput writes reals byte for byte as
// printf("%.17g"), and extreme doubles (coordinates: up to the ends of
// their range) survive a round trip through Triangle's formats bit for bit.
#include "planar/text_io.hpp"
#include "planar/triangle_io.hpp"
#include "util/error.hpp"

#include <catch2/catch.hpp>

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <limits>
#include <random>
#include <string>
#include <unistd.h>

using namespace imgmesh;
namespace fs = std::filesystem;

namespace {

std::string scratch(const std::string& name) {
  const fs::path dir = fs::current_path() / ("imgmesh_text_io_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  return (dir / name).string();
}

std::string contents(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), {});
}

std::uint64_t bits(double v) {
  std::uint64_t b;
  std::memcpy(&b, &v, sizeof b);
  return b;
}

// Attributes: any finite double.
const double extremes[] = {0.0,
                           -0.0,
                           1e308,
                           -1.7976931348623157e308,
                           std::numeric_limits<double>::max(),
                           std::numeric_limits<double>::min(),        // smallest normal
                           std::numeric_limits<double>::denorm_min(),  // 4.9e-324
                           -2.2250738585072009e-308,                   // largest denormal
                           1e-320,
                           0.1 + 0.2,
                           1.0 / 3.0,
                           123456789.12345678,
                           -9007199254740993.0,
                           std::nextafter(1.0, 2.0),
                           std::ldexp(1.0, -1074) * 3};
// Coordinates: any finite double of magnitude at most 1e30 (util/coordinates.hpp).
const double coordinate_extremes[] = {0.0,
                                      -0.0,
                                      1e30,
                                      -1e30,
                                      std::nextafter(1e30, 0.0),
                                      std::numeric_limits<double>::min(),
                                      std::numeric_limits<double>::denorm_min(),
                                      -2.2250738585072009e-308,
                                      1e-320,
                                      0.1 + 0.2,
                                      1.0 / 3.0,
                                      123456789.12345678,
                                      -9007199254740993.0,
                                      std::nextafter(1.0, 2.0)};

} // namespace

TEST_CASE("TextOutput writes reals as %.17g, byte for byte, across chunk boundaries") {
  std::mt19937_64 rng(7);
  const std::string path = scratch("reals.txt");
  std::string want;
  {
    TextOutput o(path);
    char buf[64];
    // ~3 MB: several 1 MiB chunks.
    for (int i = 0; i < 150000; ++i) {
      const std::uint64_t b = rng();
      double x;
      std::memcpy(&x, &b, sizeof x);
      if (!std::isfinite(x)) x = i;
      if (i % 2) x = std::ldexp(double(b >> 11), int(b % 80) - 90);  // values near the integers too
      std::snprintf(buf, sizeof buf, "%.17g", x);
      want += buf;
      want += ' ';
      want += std::to_string(i - 75000);
      want += '\n';
      o << x << ' ' << i - 75000 << '\n';
    }
    for (double x : extremes) {
      std::snprintf(buf, sizeof buf, "%.17g", x);
      want += buf;
      o << x;
    }
    const std::string big(3 << 20, 'z');  // a string longer than a chunk
    want += big;
    o << big << "end\n";
    want += "end\n";
    o.commit();
  }
  CHECK(contents(path) == want);
  fs::remove_all(fs::path(path).parent_path());
}

TEST_CASE("extreme doubles round trip through .node/.poly/.ele bit for bit") {
  PlanarMesh m;
  for (double x : coordinate_extremes)
    for (double y : {-0.0, 1e30, std::numeric_limits<double>::denorm_min()}) m.points.push_back({x, y});
  for (std::size_t i = 0; i < m.points.size(); ++i) m.point_attributes.push_back({extremes[i % std::size(extremes)]});
  m.point_markers.assign(m.points.size(), -3);
  m.elements = {{0, 1, 2, 3}, {4, 5, 6, 7}};
  m.element_attributes = {{-0.0}, {1e-320}};
  m.segments = {{0, 1}};
  m.holes = {{-0.0, 1e-310}};
  m.regions = {{{1e30, -1e-308}, -0.0, 1.0 / 3.0}};
  const std::string ele = scratch("x.ele"), poly = scratch("x.poly");
  write_node(scratch("x.node"), m);
  write_ele(ele, m);
  write_poly(poly, m);
  const PlanarMesh r = read_ele(ele), p = read_poly(poly);
  for (const PlanarMesh* q : {&r, &p}) {
    REQUIRE(q->points.size() == m.points.size());
    for (std::size_t i = 0; i < m.points.size(); ++i) {
      CHECK(bits(q->points[i][0]) == bits(m.points[i][0]));
      CHECK(bits(q->points[i][1]) == bits(m.points[i][1]));
      CHECK(bits(q->point_attributes[i][0]) == bits(m.point_attributes[i][0]));
    }
    CHECK(q->point_markers == m.point_markers);
  }
  CHECK(r.elements == m.elements);
  CHECK(bits(r.element_attributes[0][0]) == bits(-0.0));
  CHECK(bits(r.element_attributes[1][0]) == bits(1e-320));
  CHECK(bits(p.holes[0][0]) == bits(-0.0));
  CHECK(bits(p.holes[0][1]) == bits(1e-310));
  REQUIRE(p.regions.size() == 1);
  CHECK(bits(p.regions[0].point[0]) == bits(1e30));
  CHECK(bits(p.regions[0].point[1]) == bits(-1e-308));
  CHECK(bits(p.regions[0].attribute) == bits(-0.0));
  CHECK(bits(p.regions[0].max_area) == bits(1.0 / 3.0));
  fs::remove_all(fs::path(ele).parent_path());
}

TEST_CASE("Triangle readers: strtod's forms and comments right after data") {
  const std::string node = scratch("y.node");
  std::ofstream(node) << "3 2 0 0#header\n"
                         "  \t \n"
                         "0 +1.5 0x1p3\n"
                         "1 1e-400 .5# no space before the comment\n"
                         "#\n"
                         "2 5. -0\r\n";
  const PlanarMesh m = read_node(node);
  REQUIRE(m.points.size() == 3);
  CHECK(m.points[0] == Point2{1.5, 8});
  CHECK(m.points[1] == Point2{0, 0.5});
  CHECK(m.points[2] == Point2{5, 0});
  CHECK(std::signbit(m.points[2][1]));
  for (const char* bad : {"1e400", "-1e31", "1.0000000000000002e30", "nan", "-inf"}) {
    std::ofstream(node) << "3 2 0 0\n0 0 0\n1 " << bad << " 0\n2 0 1\n";
    try {
      read_node(node);
      FAIL(std::string(bad) + " accepted");
    } catch (const Error& e) {
      CHECK(e.message().find(std::string("line 3: coordinate '") + bad +
                             "' is out of range (finite, at most 1e30 in magnitude)") != std::string::npos);
    }
  }
  // A mesh 1e-31 across is too small for double arithmetic; one all at a
  // point is a degenerate mesh, the tools' to refuse.
  std::ofstream(node) << "3 2 0 0\n0 0 0\n1 1e-31 0\n2 0 5e-32\n";
  try {
    read_node(node);
    FAIL("a mesh 1e-31 across accepted");
  } catch (const Error& e) {
    CHECK(e.message().find("the coordinates span only 1e-31: under 1e-30") != std::string::npos);
  }
  std::ofstream(node) << "3 2 0 0\n0 1e-31 0\n1 1e-31 0\n2 1e-31 0\n";
  CHECK(read_node(node).points.size() == 3);
  std::ofstream(node) << "3 2 0 0\n0 0 0\n1 1e-30 0\n2 0 1e-300\n";
  CHECK(read_node(node).points[1][0] == 1e-30);
  std::ofstream(node) << "3 2 1 0\n0 0 0 1e-320\n1 1 0 1e308\n2 0 1 -0\n";  // attributes: any finite number
  CHECK(read_node(node).point_attributes[1][0] == 1e308);
  std::ofstream(node) << "3 2 1 0\n0 0 0 0\n1 1 0 1e400\n2 0 1 0\n";
  try {
    read_node(node);
    FAIL("an attribute 1e400 accepted");
  } catch (const Error& e) {
    CHECK(e.message().find("line 3: '1e400' is not a finite number") != std::string::npos);
  }
  std::ofstream(node) << "3 2 0 0\n0 0 0\n1 1 0\n+2 0 1e\n";
  try {
    read_node(node);
    FAIL("1e accepted");
  } catch (const Error& e) {
    CHECK(e.message().find("line 4: '1e' is not a number") != std::string::npos);
  }
  std::ofstream(node) << "99999999999999999999 2 0 0\n";
  try {
    read_node(node);
    FAIL("a count out of range accepted");
  } catch (const Error& e) {
    CHECK(e.message().find("line 1: '99999999999999999999' is not an integer") != std::string::npos);
  }
  fs::remove_all(fs::path(node).parent_path());
}
