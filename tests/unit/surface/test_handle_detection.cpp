// HandleDetection (8.3) alone: S inside one Voronoi cell V(p) is a disk or
// not, by marching tetrahedra, and the cube-grid certificate that settles
// most cells first.
#include "shapes.hpp"
#include "surface/delmesh.hpp"
#include "surface/handle_detection.hpp"

#include <catch2/catch.hpp>

#include <set>

using namespace imgmesh;
using namespace imgmesh::surface_detail;

namespace {
// W = p and four points far outside the grid: V(p) holds the whole box.
Vh lone_vertex(DelMesh& m, const Vec3& p) {
  m.prepare();
  for (const Vec3& x : {Vec3{-900, -900, -900}, Vec3{900, -800, -700}, Vec3{100, 900, -600}, Vec3{50, 80, 950}})
    REQUIRE(m.insert(x, kSeed));
  REQUIRE(m.insert(p, kSeed));
  return m.vertices().back();
}

// handle_free's certificate done plainly: the active cubes reached from
// p's cube through mixed faces, but for those with every corner beyond one
// face of V(p), in a set; their mixed faces and crossed edges in sets (each
// corner's sign read anew); a disk when cubes - faces + edges is 1 and at
// most 512 cubes were reached.
bool plain_handle_free(const Tr& tr, const CubeGrid& g, Vh p) {
  std::vector<HalfSpace> hs;
  voronoi_cell(tr, p, hs);
  using Cube = std::array<long, 3>;
  auto corner = [&](const Cube& c, int k) { return Cube{c[0] + (k & 1), c[1] + (k >> 1 & 1), c[2] + (k >> 2 & 1)}; };
  auto beyond = [&](const Cube& c) {
    for (const HalfSpace& e : hs) {
      bool all = true;
      for (int k = 0; k < 8 && all; ++k) {
        const Cube q = corner(c, k);
        all = dot(e.d, Vec3{q[0] * g.s[0], q[1] * g.s[1], q[2] * g.s[2]}) > e.c;
      }
      if (all) return true;
    }
    return false;
  };
  const Vec3 pp = vec(p->point());
  Cube c0;
  for (int k = 0; k < 3; ++k) c0[std::size_t(k)] = std::clamp(long(std::floor(pp[k] / g.s[k])), 0L, g.n[k] - 2);
  if (!g.active(c0[0], c0[1], c0[2])) return false;
  std::set<Cube> reached{c0};
  std::set<std::array<long, 4>> faces, edges;
  std::vector<Cube> todo{c0};
  while (!todo.empty()) {
    const Cube c = todo.back();
    todo.pop_back();
    auto neg = [&](int k) { const Cube q = corner(c, k); return g.neg(q[0], q[1], q[2]); };
    for (int k = 0; k < 8; ++k)
      for (int a = 0; a < 3; ++a)
        if (!(k >> a & 1) && neg(k) != neg(k | 1 << a)) {
          const Cube q = corner(c, k);
          edges.insert({q[0], q[1], q[2], a});
        }
    for (int a = 0; a < 3; ++a)
      for (int side = 0; side < 2; ++side) {
        std::set<bool> signs;
        for (int k = 0; k < 8; ++k)
          if ((k >> a & 1) == side) signs.insert(neg(k));
        if (signs.size() < 2) continue;
        Cube f = c, n = c;
        f[std::size_t(a)] += side;
        n[std::size_t(a)] += side ? 1 : -1;
        faces.insert({f[0], f[1], f[2], a});
        if (g.active(n[0], n[1], n[2]) && !reached.count(n) && !beyond(n)) {
          reached.insert(n);
          todo.push_back(n);
        }
      }
  }
  return reached.size() <= 512 && long(reached.size()) - long(faces.size()) + long(edges.size()) == 1;
}
} // namespace

