// Stages of img2poly's, poly2tri's and the SVG writer's engines alone
// (planar_detail): bdCA's curves and the regional points of small label
// images, the input's small angles, the lattices of Steiner points, the SVG
// frame; each on inputs whose answer is worked out by hand.
#include "planar/image_pslg_detail.hpp"
#include "planar/svg_detail.hpp"
#include "planar/triangulate_detail.hpp"
#include "util/error.hpp"

#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <functional>

using namespace imgmesh;
using namespace imgmesh::planar_detail;

namespace {

LabelImage make_image(std::size_t W, std::size_t H, const std::function<int(int, int)>& f) {
  Geometry g;
  g.dimension = 2;
  g.size = {W, H, 1};
  LabelImage img(g);
  for (std::size_t y = 0; y < H; ++y)
    for (std::size_t x = 0; x < W; ++x) img(x, y) = f(int(x), int(y));
  return img;
}

std::vector<PixelCurve> curves_of(const LabelImage& L) { return trace_curves(pixel_boundary(L), L); }

// The square [0, side]^2 as a PSLG.
PlanarMesh square(double side) {
  PlanarMesh p;
  p.points = {{0, 0}, {side, 0}, {side, side}, {0, side}};
  p.segments = {{0, 1}, {1, 2}, {2, 3}, {3, 0}};
  return p;
}

double distance_to_pslg(const PlanarMesh& p, const Point2& q) {
  double d = 1e300;
  for (const auto& s : p.segments) d = std::min(d, distance_to_segment(q, p.points[s[0]], p.points[s[1]]));
  return d;
}

const InDomain everywhere = [](const Point2&) { return true; };

} // namespace

TEST_CASE("bdCA: a square inside is one closed curve", "[stages][curves]") {
  const auto L = make_image(4, 4, [](int x, int y) { return x >= 1 && x <= 2 && y >= 1 && y <= 2; });
  const auto c = curves_of(L);
  REQUIRE(c.size() == 1);
  CHECK(c[0].closed);
  CHECK(c[0].points.size() == 8);
  CHECK(c[0].points[0] == Point2{0.5, 0.5});
  CHECK(c[0].labels == std::pair<std::int32_t, std::int32_t>{0, 1});
}

TEST_CASE("bdCA: a curve across the image ends on its rectangle", "[stages][curves]") {
  const auto L = make_image(4, 4, [](int x, int) { return x < 2 ? 7 : 3; });
  const auto bd = pixel_boundary(L);
  CHECK(bd.fixed(2, 0));
  CHECK(bd.fixed(2, 4));
  CHECK(!bd.fixed(2, 2));
  CHECK(bd.degree(2, 2) == 2);
  const auto c = trace_curves(bd, L);
  REQUIRE(c.size() == 1);
  CHECK(!c[0].closed);
  CHECK(c[0].points.front() == Point2{1.5, -0.5});
  CHECK(c[0].points.back() == Point2{1.5, 3.5});
  CHECK(c[0].points.size() == 5);
  CHECK(c[0].labels == std::pair<std::int32_t, std::int32_t>{3, 7});
}

TEST_CASE("bdCA: a junction of three labels cuts three curves", "[stages][curves]") {
  const auto L = make_image(4, 4, [](int x, int y) { return y < 2 ? 1 : x < 2 ? 2 : 3; });
  const auto bd = pixel_boundary(L);
  CHECK(bd.degree(2, 2) == 3);
  CHECK(bd.fixed(2, 2));
  const auto c = trace_curves(bd, L);
  REQUIRE(c.size() == 3);
  // From the corners in raster order: (0, 2) to the junction, then the
  // junction's edges +x and +y.
  CHECK(c[0].labels == std::pair<std::int32_t, std::int32_t>{1, 2});
  CHECK(c[1].labels == std::pair<std::int32_t, std::int32_t>{1, 3});
  CHECK(c[2].labels == std::pair<std::int32_t, std::int32_t>{2, 3});
  for (const auto& k : c) {
    CHECK(!k.closed);
    CHECK(k.points.size() == 3);
  }
  CHECK(c[2].points.back() == Point2{1.5, 3.5});
}

TEST_CASE("regional points: one per 4-connected region, at its deepest pixel", "[stages][regions]") {
  const auto one = region_points(make_image(5, 5, [](int, int) { return 4; }));
  REQUIRE(one.regions.size() == 1);
  CHECK(one.pixels[0] == Point2{2, 2});
  CHECK(one.regions[0].attribute == 4);
  // Label 1 on both sides of a column of 2: three regions, in raster order of
  // their first pixel; the column's pixels are all at depth 1 (the first wins).
  const auto three = region_points(make_image(7, 3, [](int x, int) { return x == 3 ? 2 : 1; }));
  REQUIRE(three.regions.size() == 3);
  CHECK(three.pixels[0] == Point2{1, 1});
  CHECK(three.pixels[1] == Point2{3, 0});
  CHECK(three.pixels[2] == Point2{5, 1});
  CHECK(three.regions[1].attribute == 2);
  CHECK(three.regions[2].attribute == 1);
}

