// tri2quad: the small-polygon constructions (appendix B) one by one, the
// steps on hand-made meshes, and properties on thousands of random
// constrained Delaunay triangulations (CGAL) with holes and interior
// constraint loops.
#include "quad/quality.hpp"
#include "quad/tri2quad.hpp"
#include "quad/tri2quad_polygons.hpp"
#include "util/error.hpp"

#include <CGAL/Constrained_Delaunay_triangulation_2.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Triangulation_face_base_with_info_2.h>

#include <catch2/catch.hpp>

#include <cmath>
#include <list>
#include <map>
#include <random>
#include <set>

using namespace imgmesh;
using t2q::LocalPatch;
using t2q::P2;

namespace {

constexpr double kPi = 3.14159265358979323846;

double poly_area(const std::vector<P2>& v) {
  double a = 0;
  for (std::size_t i = 0; i < v.size(); ++i)
    a += v[i][0] * v[(i + 1) % v.size()][1] - v[(i + 1) % v.size()][0] * v[i][1];
  return a / 2;
}

// Quads of a patch: all strictly convex (exact) and their areas add up to
// `area`; every new point used.
void check_patch(const LocalPatch& lp, double area, std::size_t quads_max, std::size_t points_max) {
  double sum = 0;
  for (const auto& q : lp.quads) {
    CHECK(is_strictly_convex(lp.p[q[0]], lp.p[q[1]], lp.p[q[2]], lp.p[q[3]]));
    sum += quad_area(lp.p[q[0]], lp.p[q[1]], lp.p[q[2]], lp.p[q[3]]);
  }
  CHECK(sum == Approx(area).epsilon(1e-9));
  CHECK(lp.quads.size() <= quads_max);
  std::size_t fresh = 0;
  for (int g : lp.gid) fresh += g < 0;
  CHECK(fresh <= points_max);
  // Edge-to-edge inside the patch: no directed edge twice.
  std::set<std::pair<int, int>> seen;
  for (const auto& q : lp.quads)
    for (int k = 0; k < 4; ++k) CHECK(seen.insert({q[k], q[(k + 1) % 4]}).second);
}

LocalPatch patch_of(const std::vector<P2>& v) {
  LocalPatch lp;
  for (std::size_t i = 0; i < v.size(); ++i) lp.add_known(v[i], int(i));
  return lp;
}

t2q::Ring ring(int n) {
  t2q::Ring r;
  for (int i = 0; i < n; ++i) r.push_back(i);
  return r;
}

// A random simple (star-shaped) polygon around the origin.
std::vector<P2> random_star(std::mt19937& g, int n, double rmin, double rmax) {
  std::uniform_real_distribution<double> U(0, 1);
  std::vector<double> ang;
  for (int i = 0; i < n; ++i) ang.push_back(U(g) * 2 * kPi);
  std::sort(ang.begin(), ang.end());
  std::vector<P2> v;
  for (double a : ang) {
    const double r = rmin + (rmax - rmin) * U(g);
    v.push_back({r * std::cos(a), r * std::sin(a)});
  }
  return v;
}

} // namespace

TEST_CASE("B.1.1: random hexagons get at most 5 strictly convex quads and 3 points", "[tri2quad][B11]") {
  std::mt19937 g(11);
  int done = 0, tried = 0, reflex3 = 0;
  for (int it = 0; it < 3000; ++it) {
    auto v = random_star(g, 6, 0.2, 1.0);
    if (!t2q::simple_ccw(v)) continue;
    int reflex = 0;
    for (int i = 0; i < 6; ++i) reflex += t2q::orient(v[(i + 5) % 6], v[i], v[(i + 1) % 6]) <= 0;
    reflex3 += reflex == 3;
    ++tried;
    LocalPatch lp = patch_of(v);
    if (t2q::hexagon(lp, ring(6))) {
      ++done;
      check_patch(lp, poly_area(v), 5, 3);
      // Euler: a hexagon with k interior points has 2 + k quads.
      CHECK(lp.quads.size() == 2 + (lp.p.size() - 6));
    }
  }
  CHECK(reflex3 > 0);
  // The thesis's lemma says always; our construction may miss rare ones
  // (the caller then falls back), but not many.
  WARN("B.1.1: " << done << " of " << tried << " random hexagons");
  CHECK(done == tried);
}

