// soup_crossing_pairs (embedding.hpp): the exact test on any triangle
// set, shared vertex ids standing for shared corners; three triangles on one
// edge (a multi-label mesh's curves) meet only there.
#include "mesh/embedding.hpp"

#include <catch2/catch.hpp>

#include <algorithm>

using namespace imgmesh;

namespace {
using Pairs = std::vector<std::array<std::size_t, 2>>;
Pairs pairs_of(const std::vector<Vec3>& p, const std::vector<std::array<int, 3>>& t) {
  Pairs r = soup_crossing_pairs(p, t, 100);
  std::sort(r.begin(), r.end());
  return r;
}
} // namespace

TEST_CASE("soup_crossing_pairs: shared edges and vertices, crossings, copies", "[embedding]") {
  // Edge 0-1 along x; 2 above it, 3 beside it, 4 below, 5 on 2's side in
  // 2's plane (overlapping it), 6 far.
  const std::vector<Vec3> p{{0, 0, 0}, {1, 0, 0}, {0.5, 0, 1}, {0.5, 1, 0}, {0.5, 0, -1}, {0.5, 0, 0.5}, {5, 5, 5}};
  SECTION("three triangles on one edge, mixed orientations: no crossing") {
    CHECK(pairs_of(p, {{0, 1, 2}, {1, 0, 3}, {0, 1, 4}}).empty());
  }
  SECTION("two coplanar triangles on one side of their edge overlap") {
    CHECK(pairs_of(p, {{0, 1, 2}, {1, 0, 5}}) == Pairs{{0, 1}});
    CHECK(pairs_of(p, {{0, 1, 2}, {0, 1, 4}}).empty());  // coplanar, either side
  }
  SECTION("a triangle given twice") { CHECK(pairs_of(p, {{0, 1, 2}, {2, 1, 0}}) == Pairs{{0, 1}}); }
  SECTION("one shared vertex: crossing or not") {
    // 0-2-6 leaves the plane; 0-{(0.5,0.5,-1)}-{(0.5,-0.5,... )} pierces 0-1-3.
    std::vector<Vec3> q = p;
    q.push_back({0.6, 0.2, -1});  // 7
    q.push_back({0.6, 0.2, 1});   // 8
    CHECK(pairs_of(q, {{0, 1, 3}, {0, 7, 8}}) == Pairs{{0, 1}});
    CHECK(pairs_of(q, {{0, 1, 3}, {0, 2, 6}}).empty());
  }
  SECTION("disjoint triangles crossing, and a degenerate one") {
    std::vector<Vec3> q = p;
    q.push_back({0.3, 0.2, -1});  // 7
    q.push_back({0.3, 0.2, 1});   // 8
    q.push_back({0.4, 0.3, 1});   // 9
    CHECK(pairs_of(q, {{0, 1, 3}, {7, 8, 9}}) == Pairs{{0, 1}});
    q.push_back({2, 0, 0});  // 10: collinear with 0, 1
    CHECK(pairs_of(q, {{0, 1, 3}, {0, 1, 10}}) == Pairs{{1, 1}});
  }
  SECTION("the cap") {
    std::vector<Vec3> q = p;
    std::vector<std::array<int, 3>> t{{0, 1, 3}};
    for (int i = 0; i < 5; ++i) {
      q.push_back({0.2 + 0.1 * i, 0.1, -1});
      q.push_back({0.2 + 0.1 * i, 0.1, 1});
      q.push_back({0.25 + 0.1 * i, 0.2, 1});
      t.push_back({7 + 3 * i, 8 + 3 * i, 9 + 3 * i});
    }
    CHECK(soup_crossing_pairs(q, t, 100).size() == 5);
    const SelfIntersections s = summarize_intersections(soup_crossing_pairs(q, t, 3), 3);
    CHECK(s.pairs == 3);
    CHECK(s.capped);
  }
}

TEST_CASE("soup_crossing_pairs: triangles that only touch, at coordinates no float holds, are found", "[embedding]") {
  // The boxes are floats rounded outward: rounded to nearest (or inward)
  // two triangles meeting at x = 0.1 (no float) could have boxes apart.
  for (double x : {0.1, 1.0 / 3, 1e5 + 0.1, -7.3}) {
    const std::vector<Vec3> p{{x - 1, 0, 0}, {x, 0.3, 0.2}, {x - 1, 1, 0}, {x, 0.3, 0.2}, {x + 1, 0, 1}, {x + 1, 1, 1}};
    INFO(x);
    // A corner of each at the same point, no shared id: they meet.
    CHECK(pairs_of(p, {{0, 1, 2}, {3, 4, 5}}) == Pairs{{0, 1}});
    // The same point as one shared vertex: they do not cross.
    CHECK(pairs_of(p, {{0, 1, 2}, {1, 4, 5}}).empty());
  }
}

TEST_CASE("SurfaceGeometry::sides: each point's side() on lines through vertices, edges and faces", "[embedding]") {
  // Two octahedra (outward), one tilted off the axes, the other's top and
  // bottom vertices on a line of points; the points on a 0.25 grid, many
  // on triangles, on lines through edges and vertices, inside and outside.
  std::vector<Vec3> p;
  std::vector<std::array<int, 3>> t;
  std::vector<int> comp;
  auto octahedron = [&](const Vec3& c, const std::array<Vec3, 3>& axes, int id) {
    const int base = int(p.size());
    for (const Vec3& a : axes) {
      p.push_back({c[0] + a[0], c[1] + a[1], c[2] + a[2]});
      p.push_back({c[0] - a[0], c[1] - a[1], c[2] - a[2]});
    }
    // Vertices 0/1: +-x, 2/3: +-y, 4/5: +-z; faces outward (right-handed axes).
    for (int sx : {0, 1})
      for (int sy : {0, 1})
        for (int sz : {0, 1}) {
          std::array<int, 3> f{base + sx, base + 2 + sy, base + 4 + sz};
          if ((sx + sy + sz) % 2) std::swap(f[1], f[2]);
          t.push_back(f);
          comp.push_back(id);
        }
  };
  octahedron({2, 2, 2}, {Vec3{1, 0, 0}, Vec3{0, 1, 0}, Vec3{0, 0, 1}}, 0);
  octahedron({6, 2, 2}, {Vec3{1.5, 0.5, 0.25}, Vec3{-0.5, 1.5, 0.5}, Vec3{0.25, -0.5, 1.5}}, 1);
  const SurfaceGeometry g(p, t, comp, 2);
  std::vector<Vec3> q;
  for (double x = 0.5; x <= 8.5; x += 0.25)
    for (double y = 0.5; y <= 3.5; y += 0.25)
      for (double z = 0.25; z <= 4; z += 0.25) q.push_back({x, y, z});
  const std::vector<int> s = g.sides(q);
  REQUIRE(s.size() == q.size());
  long count[3] = {0, 0, 0};
  for (std::size_t i = 0; i < q.size(); ++i) {
    const int want = g.side(q[i]);
    ++count[want + 1];
    if (s[i] != want) FAIL_CHECK("point " << q[i][0] << ' ' << q[i][1] << ' ' << q[i][2] << ": " << s[i] << " != " << want);
  }
  CHECK(count[0] > 100);  // inside
  CHECK(count[1] > 10);   // on a triangle
  CHECK(count[2] > 1000); // outside
}
