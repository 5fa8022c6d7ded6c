// EdgeSurface (8.2) alone: the crossings of S with a segment, and on the
// Voronoi edges of a triangulation DELMESH built.
#include "shapes.hpp"
#include "surface/delmesh.hpp"
#include "surface/edge_surface.hpp"

#include <catch2/catch.hpp>

#include <random>

using namespace imgmesh;
using namespace imgmesh::surface_detail;

namespace {
// Distance from x to segment [a, b].
double to_segment(const Vec3& x, const Vec3& a, const Vec3& b) {
  const Vec3 d = sub(b, a);
  const double t = std::clamp(dot(sub(x, a), d) / dot(d, d), 0.0, 1.0);
  return std::sqrt(dist2(x, Vec3{a[0] + t * d[0], a[1] + t * d[1], a[2] + t * d[2]}));
}
} // namespace

TEST_CASE("edge_surface: none, one or two crossings of a segment with a sphere; the far one when two") {
  const Vec3 c{10.3, 9.7, 10.1};
  FunctionSurface s(test::box(21, 21, 21), [&](const Vec3& p) { return test::sphere_f(p, c, 6.3); });
  CubeGrid grid(s.samples());
  grid.label();
  SurfaceSampler f(s, grid);
  const Vec3 a{1.0, 9.7, 10.1}, b{19.6, 9.7, 10.1};  // through the centre: x = 4.0 and 16.6
  for (const Vec3& site : {a, b}) {
    const EdgeCrossing e = edge_surface(f, a, b, site);
    REQUIRE(e.count == 2);
    CHECK(std::abs(s.value(e.x)) < 1e-9);
    CHECK(to_segment(e.x, a, b) < 1e-12);
    CHECK(e.x[0] == Approx(site == a ? 16.6 : 4.0).margin(1e-8));  // farther from the site
  }
  const EdgeCrossing one = edge_surface(f, c, b, c);
  CHECK(one.count == 1);
  CHECK(one.x[0] == Approx(16.6).margin(1e-8));
  CHECK(edge_surface(f, Vec3{8, 9.7, 10.1}, Vec3{12, 9.7, 10.1}, c).count == 0);   // inside S
  CHECK(edge_surface(f, Vec3{-9, -5, -5}, Vec3{-1, -1, -1}, c).count == 0);        // outside the box
  CHECK(edge_surface(f, Vec3{1, 1, 1}, Vec3{3, 1, 19}, c).count == 0);             // beside S
}

TEST_CASE("edge_surface: two close sheets 0.7 voxel apart give two crossings") {
  FunctionSurface s(test::box(21, 21, 21), [](const Vec3& p) {
    return test::sheets_f(p, 10.2, 0.35, 3, 17);
  });
  CubeGrid grid(s.samples());
  grid.label();
  SurfaceSampler f(s, grid);
  const Vec3 a{3, 10.1, 9.9}, b{17, 10.1, 9.9};
  const EdgeCrossing e = edge_surface(f, a, b, a);
  REQUIRE(e.count == 2);
  CHECK(e.x[0] == Approx(10.55).margin(1e-8));
  CHECK(std::abs(s.value(e.x)) < 1e-9);
}

