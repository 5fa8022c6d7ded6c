// HandleDetection (8.3) alone: S inside one Voronoi cell V(p) is a disk or
// not, by marching tetrahedra, and the cube-grid certificate that settles
// most cells first.
#include "shapes.hpp"
#include "surface/delmesh.hpp"
#include "surface/handle_detection.hpp"

#include <catch2/catch.hpp>

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
} // namespace

TEST_CASE("HandleDetection: a whole torus inside V(p) has a handle; the point returned is on S, in V(p)") {
  const Vec3 c{12.2, 11.9, 7.1};
  FunctionSurface s(test::box(25, 25, 15), [&](const Vec3& x) { return test::torus_f(x, c, 7, 2.6); });
  RestrictedDelaunayOptions o;
  DelMesh m(s, o);
  const Vh p = lone_vertex(m, Vec3{c[0] + 9.6, c[1], c[2]});  // on the torus' outer equator
  Vec3 q;
  CHECK_FALSE(handle_free(m.triangulation(), m.grid(), p));
  REQUIRE(handle_detection(m.triangulation(), m.sampler(), p, q));
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
  REQUIRE(handle_detection(m.triangulation(), m.sampler(), p, q));
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
    CHECK_FALSE(handle_detection(m.triangulation(), m.sampler(), v, q));
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