TEST_CASE("smallest_segment_angle: between segments at a vertex only", "[stages]") {
  PlanarMesh p;
  p.points = {{0, 0}, {1, 0}, {1, 1}, {5, 5}, {6, 5.1}};
  p.segments = {{0, 1}, {0, 2}, {3, 4}};
  CHECK(smallest_segment_angle(p) == Approx(45));
  p.segments = {{3, 4}};
  CHECK(smallest_segment_angle(p) == 180);
}

TEST_CASE("input_angles: the small angles and the discs around their apexes", "[stages][angles]") {
  PlanarMesh p;
  p.points = {{0, 0}, {1, 0}, {0, 1}, {5, 5}, {6, 5}};
  p.segments = {{0, 1}, {1, 2}, {2, 0}, {3, 4}};
  const InputAngles a = input_angles(p);
  CHECK(a.smallest == Approx(45));
  CHECK(a.small_vertices == 2);
  REQUIRE(a.apexes.size() == 2);
  CHECK(a.apexes[0].first == 1);
  CHECK(a.apexes[1].first == 2);
  CHECK(a.apexes[0].second == Approx(1));  // the shorter of 1 and sqrt 2
  CHECK(a.apexes[1].second == Approx(1));
}

TEST_CASE("equilateral_lattice: half a side from the segments, a side apart", "[stages][lattice]") {
  const PlanarMesh p = square(10);
  const auto pts = equilateral_lattice(p, 1, 1000000, everywhere);
  REQUIRE(pts.size() > 50);
  double closest = 1e300;
  for (std::size_t i = 0; i < pts.size(); ++i) {
    CHECK(distance_to_pslg(p, pts[i]) >= 0.5 - 1e-12);
    for (std::size_t j = 0; j < i; ++j)
      closest = std::min(closest, std::hypot(pts[i][0] - pts[j][0], pts[i][1] - pts[j][1]));
  }
  CHECK(closest == Approx(1));
  // The domain decides, point by point.
  const auto right = equilateral_lattice(p, 1, 1000000, [](const Point2& q) { return q[0] > 5; });
  CHECK(!right.empty());
  CHECK(std::all_of(right.begin(), right.end(), [](const Point2& q) { return q[0] > 5; }));
  CHECK_THROWS_AS(equilateral_lattice(p, 0.01, 1000, everywhere), UsageError);
}

TEST_CASE("square_lattice: uniform, then coarsening away from the segments", "[stages][lattice]") {
  // Uniform: the cell centres of the unit grid, all of them (half a side
  // from the square's sides is far enough).
  const auto uniform = square_lattice(square(10), 1, 0, 0, false, 1000000, everywhere);
  CHECK(uniform.size() == 100);
  for (const auto& q : uniform) {
    CHECK(q[0] - std::floor(q[0]) == 0.5);
    CHECK(q[1] - std::floor(q[1]) == 0.5);
  }
  CHECK_THROWS_AS(square_lattice(square(10), 1, 0, 0, false, 99, everywhere), UsageError);
  // Graded: the sides ask for 8 (their length 64 clamped to max_side), the
  // corners for 1, so the centre is a node of the lattice of side 8 and its
  // neighbours of side 1 are left out, where a corner keeps the finest.
  const PlanarMesh p = square(64);
  const auto graded = square_lattice(p, 1, 0.5, 8, false, 1000000, everywhere);
  CHECK(graded.size() < 64 * 64 / 4);
  const auto has = [&](const Point2& q) { return std::find(graded.begin(), graded.end(), q) != graded.end(); };
  CHECK(has({32.5, 32.5}));
  CHECK(!has({33.5, 32.5}));
  CHECK(has({0.5, 0.5}));
  for (const auto& q : graded) CHECK(distance_to_pslg(p, q) >= 0.5);
}

TEST_CASE("svg_frame: the foreground with a margin, within the whole", "[stages][svg]") {
  PlanarMesh m;
  m.points = {{0, 0}, {100, 0}, {100, 100}, {0, 100}, {40, 40}, {50, 40}, {50, 50}};
  m.elements = {{0, 1, 2}, {0, 2, 3}, {4, 5, 6}};
  m.element_attributes = {{0}, {0}, {1}};
  m.segments = {{0, 1}, {1, 2}, {2, 3}, {3, 0}};
  m.segment_markers = {1, 1, 1, 1};  // the image rectangle's: not foreground
  PlanarWriteOptions opt;
  // A margin of max(0.1 x 10, 0.02 x 100) = 2.
  CHECK(svg_frame(m, opt) == std::array<double, 4>{38, 38, 52, 52});
  opt.svg_frame_foreground = false;
  CHECK(svg_frame(m, opt) == std::array<double, 4>{0, 0, 100, 100});
  opt.svg_frame_foreground = true;
  m.segments.push_back({0, 4});
  m.segment_markers.push_back(2);  // a curve from the corner: the foreground is [0, 50]^2, margin 5
  CHECK(svg_frame(m, opt) == std::array<double, 4>{0, 0, 55, 55});
}
