// The grading pass (lib/quadsmooth/smooth_grade.cpp): alone on a hand-made
// mesh, and through the loop on tri2quad's outputs.
#include "smooth_test_support.hpp"

#include "quad/predicates.hpp"
#include "quad/quality.hpp"
#include "quadsmooth/smooth.hpp"
#include "quadsmooth/smooth_mesh.hpp"

#include <catch2/catch.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <map>

using namespace imgmesh;
using namespace quadsmooth_test;

namespace {

// The largest size ratio (square roots of the areas) of two quads sharing an edge.
double max_neighbour_ratio(const PlanarMesh& m) {
  std::map<std::pair<int, int>, double> seen;
  double worst = 1;
  for (const auto& e : m.elements) {
    const double s = std::sqrt(quad_area(m.points[e[0]], m.points[e[1]], m.points[e[2]], m.points[e[3]]));
    for (int i = 0; i < 4; ++i) {
      const auto k = std::minmax(e[i], e[(i + 1) % 4]);
      const auto it = seen.find(k);
      if (it == seen.end()) seen[k] = s;
      else worst = std::max(worst, std::max(s / it->second, it->second / s));
    }
  }
  return worst;
}

} // namespace

TEST_CASE("the grading pass grows a small quad ringed by four large ones to sqrt 6", "[smooth]") {
  // A 3 x 3 square (its corners on the boundary) with a concentric square
  // of side 0.3 inside, joined corner to corner: four trapezoids 5 times
  // the inner square's size (mu 5.7 degrees). The pass alone (quadsmooth's
  // clean-up merges the five into one).
  PlanarMesh m;
  m.points = {{0, 0}, {3, 0}, {3, 3}, {0, 3}, {1.35, 1.35}, {1.65, 1.35}, {1.65, 1.65}, {1.35, 1.65}};
  m.elements = {{4, 5, 6, 7}, {0, 1, 5, 4}, {1, 2, 6, 5}, {2, 3, 7, 6}, {3, 0, 4, 7}};
  m.element_attributes.assign(5, {1.0});
  REQUIRE(max_neighbour_ratio(m) > 4.9);
  SmoothOptions opt;
  quadsmooth_detail::QuadMesh qm(m, opt, quadsmooth_detail::conforming_stars(m, {}));
  SmoothStats st;
  st.before = quality_report(m);
  quadsmooth_detail::grading_pass(qm, st, opt.grading);
  qm.compact();
  const QualityReport after = quality_report(m);
  CAPTURE(max_neighbour_ratio(m), st.grading_moves, after.min_mu);
  CHECK(max_neighbour_ratio(m) <= std::sqrt(6.0) * (1 + 1e-9));
  CHECK(st.grading_moves > 0);
  CHECK(m.elements.size() == 5);
  REQUIRE_NOTHROW(check_quad_mesh(m));
  for (const auto& e : m.elements)
    REQUIRE(is_strictly_convex(m.points[e[0]], m.points[e[1]], m.points[e[2]], m.points[e[3]]));
  CHECK(after.min_mu >= st.before.min_mu - 1e-9);
  CHECK(region_area(m, 1) == Approx(9).epsilon(1e-12));
  for (int v = 0; v < 4; ++v) CHECK(m.points[v] == (std::array<double, 2>{v == 1 || v == 2 ? 3.0 : 0.0, v >= 2 ? 3.0 : 0.0}));
}

TEST_CASE("the grading pass takes no quad under 10 degrees nor under its own mu", "[smooth]") {
  // tri2quad's outputs of jittered grids through quadsmooth with and
  // without the pass (which runs last, but for guarded mean rounds): the
  // worst mu is the one without it, or 10 degrees if that is lower.
  for (unsigned seed = 1; seed <= 20; ++seed) {
    const int n = 4 + 2 * int(seed % 5);
    PlanarMesh with = tri2quad_mesh(n, seed), without = with;
    SmoothOptions opt;
    opt.grading = 0;
    const SmoothStats s0 = smooth_quad_mesh(without, opt);
    const SmoothStats s1 = smooth_quad_mesh(with, SmoothOptions{});
    CAPTURE(seed, n, s0.after.min_mu, s1.after.min_mu, max_neighbour_ratio(without), max_neighbour_ratio(with));
    REQUIRE_NOTHROW(check_quad_mesh(with));
    for (const auto& e : with.elements)
      REQUIRE(is_strictly_convex(with.points[e[0]], with.points[e[1]], with.points[e[2]], with.points[e[3]]));
    CHECK(s1.after.min_mu >= std::min(10.0, s0.after.min_mu) - 1e-9);
    // The largest ratio only falls, or the mean rounds after raise it to sqrt 6.
    CHECK(max_neighbour_ratio(with) <= std::max(std::sqrt(6.0), max_neighbour_ratio(without)) * (1 + 1e-9));
  }
}