TEST_CASE("HandleDetection's cheap certificate answers as the plain count does, yes and no, on a coarse torus") {
  const Vec3 c{12.2, 11.9, 7.1};
  FunctionSurface s(test::box(25, 25, 15), [&](const Vec3& x) { return test::torus_f(x, c, 7, 2.6); });
  DelMesh m(s, RestrictedDelaunayOptions{});
  m.prepare();
  m.seeds();
  int yes = 0, no = 0;
  auto compare = [&] {
    for (Vh v : m.vertices()) {
      const bool plain = plain_handle_free(m.triangulation(), m.grid(), v);
      REQUIRE(handle_free(m.triangulation(), m.grid(), v) == plain);
      (plain ? yes : no) += 1;
    }
  };
  for (int n : {4, 8, 12}) {  // points of S, further apart, then closer
    for (int i = 0; i < n; ++i)
      for (int j = 0; j < n / 2; ++j) {
        const double u = 2 * M_PI * (i + 0.31 * j) / n, v = 2 * M_PI * (j + 0.17) / (n / 2), q = 7 + 2.6 * std::cos(v);
        m.insert(Vec3{c[0] + q * std::cos(u), c[1] + q * std::sin(u), c[2] + 2.6 * std::sin(v)}, kSeed);
      }
    compare();
  }
  CHECK(yes > 0);
  CHECK(no > 0);
}

TEST_CASE("HandleDetection: a whole torus inside V(p) has a handle; the point returned is on S, in V(p)") {
  const Vec3 c{12.2, 11.9, 7.1};
  FunctionSurface s(test::box(25, 25, 15), [&](const Vec3& x) { return test::torus_f(x, c, 7, 2.6); });
  RestrictedDelaunayOptions o;
  DelMesh m(s, o);
  const Vh p = lone_vertex(m, Vec3{c[0] + 9.6, c[1], c[2]});  // on the torus' outer equator
  Vec3 q;
  CHECK_FALSE(handle_free(m.triangulation(), m.grid(), p));
  REQUIRE(handle_detection(m.triangulation(), m.sampler(), p, q) == HandleAnswer::kNotDisk);
  CHECK(std::abs(s.value(q)) < 1e-9);
  CHECK(m.triangulation().nearest_vertex(Point(q[0], q[1], q[2])) == p);
  CHECK(std::sqrt(dist2(q, vec(p->point()))) > 15);  // the far side of the ring
  HandleChecks checks;
  const Candidates pts = handle_points(m.triangulation(), m.sampler(), {p}, 2, checks);
  REQUIRE(pts.size() == 1);
  CHECK(pts[0].first == q);
  CHECK(checks.full == 1);
  CHECK(checks.certified == 0);
}

TEST_CASE("HandleDetection: a whole sphere inside V(p) is a second piece, not a disk") {
  const Vec3 c{10.3, 9.7, 10.1};
  FunctionSurface s(test::box(21, 21, 21), [&](const Vec3& x) { return test::sphere_f(x, c, 6.3); });
  RestrictedDelaunayOptions o;
  DelMesh m(s, o);
  const Vh p = lone_vertex(m, Vec3{c[0], c[1], c[2] + 6.3});
  Vec3 q;
  REQUIRE(handle_detection(m.triangulation(), m.sampler(), p, q) == HandleAnswer::kNotDisk);
  CHECK(std::abs(s.value(q)) < 1e-9);
  CHECK(q[2] < c[2] - 5);  // near the opposite pole
}

