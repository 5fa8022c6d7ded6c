// Steps 1-5 on hand-made meshes, case by case (lib/tri2quad/steps.cpp and the
// fallbacks they reach; the safe split alone is in test_fallback.cpp).
#include "tri2quad_test_support.hpp"

#include "quad/quality.hpp"
#include "tri2quad/conversion.hpp"
#include "tri2quad/polygons.hpp"
#include "tri2quad/tri2quad.hpp"
#include "util/error.hpp"

#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>
#include <random>
#include <set>

using namespace imgmesh;
using namespace tri2quad_test;
using tri2quad_detail::LocalPatch;

namespace {

// The case counters that ran (non-zero), by name: what --stats reports.
std::map<std::string, std::size_t> cases_run(const Tri2QuadResult& r) {
  std::map<std::string, std::size_t> cs;
  for (const auto& [n, c] : r.cases)
    if (c) cs[n] = c;
  return cs;
}

// p in the closed simple polygon v: inside, or on an edge up to rounding
// (points the algorithm put "on" an edge are computed in floating point).
bool in_closed_polygon(const std::vector<P2>& v, const P2& p) {
  bool in = false;
  for (std::size_t i = 0; i < v.size(); ++i) {
    const P2 &a = v[i], &b = v[(i + 1) % v.size()];
    const double dx = b[0] - a[0], dy = b[1] - a[1], len2 = dx * dx + dy * dy;
    const double cr = dx * (p[1] - a[1]) - dy * (p[0] - a[0]);
    const double t = (dx * (p[0] - a[0]) + dy * (p[1] - a[1])) / len2;
    if (std::fabs(cr) <= 1e-9 * len2 && t >= -1e-9 && t <= 1 + 1e-9) return true;
    if ((a[1] > p[1]) != (b[1] > p[1]) && p[0] < a[0] + (p[1] - a[1]) * dx / dy) in = !in;
  }
  return in;
}

bool strictly_inside(const P2& a, const P2& b, const P2& c, const P2& p) {
  return orientation(a, b, p) > 0 && orientation(b, c, p) > 0 && orientation(c, a, p) > 0;
}

// The local result of one case: the quads with every corner in the closed
// region (the domain of T_v as the case sees it, counter-clockwise), all
// whether they are strictly convex, their area, and the Steiner points among their
// corners that are not corners of the region (the ones the case placed).
struct Local {
  std::size_t quads = 0, steiner = 0;
  double area = 0;
  bool convex = true;
};
Local local_result(const Tri2QuadResult& r, const std::vector<P2>& region) {
  Local l;
  std::set<int> placed;
  const auto& P = r.points;
  for (const auto& q : r.quads) {
    bool inside = true;
    for (int v : q) inside = inside && in_closed_polygon(region, P[v]);
    if (!inside) continue;
    ++l.quads;
    l.area += quad_area(P[q[0]], P[q[1]], P[q[2]], P[q[3]]);
    l.convex = l.convex && is_strictly_convex(P[q[0]], P[q[1]], P[q[2]], P[q[3]]);
    for (int v : q)
      if (std::size_t(v) >= r.input_points && std::find(region.begin(), region.end(), P[v]) == region.end())
        placed.insert(v);
  }
  l.steiner = placed.size();
  return l;
}

// The fourth corner of the quad with corners a, b and c, or -1: with (a, b)
// a case's outgoing edge and c the far vertex of the parent's triangle, the
// apex of the leftover triangle the case passed up.
int fourth_corner(const Tri2QuadResult& r, int a, int b, int c) {
  for (const auto& q : r.quads) {
    const auto has = [&](int v) { return std::find(q.begin(), q.end(), v) != q.end(); };
    if (!has(a) || !has(b) || !has(c)) continue;
    for (int v : q)
      if (v != a && v != b && v != c) return v;
  }
  return -1;
}

// The point a case put on its outgoing edge (a, b), leaning into its own
// side (left of a -> b): the Steiner point there nearest to the midpoint.
int edge_point(const Tri2QuadResult& r, const P2& a, const P2& b) {
  int best = -1;
  double bd = 0;
  const P2 mid = {0.5 * (a[0] + b[0]), 0.5 * (a[1] + b[1])};
  for (std::size_t i = r.input_points; i < r.points.size(); ++i) {
    if (orientation(a, b, r.points[i]) <= 0) continue;
    const double d = std::hypot(r.points[i][0] - mid[0], r.points[i][1] - mid[1]);
    if (best < 0 || d < bd) { best = int(i); bd = d; }
  }
  return best;
}

// Steiner points on the segment (a, b) up to rounding.
std::size_t steiner_on(const Tri2QuadResult& r, const P2& a, const P2& b) {
  std::size_t n = 0;
  for (std::size_t i = r.input_points; i < r.points.size(); ++i) n += in_closed_polygon({a, b}, r.points[i]);
  return n;
}

Tri2QuadInput mesh(const std::vector<P2>& points, const std::vector<std::array<int, 3>>& triangles) {
  Tri2QuadInput in;
  in.points = points;
  in.triangles = triangles;
  return in;
}

using Cases = std::map<std::string, std::size_t>;

// A subtree that ends in 4(c)(ii) with B.2.1 type 3 (the mesh of the 4(c)(ii)
// test below): u = (a, b, c) = (0, 1, 2) and the non-convex pair (2, 1, 3),
// (3, 1, 4) below it put a point m on the edge (0, 1), 4 quads and 3
// points; the triangle below (0, 1) becomes a degenerate quadrilateral.
const std::vector<P2> kDentPoints = {{0, 0}, {4, 0}, {1.82, 0.6}, {1.95, 1.39}, {0.17, 4.43}, {2, -2}};
const std::vector<std::array<int, 3>> kDentTriangles = {{0, 1, 2}, {2, 1, 3}, {3, 1, 4}};
constexpr std::size_t kDentQuads = 4, kDentSteiner = 3;

// That subtree placed by a similarity on the edge (x, y) of a triangle
// (its b on x, its a on y), so that the triangle gets the point.
void add_dent(std::vector<P2>& pts, std::vector<std::array<int, 3>>& tris, int x, int y) {
  const P2 X = pts[x], Y = pts[y], v = {X[0] - Y[0], X[1] - Y[1]}, n = {-v[1], v[0]};
  int id[5] = {y, x, -1, -1, -1};
  for (int k = 2; k < 5; ++k) {
    const P2& p = kDentPoints[k];
    id[k] = int(pts.size());
    pts.push_back({Y[0] + (p[0] * v[0] + p[1] * n[0]) / 4, Y[1] + (p[0] * v[1] + p[1] * n[1]) / 4});
  }
  for (const auto& t : kDentTriangles) tris.push_back({id[t[0]], id[t[1]], id[t[2]]});
}

} // namespace

