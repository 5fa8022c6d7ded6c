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