TEST_CASE("edge_surface_of: a restricted facet's surface centre is on S, on its Voronoi edge, its ball empty") {
  const Vec3 c{10.3, 9.7, 10.1};
  FunctionSurface s(test::box(21, 21, 21), [&](const Vec3& p) { return test::sphere_f(p, c, 6.3); });
  RestrictedDelaunayOptions o;
  o.roughness = M_PI / 8;  // dense enough for many facets
  DelMesh m(s, o);
  m.prepare();
  m.seeds();
  m.refine();
  const Tr& tr = m.triangulation();
  int restricted = 0, plain = 0;
  for (auto it = tr.finite_facets_begin(); it != tr.finite_facets_end(); ++it) {
    const FacetInfo fresh = edge_surface_of(tr, m.sampler(), it->first, it->second);
    const FacetInfo& kept = it->first->facet[it->second];
    CHECK(fresh.state == kept.state);  // what DELMESH stored is what EdgeSurface says now
    if (!(fresh.state & kRestricted)) {
      ++plain;
      continue;
    }
    ++restricted;
    const Vec3 x{fresh.x[0], fresh.x[1], fresh.x[2]};
    CHECK(std::abs(s.value(x)) < 1e-9);
    const auto v = facet_vertices(it->first, it->second);
    const double r0 = dist2(x, vec(v[0]->point()));
    CHECK(fresh.r2 == Approx(r0).epsilon(1e-12));
    for (int k = 1; k < 3; ++k) CHECK(dist2(x, vec(v[k]->point())) == Approx(r0).epsilon(1e-6));
    const Vh nearest = tr.nearest_vertex(Point(x[0], x[1], x[2]));
    CHECK(dist2(x, vec(nearest->point())) >= r0 * (1 - 1e-9));
  }
  CHECK(restricted > 50);
  CHECK(plain > restricted);
}

TEST_CASE("SurfaceSampler::bisect: a root between ends of opposite signs; a pair of one sign is refused") {
  const Vec3 c{10.3, 9.7, 10.1};
  FunctionSurface s(test::box(21, 21, 21), [&](const Vec3& p) { return test::sphere_f(p, c, 6.3); });
  CubeGrid grid(s.samples());
  SurfaceSampler f(s, grid);
  const Vec3 in{10.3, 9.7, 10.1}, out{19.6, 9.7, 10.1}, out2{19.6, 1.0, 10.1};
  Vec3 x{-1, -1, -1};
  REQUIRE(f.bisect(in, out, f.value(in), x));
  CHECK(x[0] == Approx(16.6).margin(1e-9));
  CHECK(std::abs(s.value(x)) < 1e-9);
  // Both ends outside: no bracket, x untouched.
  const Vec3 keep = x;
  CHECK_FALSE(f.bisect(out, out2, f.value(out), x));
  CHECK(x == keep);
  CHECK_FALSE(f.bisect(in, in, f.value(in), x));
}

TEST_CASE("inactive_box: true only for boxes inside the grid that meet no active cube") {
  const Vec3 c{10.3, 9.7, 10.1};
  FunctionSurface s(test::box(21, 21, 21), [&](const Vec3& p) { return test::sphere_f(p, c, 6.3); });
  CubeGrid grid(s.samples());
  CHECK(grid.inactive_box(Vec3{9, 9, 9}, Vec3{11.5, 10.5, 11}));  // deep inside
  CHECK(grid.inactive_box(Vec3{0, 0, 0}, Vec3{2.5, 2.5, 2.5}));   // outside S, in a corner of the grid
  CHECK(!grid.inactive_box(Vec3{9, 9, 9}, Vec3{16.9, 10, 10}));    // reaches S (x = 16.6)
  CHECK(!grid.inactive_box(Vec3{-0.5, 1, 1}, Vec3{2, 2, 2}));       // beyond the grid
  CHECK(!grid.inactive_box(Vec3{1, 1, 1}, Vec3{2, 2, 20.5}));
  // Every cube met by the box counts, down to one touched at a corner: the
  // first active cube along the x axis through the centre, and a box ending
  // on its low face (to rounding) or 1e-6 short of it.
  long x0 = 11;
  while (!grid.active(x0, 9, 10)) ++x0;
  const double face = double(x0);
  CHECK(!grid.inactive_box(Vec3{11, 9.2, 10.2}, Vec3{face, 9.8, 10.8}));
  CHECK(!grid.inactive_box(Vec3{11, 9.2, 10.2}, Vec3{face - 1e-12, 9.8, 10.8}));
  CHECK(grid.inactive_box(Vec3{11, 9.2, 10.2}, Vec3{face - 1e-6, 9.8, 10.8}));
  // Each active cube, as a point box at its centre: refused.
  for (long z = 0; z < 20; ++z)
    for (long y = 0; y < 20; ++y)
      for (long x = 0; x < 20; ++x)
        if (grid.active(x, y, z)) {
          const Vec3 m{x + 0.5, y + 0.5, z + 0.5};
          REQUIRE(!grid.inactive_box(m, m));
        }
  // Boxes of all sizes and places (across the blocks of 8^3 cubes whose
  // layers it masks to the box's rows and columns) against a look at each
  // cube they meet.
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> at(0, 19.9), extent(0, 7);
  int met = 0, missed = 0;
  for (int t = 0; t < 3000; ++t) {
    Vec3 lo, hi;
    for (int a = 0; a < 3; ++a) lo[a] = at(rng), hi[a] = std::min(20.0, lo[a] + extent(rng));
    bool any = false;
    for (long z = long(lo[2]); z <= std::min(19L, long(hi[2])); ++z)
      for (long y = long(lo[1]); y <= std::min(19L, long(hi[1])); ++y)
        for (long x = long(lo[0]); x <= std::min(19L, long(hi[0])); ++x) any = any || grid.active(x, y, z);
    REQUIRE(grid.inactive_box(lo, hi) == !any);
    ++(any ? met : missed);
  }
  CHECK(met > 500);
  CHECK(missed > 500);
}