TEST_CASE("B.1.2: quadrilateral with an interior point, convex, kernel and arm cases", "[tri2quad][B12]") {
  std::mt19937 g(12);
  std::uniform_real_distribution<double> U(0, 1);
  int convex = 0, reflex = 0, ok_convex = 0, ok_reflex = 0;
  for (int it = 0; it < 3000; ++it) {
    auto v = random_star(g, 4, 0.1, 1.0);
    if (!t2q::simple_ccw(v)) continue;
    // A random interior point (rejection sampling in the bounding box).
    P2 q{};
    bool found = false;
    for (int k = 0; k < 100 && !found; ++k) {
      q = {2 * U(g) - 1, 2 * U(g) - 1};
      // Inside: fan triangles from v0 (the quad is star-shaped from its kernel,
      // use the ray test instead).
      int crossings = 0;
      for (int i = 0; i < 4; ++i) {
        const P2 &a = v[i], &b = v[(i + 1) % 4];
        if ((a[1] > q[1]) != (b[1] > q[1]) && q[0] < a[0] + (q[1] - a[1]) * (b[0] - a[0]) / (b[1] - a[1])) ++crossings;
      }
      found = crossings % 2 == 1;
      for (int i = 0; i < 4 && found; ++i) found = t2q::orient(v[i], v[(i + 1) % 4], q) != 0;
    }
    if (!found) continue;
    bool is_convex = true;
    for (int i = 0; i < 4; ++i) is_convex = is_convex && t2q::orient(v[(i + 3) % 4], v[i], v[(i + 1) % 4]) > 0;
    (is_convex ? convex : reflex)++;
    LocalPatch lp = patch_of(v);
    const int qi = lp.add_known(q, 4);
    if (t2q::quad_with_point(lp, ring(4), qi)) {
      (is_convex ? ok_convex : ok_reflex)++;
      check_patch(lp, poly_area(v), 5, 3);
      CHECK(lp.quads.size() == 5);  // forced by Euler
    }
  }
  CHECK(convex > 100);
  CHECK(reflex > 100);
  CHECK(ok_convex == convex);
  CHECK(ok_reflex >= reflex * 95 / 100);
}

TEST_CASE("B.2.1: pentagon edge types leave a triangle on the outgoing edge", "[tri2quad][B21]") {
  // Type 1: the outgoing edge in the centre triangle of a convex pentagon
  // whose ears make the ear shortcut impossible.
  SECTION("regular pentagon: an ear (no point) suffices") {
    std::vector<P2> v;
    for (int i = 0; i < 5; ++i) v.push_back({std::cos(2 * kPi * i / 5 - kPi / 2), std::sin(2 * kPi * i / 5 - kPi / 2)});
    LocalPatch lp = patch_of(v);
    int kind = -1;
    const int apex = t2q::pentagon(lp, ring(5), &kind);
    REQUIRE(apex >= 0);
    CHECK(kind == 0);
    const double tri = poly_area({lp.p[0], lp.p[1], lp.p[apex]});
    CHECK(tri > 0);
    check_patch(lp, poly_area(v) - tri, 1, 0);
  }
  SECTION("reflex corners next to the outgoing edge force type 1 or 2") {
    std::mt19937 g(21);
    int seen[4] = {0, 0, 0, 0}, fails = 0, total = 0;
    for (int it = 0; it < 4000; ++it) {
      auto v = random_star(g, 5, 0.15, 1.0);
      if (!t2q::simple_ccw(v)) continue;
      ++total;
      LocalPatch lp = patch_of(v);
      int kind = -1;
      const int apex = t2q::pentagon(lp, ring(5), &kind);
      if (apex < 0) { ++fails; continue; }
      ++seen[kind];
      const double tri = poly_area({lp.p[0], lp.p[1], lp.p[apex]});
      CHECK(t2q::orient(lp.p[0], lp.p[1], lp.p[apex]) > 0);
      // Types 1 and 2 as in the lemma; the type-3 stand-in may need the
      // hexagon's 3 points.
      if (kind < 3) check_patch(lp, poly_area(v) - tri, 3, 2);
      else check_patch(lp, poly_area(v) - tri, 5, 4);
    }
    CHECK(seen[0] > 0);
    CHECK(seen[1] > 0);
    CHECK(seen[2] > 0);
    CHECK(seen[3] > 0);
    CHECK(fails == 0);
  }
}

