// Triangle's formats: the rules of Triangle's own readers, round trips, and
// strict errors naming the file and line.
#include "planar/planar_formats.hpp"
#include "planar/triangle_io.hpp"
#include "util/error.hpp"

#include <catch2/catch.hpp>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>
#include <unistd.h>

using namespace imgmesh;
namespace fs = std::filesystem;

namespace {

struct Scratch {
  fs::path dir;
  Scratch() {
    dir = fs::current_path() / ("imgmesh_planar_" + std::to_string(::getpid()));
    fs::create_directories(dir);
  }
  ~Scratch() { fs::remove_all(dir); }
  std::string file(const std::string& name, const std::string& text) const {
    const std::string p = (dir / name).string();
    std::ofstream(p) << text;
    return p;
  }
  std::string path(const std::string& name) const { return (dir / name).string(); }
};

std::string error_of(const std::function<void()>& f) {
  try {
    f();
  } catch (const Error& e) {
    return e.message();
  }
  return "";
}

} // namespace

TEST_CASE("node: comments, first index 1, attributes and markers") {
  Scratch s;
  const auto p = s.file("a.node",
                        "# a square\n"
                        "4 2 1 1   # header\n"
                        "\n"
                        "1 0 0 7.5 1\n"
                        "2 1.0 0 7.5 1\n"
                        "3 1 1e0 8 0  # comment after data\n"
                        "4 0 1 8 2\n");
  const PlanarMesh m = read_node(p);
  REQUIRE(m.points.size() == 4);
  CHECK(m.first_index == 1);
  CHECK(m.points[1] == Point2{1, 0});
  CHECK(m.points[2] == Point2{1, 1});
  REQUIRE(m.point_attributes.size() == 4);
  CHECK(m.point_attributes[2][0] == 8);
  CHECK(m.point_markers == std::vector<int>{1, 1, 0, 2});
}

TEST_CASE("poly: inline vertices, segments, holes, regions") {
  Scratch s;
  const auto p = s.file("b.poly",
                        "4 2 0 0\n0 0 0\n1 4 0\n2 4 4\n3 0 4\n"
                        "4 1\n0 0 1 5\n1 1 2 5\n2 2 3 6\n3 3 0 6\n"
                        "1\n0 2 2\n"
                        "2\n0 1 1 3 0.5\n1 3 3 4\n");
  const PlanarMesh m = read_poly(p);
  CHECK(m.first_index == 0);
  REQUIRE(m.segments.size() == 4);
  CHECK(m.segments[3] == std::array<int, 2>{3, 0});
  CHECK(m.segment_markers == std::vector<int>{5, 5, 6, 6});
  REQUIRE(m.holes.size() == 1);
  CHECK(m.holes[0] == Point2{2, 2});
  REQUIRE(m.regions.size() == 2);
  CHECK(m.regions[0].attribute == 3);
  CHECK(m.regions[0].max_area == 0.5);
  // One value only: Triangle uses it as both attribute and area bound.
  CHECK(m.regions[1].attribute == 4);
  CHECK(m.regions[1].max_area == 4);
}

TEST_CASE("poly with 0 vertices reads the .node beside it; ids from 1") {
  Scratch s;
  s.file("c.node", "3 2 0 0\n1 0 0\n2 1 0\n3 0 1\n");
  const auto p = s.file("c.poly", "0 2 0 0\n3 0\n1 1 2\n2 2 3\n3 3 1\n0\n");
  const PlanarMesh m = read_poly(p);
  REQUIRE(m.points.size() == 3);
  CHECK(m.first_index == 1);
  CHECK(m.segments[0] == std::array<int, 2>{0, 1});
  CHECK(m.segments[2] == std::array<int, 2>{2, 0});
  CHECK(m.holes.empty());
  CHECK(m.regions.empty());
}

