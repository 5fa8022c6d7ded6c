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

TEST_CASE("LineSides on two octahedra: side() or grazing on lines through vertices, edges and faces", "[embedding]") {
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
  // Along each axis: side()'s answer, or kGrazing where the line meets an
  // edge or a vertex (many here: the first octahedron's on the lattice).
  LineSides lines[3] = {LineSides(p, t, 0), LineSides(p, t, 1), LineSides(p, t, 2)};
  long count[3] = {0, 0, 0};
  for (const Vec3& x : q) {
    const int want = g.side(x);
    ++count[want + 1];
    for (int a = 0; a < 3; ++a) {
      const int s = lines[a].side(x);
      if (s != LineSides::kGrazing && s != want)
        FAIL_CHECK("axis " << a << ", point " << x[0] << ' ' << x[1] << ' ' << x[2] << ": " << s << " != " << want);
    }
  }
  CHECK(count[0] > 100);  // inside
  CHECK(count[1] > 10);   // on a triangle
  CHECK(count[2] > 1000); // outside
}

TEST_CASE("LineSides: SurfaceGeometry::side's answers along every axis, grazing lines told", "[embedding]") {
  // A cube [0, 2]^3 split into 12 triangles, and inside it (enclosed: its
  // points are outside) a tetrahedron off the lattice; the points: a
  // lattice of step 0.5 from -0.5 (lines through the cube's edges and
  // corners graze; points on its faces are on the surface) and a lattice of
  // step 0.37 (lines that cross the tetrahedron).
  std::vector<Vec3> p;
  for (int m = 0; m < 8; ++m) p.push_back({m & 1 ? 2.0 : 0.0, m & 2 ? 2.0 : 0.0, m & 4 ? 2.0 : 0.0});
  std::vector<std::array<int, 3>> t = {{0, 2, 3}, {0, 3, 1}, {4, 5, 7}, {4, 7, 6}, {0, 1, 5}, {0, 5, 4},
                                       {2, 6, 7}, {2, 7, 3}, {0, 4, 6}, {0, 6, 2}, {1, 3, 7}, {1, 7, 5}};
  p.push_back({0.31, 0.42, 0.23});
  p.push_back({1.63, 0.51, 0.37});
  p.push_back({0.72, 1.71, 0.41});
  p.push_back({0.83, 0.77, 1.69});
  // Oriented out of the tetrahedron (as the cube's faces are out of it).
  for (std::array<int, 3> f : {std::array<int, 3>{8, 10, 9}, {8, 9, 11}, {8, 11, 10}, {9, 10, 11}}) t.push_back(f);
  const std::vector<int> component{0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 1, 1, 1, 1};
  const SurfaceGeometry g(p, t, component, 2);
  std::vector<Vec3> q;
  for (int i = 0; i < 6; ++i)
    for (int j = 0; j < 6; ++j)
      for (int k = 0; k < 6; ++k) q.push_back({-0.5 + 0.5 * i, -0.5 + 0.5 * j, -0.5 + 0.5 * k});
  for (int i = 0; i < 7; ++i)
    for (int j = 0; j < 7; ++j)
      for (int k = 0; k < 7; ++k) q.push_back({-0.2 + 0.37 * i, -0.2 + 0.37 * j, -0.2 + 0.37 * k});
  for (int axis = 0; axis < 3; ++axis) {
    LineSides lines(p, t, axis);
    std::array<int, 4> seen{0, 0, 0, 0};  // inside, on, outside, grazing
    for (const Vec3& x : q) {
      const int s = lines.side(x);
      ++seen[std::size_t(s + 1)];
      if (s == LineSides::kGrazing) continue;
      INFO("axis " << axis << " point " << x[0] << " " << x[1] << " " << x[2]);
      CHECK(s == g.side(x));
    }
    INFO("axis " << axis);
    CHECK(seen[0] > 0);
    CHECK(seen[1] > 0);
    CHECK(seen[2] > 0);
    CHECK(seen[3] > 0);
  }
}

TEST_CASE("nesting_depths: SurfaceGeometry's depths, a vertex on another's surface passed over", "[embedding]") {
  // Three cubes, [0, 4]^3, [1, 3]^3 in it and [1.5, 2.5]^3 in that, and a
  // fourth [6, 7]^3 beside them; the innermost's first vertex lies on no
  // other's surface, a fifth cube's [0, 1]^3 first vertex (0, 0, 0) on the
  // outer's corner: passed over for its next.
  std::vector<Vec3> p;
  std::vector<std::array<int, 3>> t;
  std::vector<int> component;
  const std::vector<std::array<int, 3>> faces = {{0, 2, 3}, {0, 3, 1}, {4, 5, 7}, {4, 7, 6}, {0, 1, 5}, {0, 5, 4},
                                                 {2, 6, 7}, {2, 7, 3}, {0, 4, 6}, {0, 6, 2}, {1, 3, 7}, {1, 7, 5}};
  auto cube = [&](double lo, double hi) {
    const int base = int(p.size());
    for (int m = 0; m < 8; ++m) p.push_back({m & 1 ? hi : lo, m & 2 ? hi : lo, m & 4 ? hi : lo});
    const int c = component.empty() ? 0 : component.back() + 1;
    for (const auto& f : faces) {
      t.push_back({f[0] + base, f[1] + base, f[2] + base});
      component.push_back(c);
    }
  };
  cube(0, 4);
  cube(1, 3);
  cube(1.5, 2.5);
  cube(6, 7);
  cube(0, 1);
  std::vector<int> component_of(p.size());
  for (std::size_t v = 0; v < p.size(); ++v) component_of[v] = int(v / 8);
  const std::vector<int> expected =
      SurfaceGeometry(p, t, component, 5).nesting_depths(component_of);
  CHECK(expected == std::vector<int>{0, 1, 2, 0, 1});
  CHECK(nesting_depths(p, t, component, 5, component_of) == expected);
}