TEST_CASE("B.3.1: heptagons, both forms (ear and the p1-p3 path)", "[tri2quad][B31]") {
  std::mt19937 g(31);
  int seen[2] = {0, 0}, fails = 0, total = 0;
  for (int it = 0; it < 3000; ++it) {
    auto v = random_star(g, 7, 0.3, 1.0);
    if (!t2q::simple_ccw(v)) continue;
    ++total;
    LocalPatch lp = patch_of(v);
    int kind = -1;
    const int apex = t2q::heptagon(lp, ring(7), &kind);
    if (apex < 0) { ++fails; continue; }
    ++seen[kind];
    CHECK(t2q::orient(lp.p[0], lp.p[1], lp.p[apex]) > 0);
    const double tri = poly_area({lp.p[0], lp.p[1], lp.p[apex]});
    // Lemma B.3.1: six quads and four points at most (ear form: 5 and 3).
    check_patch(lp, poly_area(v) - tri, 6, 4);
  }
  CHECK(seen[0] > 0);
  CHECK(seen[1] > 0);
  // Not every heptagon is covered (the caller then closes with a degenerate
  // quad or the safe split), but most are.
  CHECK(fails < total / 5);
  WARN("heptagons: ear " << seen[0] << ", path " << seen[1] << ", not covered " << fails << " of " << total);
}

TEST_CASE("Joe's and de Berg's triangle splits", "[tri2quad][splits]") {
  std::mt19937 g(31);
  std::uniform_real_distribution<double> U(-1, 1);
  for (int it = 0; it < 2000; ++it) {
    P2 a{U(g), U(g)}, b{U(g), U(g)}, c{U(g), U(g)};
    if (t2q::orient(a, b, c) < 0) std::swap(b, c);
    if (!t2q::good_triangle(a, b, c)) continue;
    {
      LocalPatch lp;
      const int ia = lp.add_known(a, 0), ib = lp.add_known(b, 1), ic = lp.add_known(c, 2);
      const int m = lp.add_new({(b[0] + c[0]) / 2, (b[1] + c[1]) / 2});
      REQUIRE(t2q::joe_split(lp, ia, ib, m, ic));
      check_patch(lp, poly_area({a, b, c}), 5, 5);
    }
    {
      LocalPatch lp;
      const int ia = lp.add_known(a, 0), ib = lp.add_known(b, 1), ic = lp.add_known(c, 2);
      const int mab = lp.add_new({(a[0] + b[0]) / 2, (a[1] + b[1]) / 2});
      const int mbc = lp.add_new({(b[0] + c[0]) / 2, (b[1] + c[1]) / 2});
      const int mca = lp.add_new({(c[0] + a[0]) / 2, (c[1] + a[1]) / 2});
      REQUIRE(t2q::deberg_split(lp, ia, ib, ic, mab, mbc, mca));
      check_patch(lp, poly_area({a, b, c}), 3, 4);
    }
  }
}

// ---------------------------------------------------------------- meshes

