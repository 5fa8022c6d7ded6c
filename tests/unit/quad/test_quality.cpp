// Quad quality measures (lib/quad/quality.cpp): known values and invariances.
#include "quad/quality.hpp"

#include <catch2/catch.hpp>

#include <cmath>
#include <random>

using namespace imgmesh;

namespace {
const double kPi = std::acos(-1.0);
Point2 rot(const Point2& p, double th, double s, Point2 t) {
  return {s * (std::cos(th) * p[0] - std::sin(th) * p[1]) + t[0],
          s * (std::sin(th) * p[0] + std::cos(th) * p[1]) + t[1]};
}
} // namespace

TEST_CASE("Joe's mu, scaled Jacobian and angles of known quads", "[quality]") {
  // Square: mu = 45 (the maximum), scaled Jacobian 1, right angles.
  Point2 a{0, 0}, b{1, 0}, c{1, 1}, d{0, 1};
  CHECK(joe_mu(a, b, c, d) == Approx(45));
  CHECK(scaled_jacobian(a, b, c, d) == Approx(1));
  for (double x : quad_angles(a, b, c, d)) CHECK(x == Approx(90));
  CHECK(quad_area(a, b, c, d) == Approx(1));
  // 2 x 1 rectangle: the diagonal makes atan(1/2).
  CHECK(joe_mu({0, 0}, {2, 0}, {2, 1}, {0, 1}) == Approx(std::atan(0.5) * 180 / kPi));
  CHECK(scaled_jacobian({0, 0}, {2, 0}, {2, 1}, {0, 1}) == Approx(1));
  // Rhombus with 60/120 degree angles: the long diagonal gives 30-30-120 triangles.
  const double h = std::sqrt(3.0) / 2;
  Point2 r0{0, 0}, r1{1, 0}, r2{1.5, h}, r3{0.5, h};
  CHECK(joe_mu(r0, r1, r2, r3) == Approx(30));
  CHECK(scaled_jacobian(r0, r1, r2, r3) == Approx(h));
  const auto ang = quad_angles(r0, r1, r2, r3);
  CHECK(ang[0] == Approx(60));
  CHECK(ang[1] == Approx(120));
  CHECK(ang[0] + ang[1] + ang[2] + ang[3] == Approx(360));
  // Triangle angles.
  CHECK(min_triangle_angle({0, 0}, {1, 0}, {0.5, h}) == Approx(60));
  CHECK(min_triangle_angle({0, 0}, {1, 0}, {2, 0}) == 0);
}

TEST_CASE("mu is invariant under similarity and relabelling and at most 45", "[quality]") {
  std::mt19937 rng(6);
  std::uniform_real_distribution<double> U(-1, 1);
  int convex = 0;
  for (int trial = 0; trial < 2000; ++trial) {
    Point2 q[4] = {{-1 + 0.6 * U(rng), -1 + 0.6 * U(rng)}, {1 + 0.6 * U(rng), -1 + 0.6 * U(rng)},
                   {1 + 0.6 * U(rng), 1 + 0.6 * U(rng)}, {-1 + 0.6 * U(rng), 1 + 0.6 * U(rng)}};
    if (!is_strictly_convex(q[0], q[1], q[2], q[3])) continue;
    ++convex;
    const double mu = joe_mu(q[0], q[1], q[2], q[3]);
    REQUIRE(mu > 0);
    REQUIRE(mu <= 45 + 1e-9);
    CHECK(joe_mu(q[1], q[2], q[3], q[0]) == Approx(mu));
    const double th = U(rng) * kPi, s = 0.001 + std::fabs(U(rng)) * 100;
    Point2 t{U(rng) * 1000, U(rng) * 1000};
    CHECK(joe_mu(rot(q[0], th, s, t), rot(q[1], th, s, t), rot(q[2], th, s, t), rot(q[3], th, s, t)) ==
          Approx(mu).epsilon(1e-6));
    const double sj = scaled_jacobian(q[0], q[1], q[2], q[3]);
    CHECK(sj > 0);
    CHECK(sj <= 1 + 1e-12);
    // Scaled Jacobian is the sine of the angle furthest from 90 degrees.
    double want = 1;
    for (double a : quad_angles(q[0], q[1], q[2], q[3])) want = std::min(want, std::sin(a * kPi / 180));
    CHECK(sj == Approx(want).margin(1e-9));
  }
  CHECK(convex > 1000);
}

TEST_CASE("Table 3.2 bins and the whole-mesh report", "[quality]") {
  CHECK(mu_bin(0) == 0);
  CHECK(mu_bin(4.999) == 0);
  CHECK(mu_bin(5) == 1);
  CHECK(mu_bin(24.9) == 2);
  CHECK(mu_bin(34.9) == 3);
  CHECK(mu_bin(35) == 4);
  CHECK(mu_bin(45) == 4);
  // Two squares side by side (areas 1 and 4) and one 2 x 1 rectangle.
  std::vector<Point2> pts{{0, 0}, {1, 0}, {1, 1}, {0, 1}, {1, -1}, {3, -1}, {3, 1}, {5, 1}, {5, 2}, {3, 2}};
  std::vector<std::array<int, 4>> quads{{0, 1, 2, 3}, {4, 5, 6, 2}, {6, 7, 8, 9}};
  // {4,5,6,2}: (1,-1) (3,-1) (3,1) (1,1) is a 2 x 2 square.
  const auto r = quality_report(pts, quads);
  CHECK(r.quads == 3);
  CHECK(r.non_convex == 0);
  CHECK(r.mu_histogram[4] == 2);
  CHECK(r.mu_histogram[3] == 1);  // atan(1/2) = 26.6
  CHECK(r.min_mu == Approx(std::atan(0.5) * 180 / kPi));
  CHECK(r.median_mu == Approx(45));
  CHECK(r.mean_mu == Approx((90 + std::atan(0.5) * 180 / kPi) / 3));
  CHECK(r.angles_45_135 == Approx(1));
  CHECK(r.mean_area == Approx(7.0 / 3));
  CHECK(r.area_stddev == Approx(std::sqrt((1 + 16 + 4) / 3.0 - 49.0 / 9)));
  const Json j = r.to_json();
  CHECK(j.at("quads").integer() == 3);
  CHECK(j.at("mu_histogram").items().size() == 5);
  // A bow-tie is counted as non-convex and fails the angle bar.
  const auto r2 = quality_report(pts, {{0, 2, 1, 3}});
  CHECK(r2.non_convex == 1);
  CHECK(r2.angles_45_135 == 0);
}