TEST_CASE("edge_surface's stages: the segment clipped to the box of voxel centres; its lattice plane crossings, in order") {
  FunctionSurface s(test::box(21, 21, 21), [](const Vec3& p) { return p[0] - 10.5; });
  CubeGrid grid(s.samples());  // the box [0, 20]^3
  double t0 = -1, t1 = -1;
  REQUIRE(clip_to_box(grid, Vec3{-10, 5, 5}, Vec3{40, 0, 0}, t0, t1));
  CHECK(t0 == 0.25);
  CHECK(t1 == 0.75);
  REQUIRE(clip_to_box(grid, Vec3{-5, 25, 1}, Vec3{30, -30, 2}, t0, t1));  // in at x = 0 and y = 20, out at x = 20 and y = 0
  CHECK(t0 == Approx(1.0 / 6));
  CHECK(t1 == Approx(5.0 / 6));
  REQUIRE(clip_to_box(grid, Vec3{1, 2, 3}, Vec3{1, 1, 1}, t0, t1));  // inside: whole
  CHECK((t0 == 0 && t1 == 1));
  CHECK_FALSE(clip_to_box(grid, Vec3{5, -1, 5}, Vec3{10, 0, 0}, t0, t1));    // beside the box, parallel to its face
  CHECK_FALSE(clip_to_box(grid, Vec3{-10, -10, 5}, Vec3{5, 40, 0}, t0, t1));  // x < 0 wherever 0 <= y <= 20
  CHECK_FALSE(clip_to_box(grid, Vec3{20, 5, 5}, Vec3{5, 0, 0}, t0, t1));      // on the face at one end only
  // x = 1, 2, 3 and y = 1 (twice 1/2: a cube's corner edge), z constant;
  // backwards along x, and from the middle.
  const double unit[3] = {1, 1, 1}, two[3] = {2, 2, 2};
  std::vector<double> ts;
  plane_crossings(Vec3{0.5, 0.5, 0.5}, Vec3{3, 1, 0}, 0, 1, unit, ts);
  REQUIRE(ts.size() == 6);
  const double want[6] = {0, 1.0 / 6, 0.5, 0.5, 5.0 / 6, 1};
  for (int k = 0; k < 6; ++k) CHECK(ts[std::size_t(k)] == Approx(want[k]));
  plane_crossings(Vec3{3.5, 0.5, 0.5}, Vec3{-3, 0, 0}, 0, 1, unit, ts);
  CHECK(ts == std::vector<double>{0, (3.5 - 3) / 3, (3.5 - 2) / 3, (3.5 - 1) / 3, 1});
  plane_crossings(Vec3{0.5, 0.5, 0.5}, Vec3{3, 1, 0}, 0.25, 0.75, unit, ts);
  CHECK(ts == std::vector<double>{0.25, 0.5, 0.5, 0.75});
  plane_crossings(Vec3{0.5, 0.5, 0.5}, Vec3{3, 1, 0}, 0, 1, two, ts);  // x = 2 only
  CHECK(ts == std::vector<double>{0, 0.5, 1});
}