TEST_CASE("HandleDetection after DELMESH on a ball: every cell's piece of S is a disk, and the cheap certificate never says otherwise") {
  const Vec3 c{10.3, 9.7, 10.1};
  FunctionSurface s(test::box(21, 21, 21), [&](const Vec3& x) { return test::sphere_f(x, c, 6.3); });
  RestrictedDelaunayOptions o;
  DelMesh m(s, o);
  m.prepare();
  m.seeds();
  m.refine();
  int certified = 0;
  for (Vh v : m.vertices()) {
    Vec3 q;
    CHECK(handle_detection(m.triangulation(), m.sampler(), v, q) == HandleAnswer::kDisk);
    certified += handle_free(m.triangulation(), m.grid(), v);
  }
  CHECK(certified > 0);
  HandleChecks checks;
  CHECK(handle_points(m.triangulation(), m.sampler(), m.vertices(), 2, checks).empty());
  CHECK(checks.full + checks.certified == long(m.vertices().size()));
  CHECK(checks.certified == certified);
  // The certificate's pass on component 0 runs the full test everywhere.
  Candidates pts;
  HandleChecks all;
  REQUIRE(handle_component_points(m.triangulation(), m.sampler(), m.vertices(), {0}, 2, all, pts));
  CHECK(pts.empty());
  CHECK(all.full == long(m.vertices().size()));
}

TEST_CASE("HandleDetection: a cell holding a disk and an annulus is not a disk (their Euler characteristics sum to 1)") {
  // V(p) = the cube [12, 28]^3 (p and its six neighbours 16 away). S in it:
  // the top of a slab (z = 16: a disk) and a tube along x (y = 20, z = 23,
  // radius 2.5: an annulus), both closed well outside the cube.
  auto fn = [](const Vec3& x) {
    const double along = std::clamp(x[0], 5.0, 35.0);
    const double tube = std::sqrt((x[0] - along) * (x[0] - along) + (x[1] - 20) * (x[1] - 20) + (x[2] - 23) * (x[2] - 23)) - 2.5;
    const double slab = std::max({std::abs(x[0] - 20) - 15, std::abs(x[1] - 20) - 15, x[2] - 16, 5 - x[2]});
    return std::min(tube, slab);
  };
  FunctionSurface s(test::box(41, 41, 41), fn);
  DelMesh m(s, RestrictedDelaunayOptions{});
  m.prepare();
  for (const Vec3& x : {Vec3{-900, -900, -900}, Vec3{900, -800, -700}, Vec3{100, 900, -600}, Vec3{50, 80, 950}})
    REQUIRE(m.insert(x, kSeed));
  const Vec3 c{20, 20, 20};
  for (int a = 0; a < 3; ++a)
    for (double sgn : {-1.0, 1.0}) {
      Vec3 x = c;
      x[a] += sgn * 16;
      REQUIRE(m.insert(x, kSeed));
    }
  REQUIRE(m.insert(c, kSeed));
  const Vh p = m.vertices().back();
  Vec3 q;
  CHECK(handle_detection(m.triangulation(), m.sampler(), p, q) == HandleAnswer::kNotDisk);
  CHECK(std::abs(s.value(q)) < 1e-9);
  INFO("q " << q[0] << " " << q[1] << " " << q[2] << " nearest " << m.triangulation().nearest_vertex(Point(q[0], q[1], q[2]))->point());
  CHECK(m.triangulation().nearest_vertex(Point(q[0], q[1], q[2])) == p);
  // Only the slab: one disk.
  FunctionSurface d(test::box(41, 41, 41), [](const Vec3& x) {
    return std::max({std::abs(x[0] - 20) - 15, std::abs(x[1] - 20) - 15, x[2] - 16, 5 - x[2]});
  });
  DelMesh md(d, RestrictedDelaunayOptions{});
  md.prepare();
  for (const Vec3& x : {Vec3{-900, -900, -900}, Vec3{900, -800, -700}, Vec3{100, 900, -600}, Vec3{50, 80, 950}})
    REQUIRE(md.insert(x, kSeed));
  for (int a = 0; a < 3; ++a)
    for (double sgn : {-1.0, 1.0}) {
      Vec3 x = c;
      x[a] += sgn * 16;
      REQUIRE(md.insert(x, kSeed));
    }
  REQUIRE(md.insert(c, kSeed));
  CHECK(handle_detection(md.triangulation(), md.sampler(), md.vertices().back(), q) == HandleAnswer::kDisk);
}

