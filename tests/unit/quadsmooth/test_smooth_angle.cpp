// Angle-based smoothing and the compass searches (lib/quadsmooth/smooth_angle.cpp):
// the mean pass and the edge move through the loop, the max-min climbs alone.
#include "smooth_test_support.hpp"

#include "quad/predicates.hpp"
#include "quad/quality.hpp"
#include "quadsmooth/smooth.hpp"
#include "quadsmooth/smooth_mesh.hpp"

#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>

using namespace imgmesh;
using namespace quadsmooth_test;

TEST_CASE("the mean pass raises the mean mu and lowers no quad below the worst around it", "[smooth]") {
  // The same smoothing with and without the mean pass, which runs last: it
  // moves a vertex only to raise the sum of sin(mu) of its star, no quad of
  // the star below the star's worst, none non-convex; so the whole mesh's
  // sum of sin(mu) rises and its worst mu stays.
  double gain = 0;
  std::size_t climbs = 0;
  for (unsigned seed = 1; seed <= 40; ++seed) {
    const int n = 4 + 2 * int(seed % 5);
    PlanarMesh with = tri2quad_mesh(n, seed), without = with;
    SmoothOptions opt;
    opt.iterations = 6;
    opt.mean_rounds = 0;
    opt.grading = 0;  // its collapses and splits would follow the mean pass's moves
    const SmoothStats s0 = smooth_quad_mesh(without, opt);
    opt.mean_rounds = 3;
    const SmoothStats s1 = smooth_quad_mesh(with, opt);
    CAPTURE(seed, n, s0.after.min_mu, s1.after.min_mu, s0.after.mean_mu, s1.after.mean_mu);
    REQUIRE(with.elements == without.elements);  // the pass moves vertices only
    REQUIRE_NOTHROW(check_quad_mesh(with));
    double sin0 = 0, sin1 = 0;
    for (std::size_t e = 0; e < with.elements.size(); ++e) {
      const auto& q = with.elements[e];
      REQUIRE(is_strictly_convex(with.points[q[0]], with.points[q[1]], with.points[q[2]], with.points[q[3]]));
      const auto mu = [&](const PlanarMesh& m) {
        return joe_mu(m.points[q[0]], m.points[q[1]], m.points[q[2]], m.points[q[3]]);
      };
      sin0 += std::sin(mu(without) * M_PI / 180);
      sin1 += std::sin(mu(with) * M_PI / 180);
    }
    CHECK(s1.after.min_mu >= s0.after.min_mu - 1e-9);
    CHECK(sin1 >= sin0 - 1e-9);
    CHECK((s1.mean_climbs > 0) == (sin1 > sin0 + 1e-9));
    // Segment vertices stay.
    for (const auto& sg : with.segments)
      for (int v : sg) CHECK(with.points[v] == without.points[v]);
    gain += s1.after.mean_mu - s0.after.mean_mu;
    climbs += s1.mean_climbs;
  }
  CHECK(climbs > 0);
  CHECK(gain / 40 >= 0.5);  // degrees of mean mu, on average
}

TEST_CASE("a sliver along a segment is opened by moving its two free corners together", "[smooth]") {
  // The square's bottom side A-B carries a sliver (A, B, v, u) with its free
  // corners u, v just above it (corners of about 174 degrees at u and v, mu
  // under 3): moving u or v alone away from A-B makes the other reflex, so
  // only the edge move opens it (as on the lung through poly2tri --lattice 2).
  PlanarMesh m;
  m.points = {{0, 0}, {4, 0}, {4, 3}, {0, 3}, {1, 0.1}, {3, 0.1}, {1, 2}, {3, 2}};  // A B C D u v p q
  m.elements = {{0, 1, 5, 4}, {0, 4, 6, 3}, {4, 5, 7, 6}, {5, 1, 2, 7}, {6, 7, 2, 3}};
  const PlanarMesh orig = m;
  SmoothOptions opt;
  const SmoothStats st = smooth_quad_mesh(m, opt);
  CAPTURE(st.before.min_mu, st.after.min_mu, st.edge_moves);
  CHECK(st.before.min_mu < 3);
  CHECK(st.edge_moves >= 1);
  CHECK(st.after.min_mu >= 15);
  REQUIRE_NOTHROW(check_quad_mesh(m));
  for (const auto& e : m.elements)
    REQUIRE(is_strictly_convex(m.points[e[0]], m.points[e[1]], m.points[e[2]], m.points[e[3]]));
  for (int v = 0; v < 4; ++v) CHECK(m.points[v] == orig.points[v]);  // the boundary stays
}

TEST_CASE("the max-min climb raises the worst mu around a free vertex, every quad strictly convex", "[smooth]") {
  // Four unit squares around v = (1, 1), v pulled to (1.5, 1.3): its worst
  // quad has mu under 20 degrees; the square's centre is the max-min.
  PlanarMesh m;
  m.points = {{0, 0}, {1, 0}, {2, 0}, {0, 1}, {1.5, 1.3}, {2, 1}, {0, 2}, {1, 2}, {2, 2}};
  m.elements = {{0, 1, 4, 3}, {1, 2, 5, 4}, {3, 4, 7, 6}, {4, 5, 8, 7}};
  const SmoothOptions opt;
  quadsmooth_detail::QuadMesh qm(m, opt, quadsmooth_detail::conforming_stars(m, {}));
  REQUIRE_FALSE(qm.fixed[4]);
  const double worst_before = *std::min_element(qm.quad_sin_mu.begin(), qm.quad_sin_mu.end());
  REQUIRE(worst_before < std::sin(20 * 3.14159265358979323846 / 180));
  REQUIRE(quadsmooth_detail::raise_worst(qm, 4, 1.0));
  CHECK(live_quads_strictly_convex(qm));
  for (int q = 0; q < 4; ++q) CHECK(qm.quad_sin_mu[q] == Approx(qm.sin_mu_of(qm.quads[q])));
  CHECK(*std::min_element(qm.quad_sin_mu.begin(), qm.quad_sin_mu.end()) > worst_before + 0.2);
}

TEST_CASE("the max-min climb of two vertices never lowers the worst mu of their stars", "[smooth]") {
  // tri2quad's quads of random point sets: every edge with two free ends
  // of a quad under 12 degrees climbs; the worst mu of the two stars does
  // not drop, and every quad stays strictly convex.
  std::size_t moved = 0;
  for (unsigned seed = 1; seed <= 20; ++seed) {
    PlanarMesh m = tri2quad_mesh(4 + 2 * int(seed % 5), seed);
    const SmoothOptions opt;
    quadsmooth_detail::QuadMesh qm(m, opt, quadsmooth_detail::conforming_stars(m, {}));
    for (int q = 0; q < int(qm.quads.size()); ++q)
      for (int k = 0; k < 4; ++k) {
        const int u = qm.quads[q][k], v = qm.quads[q][(k + 1) & 3];
        if (qm.fixed[u] || qm.fixed[v] || qm.quad_sin_mu[q] >= std::sin(12 * M_PI / 180)) continue;
        auto worst = [&] {
          double w = 2;
          for (int x : {u, v})
            for (int r : qm.vertex_quads[x]) w = std::min(w, qm.sin_mu_of(qm.quads[r]));
          return w;
        };
        const double before = worst();
        CAPTURE(seed, q, k);
        if (quadsmooth_detail::raise_worst_pair(qm, u, v, 0.1)) ++moved;
        CHECK(worst() >= before);
      }
    CHECK(live_quads_strictly_convex(qm));
  }
  CHECK(moved > 0);
}