TEST_CASE("Steps on hand-made meshes", "[tri2quad][steps]") {
  SECTION("two triangles forming a convex quad: one quad, no point (4(c) shortcut)") {
    Tri2QuadInput in;
    in.points = {{0, 0}, {1, 0}, {1.2, 1}, {0, 1}};
    in.triangles = {{0, 1, 2}, {0, 2, 3}};
    const auto r = tri2quad(in);
    check_result(in, r, false);
    CHECK(r.quads.size() == 1);
    CHECK(r.steiner == 0);
  }
  SECTION("a non-convex pair at the root: step 5(c), nested template") {
    Tri2QuadInput in;
    in.points = {{0, 0}, {2, 0}, {1, 0.3}, {1, 2}};  // dart: 2 is reflex in (0,1,3,2)? use (0,1,2)+(0,2,3)
    in.points = {{0, 0}, {2, 1}, {0.5, 0.5}, {1, 2}};
    in.triangles = {{0, 1, 2}, {2, 1, 3}};
    const auto r = tri2quad(in);
    check_result(in, r, false);
  }
  SECTION("a single triangle: Joe's split by default, one outside point with --allow-outside") {
    Tri2QuadInput in;
    in.points = {{0, 0}, {1, 0}, {0.3, 0.8}};
    in.triangles = {{0, 1, 2}};
    const auto r = tri2quad(in);
    check_result(in, r, false);
    CHECK(r.quads.size() == 5);
    Tri2QuadOptions o;
    o.allow_outside = true;
    const auto r2 = tri2quad(in, o);
    CHECK(r2.quads.size() == 1);
    CHECK(r2.steiner_outside == 1);
    CHECK(is_strictly_convex(r2.points[r2.quads[0][0]], r2.points[r2.quads[0][1]], r2.points[r2.quads[0][2]],
                             r2.points[r2.quads[0][3]]));
  }
  SECTION("a fan around an interior vertex (non-empty triangles, B.1.2)") {
    for (int n = 3; n <= 9; ++n) {
      Tri2QuadInput in;
      in.points.push_back({0, 0});
      for (int i = 0; i < n; ++i) in.points.push_back({std::cos(2 * kPi * i / n), std::sin(2 * kPi * i / n)});
      for (int i = 0; i < n; ++i) in.triangles.push_back({0, 1 + i, 1 + (i + 1) % n});
      const auto r = tri2quad(in);
      check_result(in, r, false);
    }
  }
  SECTION("3(d): two non-empty triangles close with a point on the outgoing edge and B.1.2 twice") {
    // u = (a, b, c) with three triangles around y1 on bc and around y2 on
    // ca; at the root (ab on the boundary) and below a parent (b, a, z).
    for (int with_parent = 0; with_parent < 2; ++with_parent) {
      Tri2QuadInput in;
      in.points = {{0, 0}, {4, 0}, {2, 2}, {4, 3}, {10.0 / 3, 5.0 / 3}, {0, 3}, {2.0 / 3, 5.0 / 3}, {2, -2}};
      if (with_parent) in.triangles.push_back({1, 0, 7});
      in.triangles.push_back({0, 1, 2});
      for (const std::array<int, 3>& t : {std::array<int, 3>{1, 3, 4}, {3, 2, 4}, {2, 1, 4}, {2, 5, 6}, {5, 0, 6}, {0, 2, 6}})
        in.triangles.push_back(t);
      const auto r = tri2quad(in);
      check_result(in, r, false);
      std::map<std::string, std::size_t> cs(r.cases.begin(), r.cases.end());
      CHECK(cs["3_nonempty_triangle"] == 2);
      CHECK(cs["3d_edge_point_B12_twice"] == 1);
      // B.1.2 twice with the edge point (10 quads, 7 points); below a
      // parent, the parent's triangle with that point is one quad (step 1).
      CHECK(r.quads.size() == std::size_t(with_parent ? 11 : 10));
      CHECK(r.steiner == 7);
    }
  }
  SECTION("4(c)(v)(f) and 4(c)(iv): two non-convex pairs, or a pair and a non-empty triangle") {
    // u = (a, b, c); on bc the pair (c, b, w), (w, b, x), reflex at w; on
    // ca its mirror image (heptagon) or three triangles around y2.
    const std::vector<P2> p = {{0, 0}, {4, 0}, {2, 2}, {4.5, 2.5}, {6, 4}, {-0.5, 2.5}, {-2, 4},
                               {0, 3}, {2.0 / 3, 5.0 / 3}, {2, -2}};
    const std::vector<std::array<int, 3>> pair_bc = {{2, 1, 3}, {3, 1, 4}}, pair_ca = {{2, 0, 5}, {5, 0, 6}},
                                          ntri_ca = {{2, 7, 8}, {7, 0, 8}, {0, 2, 8}};
    for (int with_parent = 0; with_parent < 2; ++with_parent)
      for (int hept = 0; hept < 2; ++hept) {
        Tri2QuadInput in;
        in.points = p;
        if (with_parent) in.triangles.push_back({1, 0, 9});
        in.triangles.push_back({0, 1, 2});
        for (const auto& t : pair_bc) in.triangles.push_back(t);
        for (const auto& t : hept ? pair_ca : ntri_ca) in.triangles.push_back(t);
        INFO("parent " << with_parent << " heptagon " << hept);
        const auto r = tri2quad(in);
        check_result(in, r, false);
        std::map<std::string, std::size_t> cs(r.cases.begin(), r.cases.end());
        CHECK(cs["4c_quad_to_grandparent"] == std::size_t(hept ? 2 : 1));
        if (hept) {
          // The root closes with a point on its edge (7 quads, 5 points);
          // below a parent the leftover form (6 quads, 4 points at most).
          CHECK(cs["4cvf_B31_heptagon"] + cs["B31_heptagon_edge_point"] == 1);
          if (!with_parent) CHECK(cs["B31_heptagon_edge_point"] == 1);
        } else {
          CHECK(cs["3_nonempty_triangle"] == 1);
          CHECK(cs["4civ_hexagon_point"] + cs["4civ_B21_B12_pair_nonempty"] == 1);
        }
        CHECK(cs["fallback_pair_nested"] + cs["fallback_dent_triangle"] + cs["fallback_dent_nonempty"] == 0);
      }
  }
  SECTION("3(c) with its cross-edge / 4(c)(v)(d)-(e): a triangle with two vertices inside") {
    // The triangle (a, b, X) with c and y inside; u = (a, b, c) keeps its
    // triangle as the leftover and B.1.2 closes (b, X, a, c) around y.
    for (int with_parent = 0; with_parent < 2; ++with_parent) {
      Tri2QuadInput in;
      in.points = {{0, 0}, {4, 0}, {2, 4}, {2, 1}, {1.5, 1.2}, {2, -2}};  // a b X c y z
      if (with_parent) in.triangles.push_back({1, 0, 5});
      for (const std::array<int, 3>& t : {std::array<int, 3>{0, 1, 3}, {1, 2, 3}, {3, 2, 4}, {2, 0, 4}, {0, 3, 4}})
        in.triangles.push_back(t);
      INFO("parent " << with_parent);
      const auto r = tri2quad(in);
      check_result(in, r, false);
      std::map<std::string, std::size_t> cs(r.cases.begin(), r.cases.end());
      CHECK(cs["3c_4cvde_leftover_B12"] == 1);
      CHECK(cs["fallback_pair_nested"] + cs["fallback_dent_triangle"] + cs["fallback_dent_nonempty"] == 0);
    }
  }
  SECTION("4(c)(ii) with B.2.1 type 3: a point on the outgoing edge, the parent a degenerate quad (step 1)") {
    // u = (a, b, c) and the pair (c, b, w), (w, b, x) form a pentagon with
    // no leftover form within budget; the parent (b, a, z) takes the point.
    Tri2QuadInput in;
    in.points = kDentPoints;
    in.triangles = kDentTriangles;
    in.triangles.insert(in.triangles.begin(), std::array<int, 3>{1, 0, 5});
    const auto r = tri2quad(in);
    check_result(in, r, false);
    std::map<std::string, std::size_t> cs(r.cases.begin(), r.cases.end());
    CHECK(cs["4c_quad_to_grandparent"] == 1);
    CHECK(cs["4cii_B21_type3_edge_point"] == 1);
    CHECK(cs["4c_convex_quad"] == 1);  // the parent's triangle with the point
    // Type 3: 4 quads and 3 points (one on the edge); the parent 1 quad.
    CHECK(r.quads.size() == 5);
    CHECK(r.steiner == 3);
  }
  SECTION("a dangling constraint edge is refused, naming the edge") {
    Tri2QuadInput in;
    in.points = {{0, 0}, {2, 0}, {2, 2}, {0, 2}, {1, 1}};
    in.triangles = {{0, 1, 4}, {1, 2, 4}, {2, 3, 4}, {3, 0, 4}};
    in.constraints = {{0, 4}};
    in.index_base = 1;
    try {
      tri2quad(in);
      FAIL("no error");
    } catch (const Error& e) {
      const std::string w = e.what();
      CHECK((w.find("(1, 5)") != std::string::npos || w.find("(5, 1)") != std::string::npos));
      CHECK(w.find("dangles") != std::string::npos);
    }
  }
  SECTION("a constraint that is not a mesh edge is refused") {
    Tri2QuadInput in;
    in.points = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
    in.triangles = {{0, 1, 2}, {0, 2, 3}};
    in.constraints = {{1, 3}};
    CHECK_THROWS_AS(tri2quad(in), Error);
  }
}