namespace {

struct Check {
  std::size_t quads = 0, steiner = 0, bound_q = 0, bound_s = 0;
};

// Properties of a result against its input: strictly convex quads,
// conforming (each directed edge once, each interior edge in two quads),
// area, input vertices and every constraint kept as a chain of quad edges,
// and the size bounds.
// Largest excess over the size bounds seen (must stay <= 0).
long small_excess_q = -1000000, small_excess_s = -1000000;

void check_result(const Tri2QuadInput& in, const Tri2QuadResult& r, bool allow_outside) {
  const auto& P = r.points;
  REQUIRE(P.size() == in.points.size() + r.steiner);
  for (std::size_t i = 0; i < in.points.size(); ++i) REQUIRE(P[i] == in.points[i]);
  std::size_t non_convex = 0;
  double qa = 0, ta = 0;
  std::map<std::pair<int, int>, int> directed;
  std::set<int> used;
  for (const auto& q : r.quads) {
    non_convex += !is_strictly_convex(P[q[0]], P[q[1]], P[q[2]], P[q[3]]);
    qa += quad_area(P[q[0]], P[q[1]], P[q[2]], P[q[3]]);
    for (int k = 0; k < 4; ++k) {
      ++directed[{q[k], q[(k + 1) % 4]}];
      used.insert(q[k]);
    }
  }
  CHECK(non_convex == 0);
  for (const auto& t : in.triangles) {
    ta += std::fabs(poly_area({in.points[t[0]], in.points[t[1]], in.points[t[2]]}));
    for (int v : t) CHECK(used.count(v) == 1);
  }
  // With --allow-outside one quad per outer component may stick out.
  if (!allow_outside) CHECK(qa == Approx(ta).epsilon(1e-9));
  else CHECK(qa >= ta * (1 - 1e-9));
  std::size_t repeated = 0, boundary = 0;
  std::map<int, std::vector<int>> adj;
  for (const auto& [e, n] : directed) {
    repeated += n > 1;
    if (!directed.count({e.second, e.first})) ++boundary;
    adj[e.first].push_back(e.second);
    adj[e.second].push_back(e.first);
  }
  CHECK(repeated == 0);
  // Every constraint / boundary edge of the input is a chain of quad edges
  // through points on the segment.
  std::set<std::pair<int, int>> input_boundary;
  {
    std::map<std::pair<int, int>, int> te;
    for (const auto& t : in.triangles)
      for (int k = 0; k < 3; ++k) ++te[{std::min(t[k], t[(k + 1) % 3]), std::max(t[k], t[(k + 1) % 3])}];
    for (const auto& [e, n] : te) if (n == 1) input_boundary.insert(e);
  }
  std::vector<std::array<int, 2>> segs = in.constraints;
  for (const auto& e : input_boundary) segs.push_back({e.first, e.second});
  std::size_t lost = 0;
  double boundary_len_in = 0;
  for (const auto& s : segs) {
    const P2 a = P[s[0]], b = P[s[1]];
    const double len2 = (b[0] - a[0]) * (b[0] - a[0]) + (b[1] - a[1]) * (b[1] - a[1]);
    int cur = s[0], prev = -1, steps = 0;
    while (cur != s[1] && steps < 50) {
      int next = -1;
      for (int w : adj[cur]) {
        if (w == prev) continue;
        if (w == s[1]) { next = w; break; }
        const P2 p = P[w];
        const double cr = (b[0] - a[0]) * (p[1] - a[1]) - (b[1] - a[1]) * (p[0] - a[0]);
        const double t = ((p[0] - a[0]) * (b[0] - a[0]) + (p[1] - a[1]) * (b[1] - a[1])) / len2;
        const double tc = ((P[cur][0] - a[0]) * (b[0] - a[0]) + (P[cur][1] - a[1]) * (b[1] - a[1])) / len2;
        if (std::size_t(w) >= in.points.size() && std::fabs(cr) <= 1e-9 * len2 && t > tc && t < 1) next = w;
      }
      if (next < 0) break;
      prev = cur;
      cur = next;
      ++steps;
    }
    lost += cur != s[1];
  }
  for (const auto& e : input_boundary)
    boundary_len_in += std::hypot(P[e.second][0] - P[e.first][0], P[e.second][1] - P[e.first][1]);
  CHECK(lost <= r.steiner_outside);
  double boundary_len_out = 0;
  for (const auto& [e, n] : directed)
    if (!directed.count({e.second, e.first}))
      boundary_len_out += std::hypot(P[e.second][0] - P[e.first][0], P[e.second][1] - P[e.first][1]);
  if (!allow_outside) CHECK(boundary_len_out == Approx(boundary_len_in).epsilon(1e-9));
  // The size bounds of the thesis, for every t (small meshes included).
  CHECK(r.quads.size() <= r.quad_bound());
  CHECK(r.steiner <= r.steiner_bound(allow_outside));
  small_excess_q = std::max(small_excess_q, long(r.quads.size()) - long(r.quad_bound()));
  small_excess_s = std::max(small_excess_s, long(r.steiner) - long(r.steiner_bound(allow_outside)));
  if (!allow_outside) CHECK(r.steiner_outside == 0);
}

struct FaceInfo { int nesting = -1; int region = 0; bool in_domain() const { return nesting % 2 == 1; } };
using K = CGAL::Exact_predicates_inexact_constructions_kernel;
using Fbb = CGAL::Triangulation_face_base_with_info_2<FaceInfo, K>;
using Fb = CGAL::Constrained_triangulation_face_base_2<K, Fbb>;
using Tds = CGAL::Triangulation_data_structure_2<CGAL::Triangulation_vertex_base_2<K>, Fb>;
using CDT = CGAL::Constrained_Delaunay_triangulation_2<K, Tds, CGAL::Exact_predicates_tag>;

// Nesting levels across the outer boundary and holes (odd = domain); the
// interior loops are constraints that do not change the level (they only
// give the faces a different region attribute).
void mark(CDT& cdt, const std::set<std::pair<K::Point_2, K::Point_2>>& walls,
          const std::set<std::pair<K::Point_2, K::Point_2>>& loops) {
  for (auto f = cdt.all_faces_begin(); f != cdt.all_faces_end(); ++f) f->info().nesting = -1;
  std::list<std::pair<CDT::Face_handle, std::pair<int, int>>> border;
  border.push_back({cdt.infinite_face(), {0, 0}});
  while (!border.empty()) {
    auto [start, lv] = border.front();
    border.pop_front();
    if (start->info().nesting != -1) continue;
    std::list<std::pair<CDT::Face_handle, int>> q{{start, lv.second}};
    while (!q.empty()) {
      auto [f, reg] = q.front();
      q.pop_front();
      if (f->info().nesting != -1) continue;
      f->info().nesting = lv.first;
      f->info().region = reg;
      for (int i = 0; i < 3; ++i) {
        auto n = f->neighbor(i);
        if (n->info().nesting != -1) continue;
        const auto a = f->vertex(f->cw(i))->point(), b = f->vertex(f->ccw(i))->point();
        const auto key = a < b ? std::make_pair(a, b) : std::make_pair(b, a);
        if (walls.count(key)) border.push_back({n, {lv.first + 1, 0}});
        else if (loops.count(key)) border.push_front({n, {lv.first, reg + 1}});
        else q.push_back({n, reg});
      }
    }
  }
}

Tri2QuadInput random_cdt(std::mt19937& g, int npoints, int nholes, int nloops) {
  std::uniform_real_distribution<double> U(0, 1);
  CDT cdt;
  std::set<std::pair<K::Point_2, K::Point_2>> walls, loops;
  auto add_loop = [&](const std::vector<P2>& v, double cx, double cy, bool wall) {
    for (std::size_t i = 0; i < v.size(); ++i) {
      K::Point_2 a(cx + v[i][0], cy + v[i][1]), b(cx + v[(i + 1) % v.size()][0], cy + v[(i + 1) % v.size()][1]);
      cdt.insert_constraint(a, b);
      (wall ? walls : loops).insert(a < b ? std::make_pair(a, b) : std::make_pair(b, a));
    }
  };
  add_loop(random_star(g, 5 + int(U(g) * 10), 0.38, 0.5), 0.5, 0.5, true);
  // Four slots for holes and loops, well apart.
  const double sx[4] = {0.35, 0.65, 0.35, 0.65}, sy[4] = {0.35, 0.35, 0.65, 0.65};
  int slot = 0;
  for (int h = 0; h < nholes && slot < 4; ++h, ++slot) add_loop(random_star(g, 3 + int(U(g) * 4), 0.04, 0.1), sx[slot], sy[slot], true);
  for (int l = 0; l < nloops && slot < 4; ++l, ++slot) add_loop(random_star(g, 3 + int(U(g) * 5), 0.05, 0.11), sx[slot], sy[slot], false);
  for (int i = 0; i < npoints; ++i) {
    const double r = 0.36 * std::sqrt(U(g)), a = 2 * kPi * U(g);
    cdt.insert(K::Point_2(0.5 + r * std::cos(a), 0.5 + r * std::sin(a)));
  }
  mark(cdt, walls, loops);
  Tri2QuadInput in;
  std::map<CDT::Vertex_handle, int> id;
  auto vid = [&](CDT::Vertex_handle v) {
    auto it = id.find(v);
    if (it != id.end()) return it->second;
    const int k = int(in.points.size());
    id[v] = k;
    in.points.push_back({v->point().x(), v->point().y()});
    return k;
  };
  for (auto f = cdt.finite_faces_begin(); f != cdt.finite_faces_end(); ++f) {
    if (!f->info().in_domain()) continue;
    in.triangles.push_back({vid(f->vertex(0)), vid(f->vertex(1)), vid(f->vertex(2))});
    in.region.push_back(f->info().region);
  }
  // Interior constraint edges (the loops, as the CDT split them).
  for (auto e = cdt.finite_edges_begin(); e != cdt.finite_edges_end(); ++e) {
    if (!cdt.is_constrained(*e)) continue;
    const auto f = e->first;
    const auto n = f->neighbor(e->second);
    if (!f->info().in_domain() || cdt.is_infinite(n) || !n->info().in_domain()) continue;
    in.constraints.push_back({id.at(f->vertex(f->cw(e->second))), id.at(f->vertex(f->ccw(e->second)))});
  }
  return in;
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

TEST_CASE("Random constrained Delaunay triangulations: all guarantees", "[tri2quad][property]") {
  std::mt19937 g(2006);
  std::size_t total_t = 0, total_q = 0, total_s = 0, fallbacks = 0, meshes = 0;
  std::map<std::string, std::size_t> cases;
  for (int it = 0; it < 2500; ++it) {
    const int npts = 5 + int(g() % 300);
    const int holes = int(g() % 3), loops = int(g() % 3);
    const Tri2QuadInput in = random_cdt(g, npts, holes, loops);
    if (in.triangles.empty()) continue;
    const bool outside = (it % 4) == 3;
    Tri2QuadOptions o;
    o.allow_outside = outside;
    INFO("mesh " << it << ": " << in.triangles.size() << " triangles, " << holes << " holes, " << loops << " loops");
    const auto r = tri2quad(in, o);
    std::string used;
    for (const auto& [n, c] : r.cases) if (c) used += n + "=" + std::to_string(c) + " ";
    INFO("h " << r.components << " cases: " << used);
    check_result(in, r, outside);
    // Region attributes are carried: one per quad, values from the input.
    REQUIRE(r.region.size() == r.quads.size());
    total_t += r.triangles;
    total_q += r.quads.size();
    total_s += r.steiner;
    for (const auto& [n, c] : r.cases) cases[n] += c;
    ++meshes;
  }
  fallbacks = cases["fallback_split"];
  INFO("meshes " << meshes << " t " << total_t << " q " << total_q << " s " << total_s << " fallbacks " << fallbacks);
  CHECK(meshes > 2000);
  CHECK(double(total_q) / double(total_t) < 1.0);
  WARN("random CDTs: quads/t = " << double(total_q) / double(total_t) << ", Steiner/t = "
                                 << double(total_s) / double(total_t) << ", fallback splits " << fallbacks);
  std::string s;
  for (const auto& [n, c] : cases) s += n + "=" + std::to_string(c) + " ";
  WARN(s);
  // Every step and case ran somewhere in the sample.
  for (const char* name : {"4c_convex_quad", "4c_quad_to_grandparent", "B21_pentagon_ear", "4b_B21_type1",
                           "4cii_B21_type2", "B21_type3_apex_hexagon", "4ci_4ciii_B11_hexagon", "4cvf_B31_heptagon",
                           "3_nonempty_triangle", "3b_B12_quad_point", "3c_B22_pentagon_point", "5bd_joe_split",
                           "5bd_outside_point", "5c_B12_nested", "3_3_repair_split", "5_B11_root_pentagon_edge_point",
                           "B22_middle_type1_B12", "4civ_hexagon_point", "4civ_B21_B12_pair_nonempty",
                           "3d_edge_point_B12_twice", "3c_4cvde_leftover_B12", "B31_heptagon_edge_point"}) {
    INFO(name);
    CHECK(cases[name] > 0);
  }
  WARN("largest excess over the bounds: quads " << small_excess_q << ", Steiner " << small_excess_s
                                                << "; size-bound retries " << cases["size_bound_retry"]);
  CHECK(small_excess_q <= 0);
  CHECK(small_excess_s <= 0);
  // The bounds hold by construction: the rerun from other root edges (a
  // safety net) is never needed.
  CHECK(cases["size_bound_retry"] == 0);
}

// Small meshes are where the additive 4h has the least room: the exact
// bounds (and every other guarantee) on thousands of them, both modes.
TEST_CASE("Small random constrained Delaunay triangulations: exact size bounds", "[tri2quad][property][small]") {
  std::mt19937 g(31415);
  std::size_t meshes = 0, retries = 0;
  for (int it = 0; it < 3000; ++it) {
    const int npts = int(g() % 40);
    const int holes = int(g() % 3), loops = int(g() % 3);
    const Tri2QuadInput in = random_cdt(g, npts, holes, loops);
    if (in.triangles.empty()) continue;
    for (int o = 0; o < 2; ++o) {
      Tri2QuadOptions opt;
      opt.allow_outside = o == 1;
      INFO("mesh " << it << ": " << in.triangles.size() << " triangles, allow_outside " << o);
      const auto r = tri2quad(in, opt);
      check_result(in, r, opt.allow_outside);
      REQUIRE(r.region.size() == r.quads.size());
      for (const auto& [n, c] : r.cases) if (n == "size_bound_retry") retries += c;
      ++meshes;
    }
  }
  CHECK(meshes > 5000);
  CHECK(retries == 0);
  WARN("small random CDTs: " << meshes << " runs, size-bound retries " << retries);
}

// Diagnostic (hidden): excess over the size bounds on many small meshes,
// with the cases used by the worst ones.
TEST_CASE("size bound slack on small meshes", "[.slack]") {
  std::mt19937 g(4242);
  long wq = -1000, ws = -1000;
  std::size_t over_q = 0, over_s = 0, n = 0, raw_over = 0;
  long raw_q = -1000, raw_s = -1000;
  std::map<std::string, std::size_t> over_cases;
  int printed = 0;
  for (int it = 0; it < 20000; ++it) {
    const int npts = int(g() % 40);
    const int holes = int(g() % 3), loops = int(g() % 3);
    const Tri2QuadInput in = random_cdt(g, npts, holes, loops);
    if (in.triangles.empty()) continue;
    for (int o = 0; o < 4; ++o) {
      Tri2QuadOptions opt;
      opt.allow_outside = o % 2 == 1;
      opt.size_retry = o >= 2;
      const auto r = tri2quad(in, opt);
      ++n;
      if (!opt.size_retry) {
        raw_q = std::max(raw_q, long(r.quads.size()) - long(r.quad_bound()));
        raw_s = std::max(raw_s, long(r.steiner) - long(r.steiner_bound(opt.allow_outside)));
        const bool over = r.quads.size() > r.quad_bound() || r.steiner > r.steiner_bound(opt.allow_outside);
        raw_over += over;
        if (over) {
          std::string used;
          for (const auto& [nm, c] : r.cases) if (c) { used += nm + "=" + std::to_string(c) + " "; over_cases[nm] += 1; }
          if (printed++ < 30)
            std::printf("it %d o %d t %zu h %zu q %zu/%zu s %zu/%zu: %s\n", it, o, r.triangles, r.components,
                        r.quads.size(), r.quad_bound(), r.steiner, r.steiner_bound(opt.allow_outside), used.c_str());
        }
        continue;
      }
      const long eq = long(r.quads.size()) - long(r.quad_bound());
      const long es = long(r.steiner) - long(r.steiner_bound(opt.allow_outside));
      wq = std::max(wq, eq);
      ws = std::max(ws, es);
      if (eq > 0 || es > 0) {
        over_q += eq > 0;
        over_s += es > 0;
        std::string used;
        for (const auto& [nm, c] : r.cases) if (c) { used += nm + "=" + std::to_string(c) + " "; over_cases[nm] += 1; }
        if (printed++ < 30)
          std::printf("it %d o %d t %zu h %zu q %zu/%zu s %zu/%zu: %s\n", it, o, r.triangles, r.components,
                      r.quads.size(), r.quad_bound(), r.steiner, r.steiner_bound(opt.allow_outside), used.c_str());
      }
    }
  }
  std::printf("runs %zu worst excess q %ld s %ld; over q %zu over s %zu\n", n / 2, wq, ws, over_q, over_s);
  std::printf("without retries: worst excess q %ld s %ld, runs over a bound %zu\n", raw_q, raw_s, raw_over);
  for (const auto& [nm, c] : over_cases) std::printf("  %s %zu\n", nm.c_str(), c);
}

// Diagnostic (hidden): B.1.1 on spikier random hexagons.
TEST_CASE("B.1.1 success rate on spiky hexagons", "[.hexrate]") {
  std::mt19937 g(77);
  int done = 0, tried = 0, r3 = 0, r3done = 0;
  for (int it = 0; it < 40000; ++it) {
    auto v = random_star(g, 6, 0.03, 1.0);
    if (!t2q::simple_ccw(v)) continue;
    int reflex = 0;
    for (int i = 0; i < 6; ++i) reflex += t2q::orient(v[(i + 5) % 6], v[i], v[(i + 1) % 6]) <= 0;
    ++tried;
    LocalPatch lp = patch_of(v);
    const bool ok = t2q::hexagon(lp, ring(6));
    done += ok;
    if (reflex == 3) { ++r3; r3done += ok; }
  }
  std::printf("spiky hexagons: %d of %d; with 3 reflex corners %d of %d\n", done, tried, r3done, r3);
}
