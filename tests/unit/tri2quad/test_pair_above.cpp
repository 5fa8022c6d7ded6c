// --pair-above (lib/tri2quad/pair_above.cpp).
#include "tri2quad_test_support.hpp"

#include "quad/quality.hpp"
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

// The output segments are quad edges, none twice, each on an input
// constraint or boundary edge, and together exactly as long as those.
void check_segments(const Tri2QuadInput& in, const Tri2QuadResult& r) {
  const auto& P = r.points;
  std::set<std::pair<int, int>> quad_edges, seen;
  for (const auto& q : r.quads)
    for (int k = 0; k < 4; ++k) quad_edges.insert({std::min(q[k], q[(k + 1) % 4]), std::max(q[k], q[(k + 1) % 4])});
  std::map<std::pair<int, int>, int> te;
  for (const auto& t : in.triangles)
    for (int k = 0; k < 3; ++k) ++te[{std::min(t[k], t[(k + 1) % 3]), std::max(t[k], t[(k + 1) % 3])}];
  std::set<std::pair<int, int>> input;
  for (const auto& [e, n] : te) if (n == 1) input.insert(e);
  for (const auto& c : in.constraints) input.insert({std::min(c[0], c[1]), std::max(c[0], c[1])});
  double len_in = 0, len_out = 0;
  for (const auto& e : input) len_in += std::hypot(P[e.second][0] - P[e.first][0], P[e.second][1] - P[e.first][1]);
  std::size_t not_edge = 0, twice = 0, off = 0;
  for (const auto& s : r.segments) {
    const std::pair<int, int> e{std::min(s[0], s[1]), std::max(s[0], s[1])};
    not_edge += !quad_edges.count(e);
    twice += !seen.insert(e).second;
    len_out += std::hypot(P[e.second][0] - P[e.first][0], P[e.second][1] - P[e.first][1]);
    bool on = false;  // both ends on one input segment
    for (const auto& c : input) {
      const P2 a = P[c.first], b = P[c.second];
      const double len2 = (b[0] - a[0]) * (b[0] - a[0]) + (b[1] - a[1]) * (b[1] - a[1]);
      auto inside = [&](const P2& p) {
        const double cr = (b[0] - a[0]) * (p[1] - a[1]) - (b[1] - a[1]) * (p[0] - a[0]);
        const double t = ((p[0] - a[0]) * (b[0] - a[0]) + (p[1] - a[1]) * (b[1] - a[1])) / len2;
        return std::fabs(cr) <= 1e-9 * len2 && t >= -1e-12 && t <= 1 + 1e-12;
      };
      if (inside(P[e.first]) && inside(P[e.second])) { on = true; break; }
    }
    off += !on;
  }
  CHECK(not_edge == 0);
  CHECK(twice == 0);
  CHECK(off == 0);
  CHECK(len_out == Approx(len_in).epsilon(1e-9));
}

// An n x n grid of unit squares, each split by its "/" diagonal (or, with
// g, by a random one), the boundary as constraint segments.
Tri2QuadInput square_grid(int n, std::mt19937* g = nullptr) {
  Tri2QuadInput in;
  for (int y = 0; y <= n; ++y)
    for (int x = 0; x <= n; ++x) in.points.push_back({double(x), double(y)});
  auto id = [&](int x, int y) { return y * (n + 1) + x; };
  for (int y = 0; y < n; ++y)
    for (int x = 0; x < n; ++x) {
      const int a = id(x, y), b = id(x + 1, y), c = id(x + 1, y + 1), d = id(x, y + 1);
      if (g && (*g)() % 2) {
        in.triangles.push_back({a, b, d});
        in.triangles.push_back({b, c, d});
      } else {
        in.triangles.push_back({a, b, c});
        in.triangles.push_back({a, c, d});
      }
    }
  return in;
}

} // namespace

