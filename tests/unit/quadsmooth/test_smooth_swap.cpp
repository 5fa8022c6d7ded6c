// Diagonal swaps (lib/quadsmooth/smooth_swap.cpp) on small hand-made meshes.
#include "smooth_test_support.hpp"

#include "quad/predicates.hpp"
#include "quadsmooth/smooth.hpp"
#include "quadsmooth/smooth_mesh.hpp"

#include <catch2/catch.hpp>

#include <algorithm>

using namespace imgmesh;
using namespace quadsmooth_test;

namespace {

bool shares_edge(const quadsmooth_detail::QuadMesh& qm, int a, int b) {
  return qm.quad_with_edge(a, b) >= 0 && qm.quad_with_edge(b, a) >= 0;
}

} // namespace

TEST_CASE("a diagonal swap for the worst mu takes the better diagonal of the hexagon", "[smooth]") {
  // Two quads of a flat hexagon sharing its long diagonal p0-p3 (mu about
  // 22 degrees); across p1-p4 they are nearly rectangles.
  PlanarMesh m;
  m.points = {{0, 0}, {2, -0.3}, {4, 0}, {4, 1}, {2, 1.3}, {0, 1}};
  m.elements = {{0, 1, 2, 3}, {3, 4, 5, 0}};
  const double mu0 = std::min(quad_mu(m, m.elements[0]), quad_mu(m, m.elements[1]));
  REQUIRE(mu0 < 30);
  const std::vector<Point2> points0 = m.points;
  SmoothOptions opt;
  opt.split_below = 0;  // swaps only
  quadsmooth_detail::QuadMesh qm(m, opt, quadsmooth_detail::conforming_stars(m, {}));
  SmoothStats st;
  REQUIRE(quadsmooth_detail::swap_diagonal(qm, 0, 3, st));  // edge 3 of quad 0 is p3 -> p0
  CHECK(st.swaps == 1);
  CHECK(shares_edge(qm, 1, 4));
  CHECK_FALSE(shares_edge(qm, 0, 3));
  CHECK(live_quads_strictly_convex(qm));
  CHECK(qm.points == points0);  // a swap moves no vertex
  qm.compact();
  REQUIRE_NOTHROW(check_quad_mesh(m));
  CHECK(std::min(quad_mu(m, m.elements[0]), quad_mu(m, m.elements[1])) > mu0 + 5);
  CHECK(total_area(m) == Approx(4 + 2 * 0.3 * 2));
}

TEST_CASE("a diagonal swap that would make a quad non-convex is refused and nothing changes", "[smooth]") {
  // The strip below (every corner on the boundary): either other diagonal
  // of the hexagon (u, c, d, w, a, b) leaves a quad with a corner over 180
  // degrees at u or w.
  PlanarMesh m;
  m.points = {{0, 0}, {3, 1}, {0.5, 2.5}, {-3, -0.9}, {2.5, -1.5}, {6, 1.9}};  // u, w, a, b, c, d
  m.elements = {{0, 1, 2, 3}, {1, 0, 4, 5}};
  const int H[6] = {0, 4, 5, 1, 2, 3};
  for (int k = 1; k <= 2; ++k) {
    const auto& P = m.points;
    const bool n1 = is_strictly_convex(P[H[k]], P[H[k + 1]], P[H[k + 2]], P[H[(k + 3) % 6]]);
    const bool n2 = is_strictly_convex(P[H[(k + 3) % 6]], P[H[(k + 4) % 6]], P[H[(k + 5) % 6]], P[H[k]]);
    REQUIRE_FALSE((n1 && n2));
  }
  SmoothOptions opt;
  opt.split_below = 0;  // no pair split in its place
  quadsmooth_detail::QuadMesh qm(m, opt, quadsmooth_detail::conforming_stars(m, {}));
  REQUIRE(qm.quad_sin_mu[0] < 0.5);  // poor: a swap is looked for
  const State before = snapshot(qm);
  SmoothStats st;
  for (int i = 0; i < 4; ++i) CHECK_FALSE(quadsmooth_detail::swap_diagonal(qm, 0, i, st));
  CHECK(st.swaps + st.valence_swaps + st.splits == 0);
  check_same(snapshot(qm), before);
}
