// The fallbacks of lib/tri2quad/fallback.cpp called alone.
#include "tri2quad_test_support.hpp"

#include "quad/predicates.hpp"
#include "quad/quality.hpp"
#include "tri2quad/conversion.hpp"
#include "util/error.hpp"

#include <catch2/catch.hpp>

#include <random>
#include <set>
#include <utility>

using namespace imgmesh;
using namespace tri2quad_test;
using tri2quad_detail::LocalPatch;

// The safe split alone (the fallback no construction-driven test reaches):
// a fan of triangles around the origin, the first one the node's, closed
// with strictly convex quads, edge to edge, covering the fan but for the
// leftover triangle on the outgoing edge (none at the root).
TEST_CASE("safe split: fans close with strictly convex quads and at most a leftover triangle", "[tri2quad][fallback]") {
  std::mt19937 g(11);
  int closed = 0, runs = 0, with_leftover = 0;
  for (int it = 0; it < 300; ++it) {
    const int k = 3 + int(g() % 6);
    auto v = random_star(g, k, 0.6, 1.0);
    bool star = true;  // the origin strictly inside every fan triangle's angle
    for (int i = 0; i < k; ++i) star = star && orientation(v[i], v[(i + 1) % k], {0, 0}) > 0;
    if (!star || !simple_ccw(v)) continue;
    Tri2QuadInput in;
    in.points = v;
    in.points.push_back({0, 0});
    for (int i = 0; i < k; ++i) in.triangles.push_back({i, (i + 1) % k, k});
    for (const bool root : {false, true}) {
      ++runs;
      Tri2QuadResult out;
      const Tri2QuadOptions opt;
      tri2quad_detail::Conversion cv(in, opt, out);
      cv.build_mesh();
      LocalPatch lp;
      int split_m = -1;
      tri2quad_detail::Leftover r;
      try {
        r = cv.safe_split(lp, in.triangles, root, &split_m);
      } catch (const Error&) {
        continue;
      }
      ++closed;
      double area = 0;
      std::set<std::pair<int, int>> directed;
      for (const auto& q : lp.quads) {
        CHECK(good_quad(lp.p[q[0]], lp.p[q[1]], lp.p[q[2]], lp.p[q[3]]));
        area += quad_area(lp.p[q[0]], lp.p[q[1]], lp.p[q[2]], lp.p[q[3]]);
        for (int e = 0; e < 4; ++e) CHECK(directed.insert({q[e], q[(e + 1) % 4]}).second);
      }
      double fan = 0;
      for (const auto& t : in.triangles) fan += poly_area({in.points[t[0]], in.points[t[1]], in.points[t[2]]});
      if (r.type == tri2quad_detail::kLeftoverTriangle) {
        ++with_leftover;
        CHECK(!root);
        // The leftover is the triangle (a, b, x) on the outgoing edge (a, b).
        const P2 &a = in.points[0], &b = in.points[1], &x = lp.p[r.x];
        CHECK(good_triangle(a, b, x));
        area += poly_area({a, b, x});
      } else {
        CHECK(r.type == tri2quad_detail::kNoLeftover);
      }
      CHECK(area == Approx(fan).epsilon(1e-9));
      if (split_m >= 0) CHECK(root);
    }
  }
  INFO("closed " << closed << " of " << runs);
  CHECK(runs > 200);
  CHECK(closed >= runs * 9 / 10);
  CHECK(with_leftover > 0);
}