TEST_CASE("pairs first (--pair-above): every guarantee on random meshes", "[tri2quad][pairs][property]") {
  std::mt19937 g(1998);
  std::size_t meshes = 0, pairs = 0, returned = 0, abandoned = 0, total_q = 0, plain_q = 0;
  for (int it = 0; it < 700; ++it) {
    const int npts = 5 + int(g() % 250);
    const int holes = int(g() % 3), loops = int(g() % 3);
    const Tri2QuadInput in = random_cdt(g, npts, holes, loops);
    if (in.triangles.empty()) continue;
    Tri2QuadOptions o;
    o.pair_above = it % 2 ? 20 : 30;  // Delaunay pairs are seldom better
    o.allow_outside = it % 4 == 3;
    INFO("mesh " << it << ": " << in.triangles.size() << " triangles, " << holes << " holes, " << loops << " loops");
    const auto r = tri2quad(in, o);
    check_result(in, r, o.allow_outside);
    if (!o.allow_outside) check_segments(in, r);
    REQUIRE(r.region.size() == r.quads.size());
    std::map<std::string, std::size_t> c(r.cases.begin(), r.cases.end());
    pairs += c["pairs_first"];
    returned += c["pairs_returned"];
    abandoned += c["pairs_first_abandoned"];
    total_q += r.quads.size();
    plain_q += tri2quad(in, {}).quads.size();
    ++meshes;
  }
  WARN("pairs first on " << meshes << " random CDTs: " << pairs << " pairs, " << returned << " returned, "
                         << abandoned << " abandoned; quads " << total_q << " (plain " << plain_q << ")");
  CHECK(meshes > 500);
  CHECK(pairs > 0);
  // Groups left odd by the greedy pairs were joined to the boundary.
  CHECK(returned > 0);
}

TEST_CASE("pairs first on a square grid: every square comes back, where the BFS pairing shears", "[tri2quad][pairs]") {
  std::mt19937 g(12);
  for (int variant = 0; variant < 2; ++variant) {
    const int n = 24;
    const Tri2QuadInput in = square_grid(n, variant ? &g : nullptr);
    Tri2QuadOptions o;
    o.pair_above = 40;
    const auto r = tri2quad(in, o);
    check_result(in, r, false);
    check_segments(in, r);
    CHECK(r.quads.size() == std::size_t(n * n));
    CHECK(r.steiner == 0);
    double worst = 45;
    for (const auto& q : r.quads) worst = std::min(worst, joe_mu(r.points[q[0]], r.points[q[1]], r.points[q[2]], r.points[q[3]]));
    CHECK(worst > 45 - 1e-9);
    // The thesis's BFS pairing alone leaves parallelograms (mu 18.4).
    const auto plain = tri2quad(in, {});
    std::size_t poor = 0;
    for (const auto& q : plain.quads)
      poor += joe_mu(plain.points[q[0]], plain.points[q[1]], plain.points[q[2]], plain.points[q[3]]) < 40;
    CHECK(poor > plain.quads.size() / 10);
  }
  // An odd count (a notch triangle on one side): one group is odd, its
  // point goes on the input boundary and every guarantee still holds.
  Tri2QuadInput in = square_grid(9);
  in.points.push_back({4.5, -0.7});
  in.triangles.push_back({4, int(in.points.size()) - 1, 5});
  Tri2QuadOptions o;
  o.pair_above = 40;
  const auto r = tri2quad(in, o);
  check_result(in, r, false);
  check_segments(in, r);
  std::map<std::string, std::size_t> c(r.cases.begin(), r.cases.end());
  CHECK(c["pairs_first_abandoned"] == 0);
  CHECK(c["pairs_first"] >= 70);
}

TEST_CASE("pairs first keep a sharp input corner in one quad", "[tri2quad][pairs]") {
  // A 4 x 4 grid with a wedge below it: the triangle c, (2, 0), (1, 0),
  // alone at its 18.9-degree corner c. Split, the corner would go to two
  // quads, each of mu at most a quarter of it after any smoothing; paired
  // across (1, 0)-(2, 0), to one.
  Tri2QuadInput in = square_grid(4);
  in.points.push_back({1.5, -3});
  const int c = int(in.points.size()) - 1;
  in.triangles.push_back({c, 2, 1});
  Tri2QuadOptions o;
  o.pair_above = 40;
  const auto r = tri2quad(in, o);
  check_result(in, r, false);
  check_segments(in, r);
  CHECK(std::count_if(r.quads.begin(), r.quads.end(),
                      [&](const auto& q) { return std::find(q.begin(), q.end(), c) != q.end(); }) == 1);
}

TEST_CASE("pairs first do not keep a sharp corner in a nearly flat quad", "[tri2quad][pairs]") {
  // The wedge's corner c a hair left of x = 2: the pair's quad c, (2, 0),
  // (2, 1), (1, 0) is convex for the exact predicates, with an angle within
  // 1e-12 of 180 degrees at (2, 0) that no smoothing could open.
  Tri2QuadInput in = square_grid(4);
  in.points.push_back({2 - 1e-12, -3});
  in.triangles.push_back({int(in.points.size()) - 1, 2, 1});
  Tri2QuadOptions o;
  o.pair_above = 40;
  const auto r = tri2quad(in, o);
  check_result(in, r, false);
  double worst = 45;
  for (const auto& q : r.quads) worst = std::min(worst, joe_mu(r.points[q[0]], r.points[q[1]], r.points[q[2]], r.points[q[3]]));
  CHECK(worst > 1e-6);
}