// Each remaining case of steps 2-5 and each lemma's configuration on a
// hand-made mesh whose BFS tree forces it: the counters show that exactly
// that case ran (beside the cases of the rest of the mesh), and the quads
// inside the case's region are what the thesis's case produces. The root
// is triangle 0 (its first boundary edge is the root edge).
TEST_CASE("Steps on hand-made meshes: the remaining cases of steps 2-5 and of B.2.1 and B.2.2",
          "[tri2quad][steps]") {
  SECTION("4(b) and B.2.1 type 1: two leaves, the outgoing edge in the centre triangle") {
    // P = (A, B, C) below the root (B, A, z) with leaves (C, B, y) and (A, C,
    // x); C is reflex in the pentagon (A, B, y, C, x), so only the fan from C
    // triangulates it (type 1) and no ear leaves a convex quad.
    const P2 A{0, 0}, B{4, 0}, C{2, 2}, y{4, 2.5}, x{0, 2.5}, z{2, -2};
    const auto in = mesh({A, B, C, y, x, z}, {{1, 0, 5}, {0, 1, 2}, {2, 1, 3}, {0, 2, 4}});
    const auto r = tri2quad(in);
    check_result(in, r, false);
    CHECK(cases_run(r) == Cases{{"4b_B21_type1", 1}, {"4c_convex_quad", 1}});
    // Two quads and the leftover (A, B, p1), p1 in the centre triangle; the
    // root closes it with its own triangle as one quad.
    const int p1 = fourth_corner(r, 0, 1, 5);
    REQUIRE(p1 >= int(in.points.size()));
    CHECK(strictly_inside(A, B, C, r.points[p1]));
    const std::vector<P2> region = {A, B, y, C, x};
    const Local l = local_result(r, region);
    CHECK(l.convex);
    CHECK(l.quads == 2);
    CHECK(l.steiner == 1);
    CHECK(l.area == Approx(poly_area(region) - poly_area({A, B, r.points[p1]})));
    CHECK(r.quads.size() == 3);
    CHECK(r.steiner == 1);
  }
  SECTION("B.2.1 type 2: the pair's diagonal at C (4(c)(ii)), and its mirror image") {
    // P = (A, B, C) and the pair (C, B, w), (C, w, x) reflex at C: the
    // pentagon (A, B, w, x, C) has only the fan from C, so AB lies in an ear
    // away from the common vertex. 3 quads, 2 points and a leftover.
    for (int mirror = 0; mirror < 2; ++mirror) {
      std::vector<P2> p = {{0, 0}, {4, 0}, {2, 2}, {4, 2}, {0.5, 3.2}, {2, -2}};
      if (mirror)
        for (P2& v : p) v[0] = 4 - v[0];
      const auto in = mesh(p, {{1, 0, 5}, {0, 1, 2}, {2, 1, 3}, {2, 3, 4}});
      INFO("mirror " << mirror);
      const auto r = tri2quad(in);
      check_result(in, r, false);
      CHECK(cases_run(r) == Cases{{"4c_quad_to_grandparent", 1}, {"4cii_B21_type2", 1}, {"4c_convex_quad", 1}});
      const int p2 = fourth_corner(r, 0, 1, 5);
      REQUIRE(p2 >= int(in.points.size()));
      std::vector<P2> region = {p[0], p[1], p[3], p[4], p[2]};
      if (mirror) std::reverse(region.begin(), region.end());
      const Local l = local_result(r, region);
      CHECK(l.convex);
      CHECK(l.quads == 3);
      CHECK(l.steiner == 2);
      CHECK(l.area == Approx(poly_area(region) - std::fabs(poly_area({p[0], p[1], r.points[p2]}))));
      CHECK(r.quads.size() == 4);
      CHECK(r.steiner == 2);
    }
  }
  SECTION("B.2.1 type 3 mirrored: the pair on the other side, a point on the outgoing edge") {
    std::vector<P2> p = kDentPoints;
    for (P2& v : p) v[0] = 4 - v[0];
    auto tris = kDentTriangles;
    tris.insert(tris.begin(), std::array<int, 3>{1, 0, 5});
    const auto in = mesh(p, tris);
    const auto r = tri2quad(in);
    check_result(in, r, false);
    CHECK(cases_run(r) == Cases{{"4c_quad_to_grandparent", 1}, {"4cii_B21_type3_edge_point", 1}, {"4c_convex_quad", 1}});
    // The pentagon (a, b, x, w, c) (mirrored: clockwise) closed with one of
    // its 3 points on ab: 4 quads, no leftover; the parent one quad (step 1).
    std::vector<P2> region = {p[0], p[1], p[4], p[3], p[2]};
    std::reverse(region.begin(), region.end());
    const Local l = local_result(r, region);
    CHECK(l.convex);
    CHECK(l.quads == kDentQuads);
    CHECK(l.steiner == kDentSteiner);
    // The point m on ab leans into u (the perturbation of step 1), so the
    // parent's triangle with it is one quad.
    const int m = edge_point(r, p[1], p[0]);
    CHECK(fourth_corner(r, 0, 1, 5) == m);
    CHECK(l.area == Approx(poly_area(region) - std::fabs(poly_area({p[0], p[1], r.points[m]}))));
  }
  SECTION("Step 2: a degenerate pentagon (points on two edges) becomes a quad and a leftover") {
    // P = (A, B, C) below the root (B, A, z) gets points m1 on BC and m2 on
    // CA from two 4(c)(ii) subtrees: the pentagon (A, B, m1, C, m2) gives 1
    // quad, no point, and a leftover on AB (Table 3.1, step 2).
    std::vector<P2> p = {{0, 0}, {8, 0}, {4, 4}, {4, -3}};
    std::vector<std::array<int, 3>> tris = {{1, 0, 3}, {0, 1, 2}};
    add_dent(p, tris, 1, 2);
    add_dent(p, tris, 2, 0);
    const auto in = mesh(p, tris);
    const auto r = tri2quad(in);
    check_result(in, r, false);
    CHECK(cases_run(r) == Cases{{"4cii_B21_type3_edge_point", 2}, {"4c_quad_to_grandparent", 2},
                                {"B21_pentagon_ear", 1}, {"4c_convex_quad", 1}});
    const int m1 = edge_point(r, p[2], p[1]), m2 = edge_point(r, p[0], p[2]);
    const int apex = fourth_corner(r, 0, 1, 3);
    CHECK((apex == m1 || apex == m2));
    const std::vector<P2> region = {p[0], p[1], r.points[m1], p[2], r.points[m2]};
    const Local l = local_result(r, region);
    CHECK(l.convex);
    CHECK(l.quads == 1);
    CHECK(l.steiner == 0);
    CHECK(l.area == Approx(poly_area(region) - poly_area({p[0], p[1], r.points[apex]})));
    CHECK(r.quads.size() == 2 * kDentQuads + 1 + 1);
    CHECK(r.steiner == 2 * kDentSteiner);
  }
  SECTION("4(a): a degenerate quadrilateral parent and a leaf") {
    // P = (b, a, z) gets the point m on (b, a) from its child u and
    // the leaf (a, x, z); the root is (b, z, t). A point in P splits the
    // pentagon (z, b, m, a, x) into 2 quads and the leftover (z, b, s').
    std::vector<P2> p = kDentPoints;
    const P2 x{-1, 0.3}, t{4.5, -2};
    p.push_back(x);  // 6
    p.push_back(t);  // 7
    auto tris = kDentTriangles;
    tris.insert(tris.begin(), {std::array<int, 3>{1, 5, 7}, {1, 0, 5}});
    tris.push_back({0, 6, 5});
    const auto in = mesh(p, tris);
    const auto r = tri2quad(in);
    check_result(in, r, false);
    CHECK(cases_run(r) == Cases{{"4cii_B21_type3_edge_point", 1}, {"4c_quad_to_grandparent", 1},
                                {"4b_B21_type1", 1}, {"4c_convex_quad", 1}});
    const P2 &a = p[0], &b = p[1], &z = p[5];
    const int m = edge_point(r, p[0], p[1]);
    const int s = fourth_corner(r, 5, 1, 7);
    REQUIRE(s >= int(in.points.size()));
    CHECK(strictly_inside(b, a, z, r.points[s]));
    const std::vector<P2> region = {b, r.points[m], a, x, z};
    const Local l = local_result(r, region);
    CHECK(l.convex);
    CHECK(l.quads == 2);
    CHECK(l.steiner == 1);
    CHECK(l.area == Approx(poly_area(region) - poly_area({z, b, r.points[s]})));
    CHECK(r.quads.size() == kDentQuads + 2 + 1);
    CHECK(r.steiner == kDentSteiner + 1);
  }
  SECTION("3(a): a degenerate quadrilateral parent and a non-empty triangle") {
    // As 4(a), with three triangles around y across (a, z). Joining m to z
    // leaves the triangle (z, b, m) and the quadrilateral (z, m, a, x)
    // around y (B.1.2): 5 quads, 3 points. (z, b, y) is not a triangle,
    // so B.2.2's first form cannot run.
    std::vector<P2> p = kDentPoints;
    const P2 x{1.5, -4}, t{4.5, -2}, y{1.8, -2.5};
    for (const P2& v : {x, t, y}) p.push_back(v);  // 6, 7, 8
    auto tris = kDentTriangles;
    tris.insert(tris.begin(), {std::array<int, 3>{1, 5, 7}, {1, 0, 5}});
    for (const std::array<int, 3>& tr : {std::array<int, 3>{5, 0, 8}, {0, 6, 8}, {6, 5, 8}}) tris.push_back(tr);
    const auto in = mesh(p, tris);
    const auto r = tri2quad(in);
    check_result(in, r, false);
    CHECK(cases_run(r) == Cases{{"4cii_B21_type3_edge_point", 1}, {"4c_quad_to_grandparent", 1},
                                {"3_nonempty_triangle", 1}, {"3c_B22_pentagon_point", 1}, {"4c_convex_quad", 1}});
    const P2 &a = p[0], &b = p[1], &z = p[5];
    const int m = edge_point(r, p[0], p[1]);
    CHECK(fourth_corner(r, 5, 1, 7) == m);  // the leftover is (z, b, m)
    const std::vector<P2> region = {b, r.points[m], a, x, z};
    const Local l = local_result(r, region);
    CHECK(l.convex);
    CHECK(l.quads == 5);
    CHECK(l.steiner == 3);
    CHECK(l.area == Approx(poly_area(region) - poly_area({z, b, r.points[m]})));
    CHECK(r.quads.size() == kDentQuads + 5 + 1);
    CHECK(r.steiner == kDentSteiner + 3);
  }
  SECTION("3(b): a triangle parent of degree 2 and a non-empty triangle (B.1.2)") {
    // P = (A, B, C) below the root (B, A, z) and three triangles around y
    // across BC: the quadrilateral (A, B, X, C) around y, 5 quads and 3
    // points, no leftover; the root is then alone (Joe's split: 5 and 5).
    const std::vector<P2> p = {{0, 0}, {4, 0}, {2, 2}, {4, 3}, {2, -2}, {3.3, 1.7}};
    const auto in = mesh(p, {{1, 0, 4}, {0, 1, 2}, {2, 1, 5}, {1, 3, 5}, {3, 2, 5}});
    const auto r = tri2quad(in);
    check_result(in, r, false);
    CHECK(cases_run(r) == Cases{{"3_nonempty_triangle", 1}, {"3b_B12_quad_point", 1}, {"5bd_joe_split", 1}});
    const std::vector<P2> region = {p[0], p[1], p[3], p[2]};
    const Local l = local_result(r, region);
    CHECK(l.convex);
    CHECK(l.quads == 5);
    CHECK(l.steiner == 3);
    CHECK(l.area == Approx(poly_area(region)));
    CHECK(r.quads.size() == 5 + 5);
    CHECK(r.steiner == 3 + 5);
  }
  SECTION("4(c)(i): a degenerate quadrilateral and a non-convex pair below it (B.1.1)") {
    // P = (b, a, z) with m on (b, a) and the pair (z, a, x), (x, a, w),
    // reflex at a: the hexagon (b, m, a, w, x, z) closes with 2 + k quads
    // and k <= 3 points, no leftover; the root (b, z, t) is then alone
    // (Joe's split: 5 quads, 5 points).
    std::vector<P2> p = kDentPoints;
    const P2 x{0, -2.5}, w{-1, 1.5}, t{4.5, -2};
    for (const P2& v : {x, w, t}) p.push_back(v);  // 6, 7, 8
    auto tris = kDentTriangles;
    tris.insert(tris.begin(), {std::array<int, 3>{1, 5, 8}, {1, 0, 5}});
    tris.push_back({5, 0, 6});
    tris.push_back({6, 0, 7});
    const auto in = mesh(p, tris);
    const auto r = tri2quad(in);
    check_result(in, r, false);
    CHECK(cases_run(r) == Cases{{"4cii_B21_type3_edge_point", 1}, {"4c_quad_to_grandparent", 2},
                                {"4ci_4ciii_B11_hexagon", 1}, {"5bd_joe_split", 1}});
    const int m = edge_point(r, p[0], p[1]);
    const std::vector<P2> region = {p[1], r.points[m], p[0], w, x, p[5]};
    const Local l = local_result(r, region);
    CHECK(l.convex);
    CHECK(l.steiner <= 3);
    CHECK(l.quads == 2 + l.steiner);
    CHECK(l.area == Approx(poly_area(region)));
    CHECK(r.quads.size() == kDentQuads + l.quads + 5);
    CHECK(r.steiner == kDentSteiner + l.steiner + 5);
  }
  SECTION("4(c)(iii): a non-convex pair and a leaf, a hexagon or (cross-edge) a quadrilateral around C") {
    // P = (A, B, C) below the root (B, A, z), the pair (C, B, w), (C, w, x),
    // and the leaf (A, C, x2) (a hexagon, B.1.1) or (A, C, x) (a cross-edge
    // with the pair: the quadrilateral (A, B, w, x) around C, B.1.2). The
    // root is then alone (Joe's split: 5 quads, 5 points).
    const std::vector<P2> p = {{0, 0}, {4, 0}, {2, 2}, {4, 2}, {0.5, 3.2}, {2, -2}, {0.3, 1.5}};
    for (int cross = 0; cross < 2; ++cross) {
      INFO("cross-edge " << cross);
      const auto in = mesh(p, {{1, 0, 5}, {0, 1, 2}, {2, 1, 3}, {2, 3, 4}, {0, 2, cross ? 4 : 6}});
      const auto r = tri2quad(in);
      check_result(in, r, false);
      const std::vector<P2> region =
          cross ? std::vector<P2>{p[0], p[1], p[3], p[4]} : std::vector<P2>{p[0], p[1], p[3], p[4], p[2], p[6]};
      const Local l = local_result(r, region);
      CHECK(l.convex);
      CHECK(l.area == Approx(poly_area(region)));
      if (cross) {
        CHECK(cases_run(r) == Cases{{"4c_quad_to_grandparent", 1}, {"3b_B12_quad_point", 1}, {"5bd_joe_split", 1}});
        CHECK(l.quads == 5);
        CHECK(l.steiner == 3);
      } else {
        CHECK(cases_run(r) == Cases{{"4c_quad_to_grandparent", 1}, {"4ci_4ciii_B11_hexagon", 1}, {"5bd_joe_split", 1}});
        CHECK(l.steiner <= 3);
        CHECK(l.quads == 2 + l.steiner);
      }
      CHECK(r.quads.size() == l.quads + 5);
      CHECK(r.steiner == l.steiner + 5);
    }
  }
  SECTION("5(a): the root with two leaves (a pentagon) or a non-empty triangle") {
    const P2 A{0, 0}, B{4, 0};
    {
      // The pentagon (A, B, y, C, x): a point m on the root edge AB and
      // B.1.1 on the hexagon (A, m, B, y, C, x): 2 + k quads, 1 + k points.
      const std::vector<P2> p = {A, B, {2, 2}, {4, 2.5}, {0, 2.5}};
      const auto in = mesh(p, {{0, 1, 2}, {2, 1, 3}, {0, 2, 4}});
      const auto r = tri2quad(in);
      check_result(in, r, false);
      CHECK(cases_run(r) == Cases{{"5_B11_root_pentagon_edge_point", 1}});
      CHECK(steiner_on(r, A, B) == 1);
      CHECK(r.steiner <= 4);
      CHECK(r.quads.size() == 2 + r.steiner - 1);
      // --allow-outside: B.2.1 (type 1 here) and the leftover closed by a
      // point outside the domain (Fig. 3.16): 3 quads, 2 points.
      Tri2QuadOptions o;
      o.allow_outside = true;
      const auto r2 = tri2quad(in, o);
      check_result(in, r2, true);
      CHECK(cases_run(r2) == Cases{{"4b_B21_type1", 1}, {"5bd_outside_point", 1}});
      CHECK(r2.quads.size() == 3);
      CHECK(r2.steiner == 2);
      CHECK(r2.steiner_outside == 1);
    }
    {
      // The leaves share an edge: the non-empty triangle (A, B, y) around C;
      // m on AB makes the quadrilateral (A, m, B, y) around C (B.1.2, Fig.
      // 3.15): 5 quads, 4 points (in both modes: m stays on the edge).
      const P2 C{2, 1}, y{2, 3};
      const auto in = mesh({A, B, C, y}, {{0, 1, 2}, {2, 1, 3}, {0, 2, 3}});
      for (int outside = 0; outside < 2; ++outside) {
        Tri2QuadOptions o;
        o.allow_outside = outside == 1;
        const auto r = tri2quad(in, o);
        check_result(in, r, o.allow_outside);
        CHECK(cases_run(r) == Cases{{"3b_B12_quad_point", 1}});
        const Local l = local_result(r, {A, B, y});
        CHECK(l.convex);
        CHECK(l.quads == 5);
        CHECK(l.steiner == 4);
        CHECK(l.area == Approx(poly_area({A, B, y})));
        CHECK(steiner_on(r, A, B) == 1);
        CHECK(r.steiner_outside == 0);
      }
    }
  }
  SECTION("5(b): the root a degenerate quadrilateral with one leaf") {
    // The root P = (b, a, z) (root edge (z, b)) gets m on (b, a) and the
    // leaf (a, x, z). Default: a point on the root edge and B.1.1 on the
    // hexagon; --allow-outside: 4(a) (2 quads, 1 point) and the leftover
    // closed by a point outside: 3 quads, 2 points (Table 3.1).
    std::vector<P2> p = kDentPoints;
    const P2 x{-1, 0.3};
    p.push_back(x);
    auto tris = kDentTriangles;
    tris.insert(tris.begin(), std::array<int, 3>{1, 0, 5});
    tris.push_back({0, 6, 5});
    const auto in = mesh(p, tris);
    const auto r = tri2quad(in);
    check_result(in, r, false);
    CHECK(cases_run(r) ==
          Cases{{"4cii_B21_type3_edge_point", 1}, {"4c_quad_to_grandparent", 1}, {"5_B11_root_pentagon_edge_point", 1}});
    const int m = edge_point(r, p[0], p[1]);
    const std::vector<P2> region = {p[1], r.points[m], p[0], x, p[5]};
    const Local l = local_result(r, region);
    CHECK(l.convex);
    CHECK(l.area == Approx(poly_area(region)));
    CHECK(l.steiner <= 4);
    CHECK(l.quads == 2 + l.steiner - 1);
    CHECK(steiner_on(r, p[5], p[1]) == 1);
    Tri2QuadOptions o;
    o.allow_outside = true;
    const auto r2 = tri2quad(in, o);
    check_result(in, r2, true);
    CHECK(cases_run(r2) == Cases{{"4cii_B21_type3_edge_point", 1}, {"4c_quad_to_grandparent", 1},
                                 {"4b_B21_type1", 1}, {"5bd_outside_point", 1}});
    CHECK(r2.quads.size() == kDentQuads + 3);
    CHECK(r2.steiner == kDentSteiner + 2);
    CHECK(r2.steiner_outside == 1);
  }
  SECTION("4(c)(v)(a)-(c): two non-convex pairs with a cross-edge around C (B.2.2)") {
    // P = (A, B, C) below the root (B, A, z), the pairs (C, B, w1), (C, w1,
    // x) and (A, C, w2), (w2, C, x) meeting at (C, x): the pentagon (A, B,
    // w1, x, w2) around C. Here the leftover is (A, B, C) and B.1.1 closes
    // the hexagon left (2 + k quads, k <= 3 points).
    const std::vector<P2> p = {{0, 0}, {4, 0}, {1.75, 1.5}, {3.43, 2.12}, {3.68, 3.13}, {2, -2}, {-2.39, 2.92}};
    const auto in = mesh(p, {{1, 0, 5}, {0, 1, 2}, {2, 1, 3}, {2, 3, 4}, {0, 2, 6}, {6, 2, 4}});
    const auto r = tri2quad(in);
    check_result(in, r, false);
    CHECK(cases_run(r) ==
          Cases{{"4c_quad_to_grandparent", 2}, {"3c_B22_pentagon_point", 1}, {"4c_convex_quad", 1}});
    CHECK(fourth_corner(r, 0, 1, 5) == 2);
    const std::vector<P2> region = {p[0], p[1], p[3], p[4], p[6]};
    const Local l = local_result(r, region);
    CHECK(l.convex);
    CHECK(l.steiner <= 3);
    CHECK(l.quads == 2 + l.steiner);
    CHECK(l.area == Approx(poly_area(region) - poly_area({p[0], p[1], p[2]})));
    CHECK(r.quads.size() == l.quads + 1);
    CHECK(r.steiner == l.steiner);
  }
  SECTION("B.2.2 (3(c) without cross-edge): a pentagon with a point, its three cases") {
    // P = (A, B, C) below the root (B, A, z), the non-empty triangle
    // (C, B, X) around y and the leaf (A, C, x): the pentagon (A, B, X, C, x)
    // around y leaves a triangle on AB, which the root closes as one quad.
    const P2 A{0, 0}, B{4, 0}, z{2, -2};
    struct Form { const char* name; P2 y, C, X, x; };
    // (i) y sees AB: the leftover (A, B, y), B.1.1 on the hexagon left;
    // (ii) an ear on AB, B.1.2 on the quadrilateral with y (5 quads, 3
    // points); (iii) neither: the type-1 split of the centre triangle
    // (A, B, C) and B.1.2 on the quadrilateral holding y (6 quads, 4 points).
    const Form forms[] = {{"i", {2.61, 1.3}, {0.9, 2.62}, {2.79, 3.04}, {-1.1, 1.86}},
                          {"ii", {4.18, 0.85}, {3.16, 0.6}, {4.47, 1.18}, {1.64, 1.05}},
                          {"iii", {3.13, 1.36}, {2.06, 0.64}, {3.45, 2.51}, {1.05, 2.15}}};
    for (const Form& f : forms) {
      INFO("B.2.2 case " << f.name);
      const auto in = mesh({A, B, f.C, f.X, f.x, z, f.y},
                           {{1, 0, 5}, {0, 1, 2}, {2, 1, 6}, {1, 3, 6}, {3, 2, 6}, {0, 2, 4}});
      const auto r = tri2quad(in);
      check_result(in, r, false);
      const std::string form = f.name;
      CHECK(cases_run(r) == Cases{{"3_nonempty_triangle", 1},
                                  {form == "iii" ? "B22_middle_type1_B12" : "3c_B22_pentagon_point", 1},
                                  {"4c_convex_quad", 1}});
      const int apex = fourth_corner(r, 0, 1, 5);
      REQUIRE(apex >= 0);
      const std::vector<P2> region = {A, B, f.X, f.C, f.x};
      const Local l = local_result(r, region);
      CHECK(l.convex);
      CHECK(l.area == Approx(poly_area(region) - poly_area({A, B, r.points[apex]})));
      if (form == "i") {
        CHECK(apex == 6);
        CHECK(l.steiner <= 3);
        CHECK(l.quads == 2 + l.steiner);
      } else if (form == "ii") {
        CHECK((apex == 3 || apex == 4));
        CHECK(l.quads == 5);
        CHECK(l.steiner == 3);
      } else {
        REQUIRE(apex >= int(in.points.size()));
        CHECK(strictly_inside(A, B, f.C, r.points[apex]));
        CHECK(l.quads == 6);
        CHECK(l.steiner == 4);
      }
      CHECK(r.quads.size() == l.quads + 1);
      CHECK(r.steiner == l.steiner);
    }
  }
}
