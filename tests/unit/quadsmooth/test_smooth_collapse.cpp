// Quad collapse (lib/quadsmooth/smooth_collapse.cpp) on a small hand-made mesh.
#include "smooth_test_support.hpp"

#include "quadsmooth/smooth.hpp"
#include "quadsmooth/smooth_mesh.hpp"

#include <catch2/catch.hpp>

#include <algorithm>
#include <set>

using namespace imgmesh;
using namespace quadsmooth_test;

TEST_CASE("a quad collapse at a boundary vertex keeps it where it was, on the boundary", "[smooth]") {
  // a on the bottom side y = 0 with three quads; the middle one (a, b, c, d)
  // is squashed (mu under 6 degrees): c, free, merges into a, which stays.
  // b and d are boundary vertices (the domain has notches beside them).
  PlanarMesh m;
  m.points = {{-2, 0}, {0, 0}, {2, 0}, {1, 1}, {0, 1.1}, {-1, 1},  // i a e b c d
              {-2, 1}, {2, 1}, {0, 2}, {1, 2}, {-1, 2}};          // h f y x g
  enum { i, a, e, b, c, d, h, f, y, x, g };
  m.elements = {{i, a, d, h}, {a, e, f, b}, {a, b, c, d}, {d, c, y, g}, {c, b, x, y}};
  REQUIRE_NOTHROW(check_quad_mesh(m));
  const PlanarMesh orig = m;
  REQUIRE(quad_mu(m, m.elements[2]) < 15);
  const SmoothOptions opt;
  quadsmooth_detail::QuadMesh qm(m, opt, quadsmooth_detail::conforming_stars(m, {}));
  REQUIRE(qm.fixed[a]);
  REQUIRE_FALSE(qm.fixed[c]);
  SmoothStats st;
  CHECK_FALSE(quadsmooth_detail::collapse_quad(qm, 2, 1, st));  // b and d: both fixed
  REQUIRE(quadsmooth_detail::collapse_quad(qm, 2, 0, st));
  CHECK(st.collapses == 1);
  CHECK(qm.quad_dead[2]);
  CHECK(qm.vertex_dead[c]);
  CHECK(qm.points[a] == orig.points[a]);  // on the side y = 0, where it was
  CHECK(live_quads_strictly_convex(qm));
  qm.compact();
  REQUIRE_NOTHROW(check_quad_mesh(m));
  CHECK(m.elements.size() == 4);
  REQUIRE(m.points.size() == orig.points.size() - 1);
  // Vertices after c move down by one; every boundary edge stays.
  auto renum = [&](int v) { return v > c ? v - 1 : v; };
  std::set<std::pair<int, int>> expected;
  for (const auto& [p, q] : boundary_edges(orig)) expected.insert(std::minmax(renum(p), renum(q)));
  CHECK(boundary_edges(m) == expected);
  for (int v = 0; v < int(orig.points.size()); ++v)
    if (v != c) CHECK(m.points[renum(v)] == orig.points[v]);
  CHECK(total_area(m) == Approx(total_area(orig)).epsilon(1e-12));
  double mu = 90;
  for (const auto& el : m.elements) mu = std::min(mu, quad_mu(m, el));
  CHECK(mu > quad_mu(orig, orig.elements[2]));
}