namespace {
// Distance from x to the line through o along the unit vector u.
double to_line(const Vec3& x, const Vec3& o, const Vec3& u) { return norm(cross(sub(x, o), u)); }
} // namespace

// A flat cell's circumcentre can lie 1e14 voxels away (anisotropic grids
// make such cells): walked from there, points a + t (b - a) rounded to
// 2^-53 |a| ~ 0.01 off the edge, and surface centres left their Voronoi
// edge (issue 35). The crossings must be on the segment's line.
TEST_CASE("edge_surface: an edge from a Voronoi vertex 1e14 away crosses S on its line") {
  const Vec3 c{10.3, 9.7, 10.1};
  FunctionSurface s(test::box(21, 21, 21), [&](const Vec3& p) { return test::sphere_f(p, c, 6.3); });
  CubeGrid grid(s.samples());
  grid.label();
  SurfaceSampler f(s, grid);
  const double l = std::sqrt(3.0 * 3.0 + 1.0 + 0.5 * 0.5);
  const Vec3 u{3 / l, 1 / l, 0.5 / l};  // through c, crossing S at c -+ 6.3 u
  auto on = [&](double t) { return Vec3{c[0] + t * u[0], c[1] + t * u[1], c[2] + t * u[2]}; };
  // One end far (either way round), the other in the box.
  for (const auto& [a, b] : {std::pair{on(-1e14), on(2)}, std::pair{on(2), on(-1e14)}}) {
    const EdgeCrossing e = edge_surface(f, a, b, on(2));
    REQUIRE(e.count == 1);
    CHECK(to_line(e.x, c, u) < 1e-12);
    CHECK(std::abs(s.value(e.x)) < 1e-9);
    CHECK(dot(sub(e.x, c), u) == Approx(-6.3).margin(1e-9));
  }
  // Both ends far: the three sites of the dual facet, on a circle around the
  // line at c + 4 u (their circumcentre), give a point of the line.
  const Vec3 v = cross(u, Vec3{0, 0, 1}), w = cross(u, v);
  const double vl = norm(v), wl = norm(w);
  std::array<Vec3, 3> sites;
  for (int k = 0; k < 3; ++k) {
    const double th = 2.1 * k + 0.3;
    for (int i = 0; i < 3; ++i) sites[std::size_t(k)][i] = on(4)[i] + 5 * (std::cos(th) * v[i] / vl + std::sin(th) * w[i] / wl);
  }
  const EdgeCrossing e = edge_surface(f, on(-1e14), on(3e13), sites[0], &sites);
  REQUIRE(e.count == 2);
  CHECK(to_line(e.x, c, u) < 1e-12);
  CHECK(std::abs(s.value(e.x)) < 1e-9);
  const double r2 = dist2(e.x, sites[0]);
  for (const Vec3& p : sites) CHECK(dist2(e.x, p) == Approx(r2).epsilon(1e-12));
  // The ends themselves where they are near the box: both kept, bit for bit.
  Vec3 a0, b0;
  REQUIRE(walk_ends(grid, on(-30), on(2), &sites, a0, b0));
  CHECK((a0 == on(-30) && b0 == on(2)));
  REQUIRE(walk_ends(grid, on(-1e14), on(2), &sites, a0, b0));
  CHECK((a0 == on(2) && b0 == on(-1e14)));
}

