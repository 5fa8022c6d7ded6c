// The placement rule's region (lib/quad/half_plane_clip.cpp): a polygon
// clipped by closed half-planes, and its area centroid.
#include "quad/half_plane_clip.hpp"

#include <catch2/catch.hpp>

using namespace imgmesh;

namespace {
double signed_area(const std::vector<Point2>& v) {
  double a = 0;
  for (std::size_t i = 0; i < v.size(); ++i)
    a += v[i][0] * v[(i + 1) % v.size()][1] - v[(i + 1) % v.size()][0] * v[i][1];
  return a / 2;
}
} // namespace

TEST_CASE("clip keeps what is left of every half-plane's line; centroid is the area's", "[half_plane_clip]") {
  const std::vector<Point2> square = {{0, 0}, {2, 0}, {2, 2}, {0, 2}};
  CHECK(centroid(square) == Point2{1, 1});
  // Left of x = 1 going up: the left half.
  const std::vector<Point2> half = clip(square, {{{1, 0}, {1, 1}}});
  REQUIRE(half.size() == 4);
  CHECK(signed_area(half) == Approx(2));
  for (const Point2& p : half) CHECK(p[0] <= 1);
  // And above y = x: {x <= 1, y >= x} in the square, a trapezoid of area
  // 3/2 and centroid (4/9, 11/9).
  const std::vector<Point2> cut = clip(square, {{{1, 0}, {1, 1}}, {{0, 0}, {1, 1}}});
  CHECK(signed_area(cut) == Approx(1.5));
  const Point2 c = centroid(cut);
  CHECK(c[0] == Approx(4.0 / 9));
  CHECK(c[1] == Approx(11.0 / 9));
  // Closed half-planes: a line along an edge keeps the whole polygon.
  CHECK(signed_area(clip(square, {{{0, 0}, {2, 0}}})) == Approx(4));
  // Nothing left of x = 3 going down (x > 3): empty.
  CHECK(clip(square, {{{3, 1}, {3, 0}}}).empty());
  // A polygon of zero area: the mean of its vertices.
  CHECK(centroid({{0, 0}, {1, 0}, {5, 0}}) == Point2{2, 0});
}