TEST_CASE("ele: 3- and 4-node elements with attributes, and a round trip") {
  Scratch s;
  s.file("d.node", "5 2 0 1\n0 0 0 1\n1 2 0 1\n2 2 2 1\n3 0 2 1\n4 1 1 0\n");
  const auto p = s.file("d.ele", "4 3 1\n0 0 1 4 1\n1 1 2 4 1\n2 2 3 4 2\n3 3 0 4 2\n");
  PlanarMesh m = read_ele(p);
  REQUIRE(m.elements.size() == 4);
  CHECK(m.elements[2] == std::vector<int>{2, 3, 4});
  CHECK(m.element_attributes[3][0] == 2);

  // Round trip through the writers, with 1-based ids and awkward reals.
  m.first_index = 1;
  m.points[4] = {1.0 / 3.0, 0.1 + 0.2};
  m.segments = {{0, 1}, {1, 2}};
  m.segment_markers = {3, 4};
  write_planar_mesh(s.path("e.ele"), m);
  const PlanarMesh r = read_planar_mesh(s.path("e.ele"));
  CHECK(r.first_index == 1);
  CHECK(r.points == m.points);  // %.17g keeps every bit
  CHECK(r.elements == m.elements);
  CHECK(r.element_attributes == m.element_attributes);
  CHECK(r.point_markers == m.point_markers);
  CHECK(r.segments == m.segments);
  CHECK(r.segment_markers == m.segment_markers);

  const auto q = s.file("f.ele", "# quads\n1 4 0\n0 0 1 2 3\n");
  s.file("f.node", "4 2 0 0\n0 0 0\n1 1 0\n2 1 1\n3 0 1\n");
  CHECK(read_ele(q).elements[0] == std::vector<int>{0, 1, 2, 3});
}

TEST_CASE("poly round trip keeps regions and holes") {
  Scratch s;
  PlanarMesh m;
  m.points = {{0, 0}, {3, 0}, {3, 3}, {0, 3}};
  m.segments = {{0, 1}, {1, 2}, {2, 3}, {3, 0}};
  m.segment_markers = {1, 1, 2, 2};
  m.holes = {{1.5, 1.5}};
  m.regions = {{{0.5, 0.5}, 7, -1}};
  write_poly(s.path("g.poly"), m);
  const PlanarMesh r = read_poly(s.path("g.poly"));
  CHECK(r.points == m.points);
  CHECK(r.segments == m.segments);
  CHECK(r.segment_markers == m.segment_markers);
  CHECK(r.holes == m.holes);
  REQUIRE(r.regions.size() == 1);
  CHECK(r.regions[0].attribute == 7);
  CHECK(r.regions[0].max_area == -1);
}

TEST_CASE("strict errors name the file and the line") {
  Scratch s;
  const auto dangling = s.file("h.poly", "3 2 0 0\n0 0 0\n1 1 0\n2 0 1\n2 0\n0 0 1\n1 1 3\n");
  const std::string e1 = error_of([&] { read_poly(dangling); });
  CHECK(e1.find("h.poly") != std::string::npos);
  CHECK(e1.find("line 7") != std::string::npos);
  CHECK(e1.find("does not exist") != std::string::npos);

  const auto truncated = s.file("i.node", "4 2 0 0\n0 0 0\n1 1 0\n");
  const std::string e2 = error_of([&] { read_node(truncated); });
  CHECK(e2.find("truncated") != std::string::npos);

  const auto nan = s.file("j.node", "3 2 0 0\n0 0 0\n1 nan 0\n2 0 1\n");
  CHECK(error_of([&] { read_node(nan); }).find("line 3") != std::string::npos);

  const auto junk = s.file("k.node", "3 2 0 0\n0 0 0\n1 1x 0\n2 0 1\n");
  CHECK(error_of([&] { read_node(junk); }).find("not a number") != std::string::npos);

  const auto huge = s.file("l.node", "99999999999 2 0 0\n0 0 0\n");
  CHECK(error_of([&] { read_node(huge); }).find("truncated") != std::string::npos);

  const auto dim3 = s.file("m.node", "3 3 0 0\n0 0 0 0\n1 1 0 0\n2 0 1 0\n");
  CHECK(error_of([&] { read_node(dim3); }).find("dimension") != std::string::npos);

  const auto badfirst = s.file("n.node", "3 2 0 0\n5 0 0\n6 1 0\n7 0 1\n");
  CHECK(!error_of([&] { read_node(badfirst); }).empty());

  s.file("o.node", "3 2 0 0\n0 0 0\n1 1 0\n2 0 1\n");
  const auto repeat = s.file("o.ele", "1 3 0\n0 0 1 1\n");
  CHECK(error_of([&] { read_ele(repeat); }).find("repeats") != std::string::npos);

  const auto missing_node = s.file("p.ele", "1 3 0\n0 0 1 2\n");
  CHECK(error_of([&] { read_ele(missing_node); }).find("p.node") != std::string::npos);

  CHECK(!error_of([&] { read_node(s.path("absent.node")); }).empty());
  const auto empty = s.file("q.node", "# nothing\n");
  CHECK(error_of([&] { read_node(empty); }).find("truncated") != std::string::npos);
}