TEST_CASE("HandleDetection: the box stops growing at the grid's faces (tissue one voxel from the border)") {
  // A ball filling an 11^3 grid but for the border samples (S within half a
  // voxel of the border, in the box's outer sub-cubes): V(p) holds the
  // whole grid and S reaches every side of the box once it is the grid.
  const Vec3 c{5, 5, 5};
  FunctionSurface s(test::box(11, 11, 11), [&](const Vec3& x) { return test::sphere_f(x, c, 4.6); });
  DelMesh m(s, RestrictedDelaunayOptions{});
  const Vh p = lone_vertex(m, Vec3{c[0], c[1], c[2] + 4.6});
  Vec3 q;
  REQUIRE(handle_detection(m.triangulation(), m.sampler(), p, q) == HandleAnswer::kNotDisk);  // a whole sphere
  CHECK(std::abs(s.value(q)) < 1e-9);
  CHECK(q[2] < c[2] - 3);
}

namespace {
// A clipped piece through MT vertices `ids` (keys {0, id, 0}).
std::vector<ClipVertex> mt_piece(std::initializer_list<int> ids) {
  std::vector<ClipVertex> pg;
  for (int i : ids) pg.push_back({Vec3{double(i), 0, 0}, ClipKey{0, i, 0}, -1});
  return pg;
}
ClippedComplex glued(const std::vector<std::vector<ClipVertex>>& polys, std::size_t count) {
  ClippedComplex k;
  glue_pieces(polys, count, k);
  return k;
}
} // namespace

TEST_CASE("HandleDetection's glue: the clipped pieces' components and Euler characteristic") {
  // A disk: a quad and a triangle on edge 1-2 (V 5, E 6, F 2).
  ClippedComplex k = glued({mt_piece({0, 1, 2, 3}), mt_piece({1, 4, 2})}, 2);
  CHECK((k.faces == 2 && k.components == 1 && k.chi == 1));
  CHECK(k.vx.size() == 5);
  // An annulus: four quads around a hole (V 8, E 12, F 4).
  k = glued({mt_piece({0, 1, 5, 4}), mt_piece({1, 2, 6, 5}), mt_piece({2, 3, 7, 6}), mt_piece({3, 0, 4, 7})}, 4);
  CHECK((k.components == 1 && k.chi == 0));
  // Two disks apart, and a closed surface (a tetrahedron's faces).
  k = glued({mt_piece({0, 1, 2}), mt_piece({3, 4, 5})}, 2);
  CHECK((k.components == 2 && k.chi == 2));
  k = glued({mt_piece({0, 1, 2}), mt_piece({0, 3, 1}), mt_piece({1, 3, 2}), mt_piece({2, 3, 0})}, 4);
  CHECK((k.components == 1 && k.chi == 2));
  // Clipping points glue where their keys agree (MT edge 0-1 cut by plane
  // 3): V 4, E 5, F 2. Cut by plane 4 in one piece, they do not: V 5, E 6.
  const ClipVertex mt0{Vec3{0, 0, 0}, ClipKey{0, 0, 0}, -1};
  const auto cut = [](int edge, long long plane) { return ClipVertex{Vec3{0.5, double(edge), 0}, ClipKey{1, edge, plane}, -1}; };
  k = glued({{mt0, cut(1, 3), cut(2, 3)}, {mt0, cut(3, 3), cut(1, 3)}}, 2);
  CHECK((k.vx.size() == 4 && k.chi == 1));
  k = glued({{mt0, cut(1, 3), cut(2, 3)}, {mt0, cut(3, 3), cut(1, 4)}}, 2);
  CHECK(k.vx.size() == 5);
  // Pieces of fewer than three vertices are no faces; only the first
  // `count` pieces count (the scratch beyond them is stale).
  k = glued({mt_piece({0, 1}), mt_piece({})}, 2);
  CHECK(k.faces == 0);
  k = glued({mt_piece({0, 1, 2}), mt_piece({3, 4, 5})}, 1);
  CHECK((k.faces == 1 && k.components == 1 && k.chi == 1));
}
