// meshinfo's per-label and per-interface report (label_report) on two unit
// cubes side by side, labels 1 and 2 in the background 0: each label's
// surface a closed oriented cube, the union's a 2x1x1 box; and a face whose
// pair is written the wrong way round breaks both labels' orientation.
#include "meshinfo/label_report.hpp"
#include "meshinfo/meshinfo.hpp"

#include <catch2/catch.hpp>

using namespace imgmesh;

namespace {

struct Complex {
  std::vector<std::array<double, 3>> points;
  std::vector<std::array<int, 3>> triangles;
  std::vector<std::array<std::int32_t, 2>> pairs;
};

// Vertex (i, j, k) of the 3x2x2 lattice.
int v(int i, int j, int k) { return i + 3 * (j + 2 * k); }

// A unit square as two triangles oriented along n (out of `behind`).
void square(Complex& c, std::array<int, 4> q, std::array<double, 3> n, std::int32_t behind, std::int32_t front) {
  auto p = [&](int i) { return c.points[std::size_t(q[std::size_t(i)])]; };
  const std::array<double, 3> a = p(0), b = p(1), d = p(2);
  const std::array<double, 3> u{b[0] - a[0], b[1] - a[1], b[2] - a[2]}, w{d[0] - a[0], d[1] - a[1], d[2] - a[2]};
  const double s = (u[1] * w[2] - u[2] * w[1]) * n[0] + (u[2] * w[0] - u[0] * w[2]) * n[1] + (u[0] * w[1] - u[1] * w[0]) * n[2];
  if (s < 0) std::swap(q[1], q[3]);
  c.triangles.push_back({q[0], q[1], q[2]});
  c.triangles.push_back({q[0], q[2], q[3]});
  c.pairs.push_back({behind, front});
  c.pairs.push_back({behind, front});
}

Complex two_cubes() {
  Complex c;
  for (int k = 0; k < 2; ++k)
    for (int j = 0; j < 2; ++j)
      for (int i = 0; i < 3; ++i) c.points.push_back({double(i), double(j), double(k)});
  for (int l = 1; l <= 2; ++l) {
    const int x0 = l - 1, x1 = l;
    if (l == 1) square(c, {v(0, 0, 0), v(0, 1, 0), v(0, 1, 1), v(0, 0, 1)}, {-1, 0, 0}, 1, 0);
    else square(c, {v(2, 0, 0), v(2, 1, 0), v(2, 1, 1), v(2, 0, 1)}, {1, 0, 0}, 2, 0);
    square(c, {v(x0, 0, 0), v(x1, 0, 0), v(x1, 0, 1), v(x0, 0, 1)}, {0, -1, 0}, l, 0);
    square(c, {v(x0, 1, 0), v(x1, 1, 0), v(x1, 1, 1), v(x0, 1, 1)}, {0, 1, 0}, l, 0);
    square(c, {v(x0, 0, 0), v(x1, 0, 0), v(x1, 1, 0), v(x0, 1, 0)}, {0, 0, -1}, l, 0);
    square(c, {v(x0, 0, 1), v(x1, 0, 1), v(x1, 1, 1), v(x0, 1, 1)}, {0, 0, 1}, l, 0);
  }
  square(c, {v(1, 0, 0), v(1, 1, 0), v(1, 1, 1), v(1, 0, 1)}, {1, 0, 0}, 1, 2);  // out of 1, into 2
  return c;
}

const Json& entry(const Json& list, const char* key, const Json& value) {
  for (const Json& e : list.items())
    if (e.at(key).kind() == Json::Kind::String ? e.at(key).string() == value.string() : e.at(key).integer() == value.integer())
      return e;
  FAIL("no entry");
  return list;
}

} // namespace

TEST_CASE("label_report: each label's closed surface and each interface of two cubes", "[meshinfo][labels]") {
  const Complex c = two_cubes();
  const Json r = label_report(c.points, c.triangles, c.pairs);
  REQUIRE(r.at("labels").items().size() == 3);
  for (int l = 1; l <= 2; ++l) {
    const Json& e = entry(r.at("labels"), "label", Json(l));
    CHECK(e.at("triangles").integer() == 12);
    CHECK(e.at("components").integer() == 1);
    CHECK(e.at("euler").items()[0].integer() == 2);
    CHECK(e.at("closed").boolean());
    CHECK(e.at("manifold").boolean());
    CHECK(e.at("oriented").boolean());
    CHECK(e.at("area").number() == Approx(6));
    CHECK(e.at("volume").number() == Approx(1));
    CHECK(e.at("min_angle").number() == Approx(45));
  }
  const Json& u = entry(r.at("labels"), "label", Json(0));  // the union's surface, out of the union
  CHECK(u.at("triangles").integer() == 20);
  CHECK(u.at("oriented").boolean());
  CHECK(u.at("euler").items()[0].integer() == 2);
  CHECK(u.at("volume").number() == Approx(2));
  REQUIRE(r.at("interfaces").items().size() == 3);
  CHECK(entry(r.at("interfaces"), "pair", Json("1|0")).at("area").number() == Approx(5));
  CHECK(entry(r.at("interfaces"), "pair", Json("1|0")).at("patches").integer() == 1);
  CHECK(entry(r.at("interfaces"), "pair", Json("2|1")).at("triangles").integer() == 2);
  CHECK(entry(r.at("interfaces"), "pair", Json("2|1")).at("area").number() == Approx(1));

  // meshinfo's text: a line per label and per interface.
  PolyMesh m;
  m.points = c.points;
  for (const auto& t : c.triangles) m.faces.push_back({t[0], t[1], t[2]});
  m.interfaces = c.pairs;
  m.format = "ply";
  const std::string text = format_report(mesh_report(m));
  CHECK(text.find("label 2      12 triangles, 1 component(s), euler 2, closed manifold oriented, area 6, volume 1") !=
        std::string::npos);
  CHECK(text.find("interface 2|1    2 triangles in 1 patch(es)") != std::string::npos);
}

TEST_CASE("label_report: a face whose pair is the wrong way round breaks both labels' orientation", "[meshinfo][labels]") {
  Complex c = two_cubes();
  std::swap(c.pairs.back()[0], c.pairs.back()[1]);  // one triangle of the shared square now says out of 2
  const Json r = label_report(c.points, c.triangles, c.pairs);
  for (int l = 1; l <= 2; ++l) {
    const Json& e = entry(r.at("labels"), "label", Json(l));
    CHECK_FALSE(e.at("oriented").boolean());
    CHECK(e.at("volume").number() != Approx(1));
  }
  CHECK(entry(r.at("labels"), "label", Json(0)).at("oriented").boolean());  // the union's surface does not see it
}

TEST_CASE("label_report: an interface's patches are its edge-connected pieces", "[meshinfo][labels]") {
  const Complex all = two_cubes();
  // The squares x = 0 (triangles 0-1) and x = 2 (10-11), both 1|0: apart.
  // Then the two y = 0 squares (2-3, 12-13), which share an edge with
  // each other and with them: one piece.
  Complex c;
  c.points = all.points;
  auto take = [&](std::size_t t) {
    c.triangles.push_back(all.triangles[t]);
    c.pairs.push_back({1, 0});
  };
  for (std::size_t t : {0, 1, 10, 11}) take(t);
  CHECK(label_report(c.points, c.triangles, c.pairs).at("interfaces").items()[0].at("patches").integer() == 2);
  for (std::size_t t : {2, 3, 12, 13}) take(t);
  CHECK(label_report(c.points, c.triangles, c.pairs).at("interfaces").items()[0].at("patches").integer() == 1);
}