TEST_CASE("OFF in and out, other formats by extension") {
  Scratch s;
  PlanarMesh m;
  m.points = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
  m.elements = {{0, 1, 2}, {0, 2, 3}};
  m.element_attributes = {{1}, {2}};
  m.segments = {{0, 1}};
  m.segment_markers = {1};
  write_planar_mesh(s.path("r.off"), m);
  const PlanarMesh r = read_planar_mesh(s.path("r.off"));
  CHECK(r.points == m.points);
  CHECK(r.elements == m.elements);

  for (const char* ext : {".vtk", ".msh", ".svg"}) {
    const std::string p = s.path(std::string("r") + ext);
    PlanarWriteOptions opt;
    opt.element_scalar = {0.5, 0.9};
    write_planar_mesh(p, m, opt);
    CHECK(fs::file_size(p) > 100);
  }
  std::ifstream msh(s.path("r.msh"));
  std::string all((std::istreambuf_iterator<char>(msh)), {});
  CHECK(all.find("$MeshFormat\n2.2 0 8") != std::string::npos);
  CHECK(all.find("\n2 2 2 1 1 1 2 3\n") != std::string::npos);  // element 2 (after the segment): triangle, 2 tags = region 1, 1-based ids
  CHECK_THROWS_AS(write_planar_mesh(s.path("r.xyz"), m), Error);

  const auto poly_off = s.file("t.off", "OFF\n4 1 0\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n4 0 1 2 3\n");
  const PlanarMesh g = read_pslg(poly_off);
  CHECK(g.segments.size() == 4);
  CHECK(g.elements.empty());
  const auto bad_off = s.file("u.off", "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 5\n");
  CHECK_THROWS_AS(read_planar_mesh(bad_off), Error);
}

TEST_CASE("read_planar_mesh(\"-\") reads OFF from standard input; errors name \"-\"") {
  Scratch s;
  const auto off = s.file("in.off", "OFF\n# a square cut in two\n4 2 0\n0 0 0\n2 0 0\n2 1 0\n0 1 0\n"
                                    "3 0 1 2\n4 0 2 3 1\n");
  REQUIRE(std::freopen(off.c_str(), "r", stdin));
  const PlanarMesh m = read_planar_mesh("-");
  CHECK(m.points == std::vector<Point2>{{0, 0}, {2, 0}, {2, 1}, {0, 1}});
  CHECK(m.elements == std::vector<std::vector<int>>{{0, 1, 2}, {0, 2, 3, 1}});
  CHECK(m.first_index == 0);

  // A face with a missing vertex: the one-line error names "-" and the line.
  const auto bad = s.file("bad.off", "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 7\n");
  REQUIRE(std::freopen(bad.c_str(), "r", stdin));
  try {
    read_planar_mesh("-");
    FAIL("no error");
  } catch (const Error& e) {
    CHECK(e.path() == "-");
    CHECK(e.message().find("line 6") != std::string::npos);
    CHECK(std::string(e.what()).find('\n') == std::string::npos);
  }
  // An empty standard input is not an OFF file.
  const auto empty = s.file("empty.off", "");
  REQUIRE(std::freopen(empty.c_str(), "r", stdin));
  CHECK(error_of([] { read_planar_mesh("-"); }).find("not an OFF file") != std::string::npos);
}