// A hull facet's Voronoi ray leaves the finite cell's circumcentre away
// from the cell's fourth vertex. With the fourth vertex within rounding of
// the facet's plane (a flat cell), the side computed in floating point
// pointed the ray back through the cell: a crossing on the wrong half of
// the line, not in the facet's dual, whose insertion left the facet in
// place (issue 35: TopoDisk asked for it again, "TOPOLOGY insertion
// refused").
TEST_CASE("edge_surface_of: the ray of a flat cell's hull facet points away from its fourth vertex (exact side)") {
  const Vec3 c{10.3, 9.7, 10.1};
  FunctionSurface s(test::box(21, 21, 21), [&](const Vec3& p) { return test::sphere_f(p, c, 6.3); });
  CubeGrid grid(s.samples());
  grid.label();
  SurfaceSampler f(s, grid);
  // Three sites on a tilted circle of radius 3 around c (S crosses the
  // axis on both sides of c), a fourth in their plane, outside the circle,
  // nudged by a few ulps: among such cells, those whose floating-point side
  // differs from the exact one.
  std::mt19937_64 rng(35);
  std::uniform_real_distribution<double> U(-1, 1);
  int wrong_side = 0;
  for (int trial = 0; trial < 4000 && wrong_side < 20; ++trial) {
    Vec3 n{U(rng), U(rng), 1};
    const double nl = norm(n);
    n = {n[0] / nl, n[1] / nl, n[2] / nl};
    Vec3 e1 = cross(n, Vec3{1, 0, 0});
    const double el = norm(e1);
    e1 = {e1[0] / el, e1[1] / el, e1[2] / el};
    const Vec3 e2 = cross(n, e1);
    auto at = [&](double r, double th, double h) {
      return Vec3{c[0] + r * (std::cos(th) * e1[0] + std::sin(th) * e2[0]) + h * n[0],
                  c[1] + r * (std::cos(th) * e1[1] + std::sin(th) * e2[1]) + h * n[1],
                  c[2] + r * (std::cos(th) * e1[2] + std::sin(th) * e2[2]) + h * n[2]};
    };
    const Vec3 p[4] = {at(3, 0.1, 0), at(3, 2.2, 0), at(3, 4.3, 0), at(4.5, 3.3 + U(rng), 1e-15 * U(rng))};
    const double naive = dot(cross(sub(p[1], p[0]), sub(p[2], p[0])), sub(p[3], p[0]));
    const CGAL::Orientation exact = CGAL::orientation(Point(p[0][0], p[0][1], p[0][2]), Point(p[1][0], p[1][1], p[1][2]),
                                                      Point(p[2][0], p[2][1], p[2][2]), Point(p[3][0], p[3][1], p[3][2]));
    if (exact == CGAL::COPLANAR || (naive > 0) == (exact == CGAL::POSITIVE)) continue;
    ++wrong_side;
    Tr tr;
    Vh v[4];
    for (int k = 0; k < 4; ++k) {
      v[k] = tr.insert(Point(p[k][0], p[k][1], p[k][2]));
      v[k]->info().id = k;
    }
    REQUIRE(tr.dimension() == 3);
    Ch cell;
    int i0, i1, i2;
    REQUIRE(tr.is_facet(v[0], v[1], v[2], cell, i0, i1, i2));
    const FacetInfo fi = edge_surface_of(tr, f, cell, 6 - i0 - i1 - i2);  // the facet opposite the fourth index
    // The ray holds both crossings of the axis (the finite cell's centre lies
    // far beyond one of them): the facet is restricted, its surface centre
    // on S, equidistant from its sites and no nearer the fourth vertex.
    REQUIRE((fi.state & kRestricted));
    const Vec3 x{fi.x[0], fi.x[1], fi.x[2]};
    CHECK(std::abs(s.value(x)) < 1e-9);
    const double r0 = dist2(x, p[0]);
    CHECK(dist2(x, p[1]) == Approx(r0).epsilon(1e-9));
    CHECK(dist2(x, p[2]) == Approx(r0).epsilon(1e-9));
    CHECK(dist2(x, p[3]) >= r0 * (1 - 1e-9));
  }
  CHECK(wrong_side >= 5);
}
