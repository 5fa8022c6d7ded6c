// FacetCycle (8.2) alone: a closed curve of S inside the Voronoi facet of
// one Delaunay edge, which no Voronoi edge sees.
#include "shapes.hpp"
#include "surface/delmesh.hpp"
#include "surface/facet_cycle.hpp"

#include <catch2/catch.hpp>

using namespace imgmesh;
using namespace imgmesh::surface_detail;

namespace {
// p, q and four points far away (the Voronoi facet of pq is then the whole
// bisector plane inside the grid's box).
struct Pair {
  Tr tr;
  Tr::Edge pq;
  Vec3 p, q;
  Pair(const Vec3& p_, const Vec3& q_) : p(p_), q(q_) {
    const std::vector<Vec3> far{{-900, -900, -900}, {900, -800, -700}, {100, 900, -600}, {50, 80, 950}};
    int id = 0;
    for (const Vec3& x : far) tr.insert(Point(x[0], x[1], x[2]))->info().id = id++;
    const Vh vp = tr.insert(Point(p[0], p[1], p[2])), vq = tr.insert(Point(q[0], q[1], q[2]));
    vp->info().id = id++;
    vq->info().id = id++;
    Ch c;
    int i, j;
    REQUIRE(tr.is_edge(vp, vq, c, i, j));
    pq = Tr::Edge(c, i, j);
  }
};
} // namespace

TEST_CASE("FacetCycle: a small sphere around the middle of pq is a cycle in pq's Voronoi facet") {
  const Vec3 mid{10.2, 9.8, 10.1};
  FunctionSurface s(test::box(21, 21, 21), [&](const Vec3& x) { return test::sphere_f(x, mid, 2.2); });
  CubeGrid grid(s.samples());
  grid.label();
  SurfaceSampler f(s, grid);
  Pair pair(Vec3{mid[0], mid[1], mid[2] - 6}, Vec3{mid[0], mid[1], mid[2] + 6});
  Vec3 x;
  REQUIRE(facet_cycle(pair.tr, f, pair.pq, x));
  CHECK(std::abs(s.value(x)) < 1e-9);                                              // on S
  CHECK(std::abs(dist2(x, pair.p) - dist2(x, pair.q)) < 1e-6 * dist2(x, pair.p));  // on the bisector
  // The same for a thin torus lying in the bisector plane.
  FunctionSurface t(test::box(21, 21, 21), [&](const Vec3& y) { return test::torus_f(y, mid, 4.5, 1.0); });
  CubeGrid tgrid(t.samples());
  tgrid.label();
  SurfaceSampler tf(t, tgrid);
  REQUIRE(facet_cycle(pair.tr, tf, pair.pq, x));
  CHECK(std::abs(t.value(x)) < 1e-9);
  CHECK(std::abs(x[2] - mid[2]) < 1e-6);
}

TEST_CASE("FacetCycle: no cycle where S crosses the facet to its border, or misses it") {
  const Vec3 mid{10.2, 9.8, 10.1};
  Pair pair(Vec3{mid[0], mid[1], mid[2] - 6}, Vec3{mid[0], mid[1], mid[2] + 6});
  // Two close sheets x = 9.85 and 10.55 cross the plane z = 10.1 in lines
  // that reach the facet's border (the grid's box) at both ends.
  FunctionSurface sheets(test::box(21, 21, 21), [](const Vec3& y) {
    return test::sheets_f(y, 10.2, 0.35, 2, 18);
  });
  CubeGrid g1(sheets.samples());
  g1.label();
  SurfaceSampler f1(sheets, g1);
  Vec3 x;
  CHECK_FALSE(facet_cycle(pair.tr, f1, pair.pq, x));
  // A ball beside the plane: S does not meet the facet.
  FunctionSurface ball(test::box(21, 21, 21), [&](const Vec3& y) { return test::sphere_f(y, Vec3{10, 10, 15}, 2.5); });
  CubeGrid g2(ball.samples());
  g2.label();
  SurfaceSampler f2(ball, g2);
  CHECK_FALSE(facet_cycle(pair.tr, f2, pair.pq, x));
}

TEST_CASE("FacetCycle's pass: on a thin torus after the seeds it finds cycle points on S, each in its facet") {
  const Vec3 c{11.6, 11.3, 4.6};
  FunctionSurface s(test::box(24, 24, 10), [&](const Vec3& p) { return test::torus_f(p, c, 8.1, 1.1); });
  RestrictedDelaunayOptions o;
  DelMesh m(s, o);
  m.prepare();
  m.seeds();
  IdSet all;
  for (Vh v : m.vertices()) all.add(v->info().id);
  std::uint32_t stamp = 1000;
  long long checks = 0;
  const Candidates pts = facet_cycle_points(m.triangulation(), m.sampler(), m.vertices(), all, stamp, 2, checks);
  CHECK(checks == long(m.triangulation().number_of_finite_edges()));  // every edge once
  REQUIRE(!pts.empty());
  for (const auto& [x, clearance2] : pts) {
    CHECK(std::abs(s.value(x)) < 1e-9);
    // x's nearest sites: at least two of W at the same distance (a Voronoi facet).
    const Vh n = m.triangulation().nearest_vertex(Point(x[0], x[1], x[2]));
    CHECK(dist2(x, vec(n->point())) == Approx(clearance2).epsilon(1e-6));
  }
}
