// DELMESH's refinement criteria alone: QUALITY's ratio (7.6.3), the
// --max-distance bound, SMOOTH's roughness (7.6.4) on given normals and on
// a triangulation, and the termination limits.
#include "shapes.hpp"
#include "surface/criteria.hpp"
#include "surface/delmesh.hpp"

#include <catch2/catch.hpp>

using namespace imgmesh;
using namespace imgmesh::surface_detail;

TEST_CASE("QUALITY: the radius-edge ratio refuses a facet above rho_0 and accepts a good one") {
  const Vec3 a{0, 0, 0}, b{1, 0, 0}, c{0.5, std::sqrt(3.0) / 2, 0};
  CHECK(ratio(a, b, c) == Approx(1 / std::sqrt(3.0)));  // equilateral: R = l / sqrt 3
  CHECK(ratio(a, b, Vec3{0, 1, 0}) == Approx(std::sqrt(2.0) / 2));  // right isosceles: R = l sqrt 2 / 2, l_min = l
  CHECK_FALSE(quality_refines(a, b, c, 2.0));
  // A flat triangle: R = 2.525, l_min = 0.5025, ratio 5.02.
  const Vec3 flat{0.5, 0.05, 0};
  CHECK(ratio(a, b, flat) == Approx(2.525 / 0.5025).epsilon(1e-3));
  CHECK(quality_refines(a, b, flat, 2.0));
  CHECK_FALSE(quality_refines(a, b, flat, 6.0));
  CHECK(ratio(a, b, Vec3{2, 0, 0}) == INFINITY);  // collinear
  CHECK(quality_refines(a, a, c, 1e9));             // a repeated vertex
}

TEST_CASE("--max-distance: refines a facet whose surface centre is farther than E from its plane") {
  const Vec3 a{0, 0, 0}, b{1, 0, 0}, c{0, 1, 0};
  const Vec3 x{0.3, 0.3, -0.25};
  CHECK(distance_refines(a, b, c, x, 0.2));
  CHECK_FALSE(distance_refines(a, b, c, x, 0.3));
  CHECK_FALSE(distance_refines(a, b, Vec3{2, 0, 0}, x, 0.01));  // no plane: never
}

TEST_CASE("--max-distance: refines a facet whose centroid has |f| above 2E") {
  // A sphere of radius 6 and a triangle with its vertices on it: the
  // centroid lies 6 - |centroid - centre| = 2.54 inside.
  FunctionSurface s(test::box(21, 21, 21), [](const Vec3& y) { return test::sphere_f(y, Vec3{10, 10, 10}, 6); });
  RestrictedDelaunayOptions o;
  DelMesh m(s, o);
  m.prepare();
  const Vec3 a{16, 10, 10}, b{10, 16, 10}, c{10, 10, 16};
  const double depth = 6 - std::sqrt(3 * 4.0);  // centroid (12, 12, 12)
  CHECK(centroid_refines(m.sampler(), a, b, c, depth / 2 * 0.99));
  CHECK_FALSE(centroid_refines(m.sampler(), a, b, c, depth / 2 * 1.01));
}

TEST_CASE("SMOOTH: an edge's two normals within g pass, beyond g fail; edges not in two facets are ignored") {
  const double g = M_PI / 3;
  auto at = [](double deg) { return Vec3{std::sin(deg * M_PI / 180), 0, std::cos(deg * M_PI / 180)}; };
  std::vector<std::pair<int, Vec3>> n{{4, at(0)}, {7, at(10)}, {4, at(50)}, {7, at(-40)}};
  CHECK(roughness_within(n, g));  // 50 degrees at both edges
  n = {{4, at(0)}, {7, at(10)}, {4, at(70)}, {7, at(-40)}};
  CHECK_FALSE(roughness_within(n, g));  // 70 degrees at edge (v, 4)
  n = {{4, at(0)}, {4, at(170)}, {4, at(90)}, {9, at(120)}};
  CHECK(roughness_within(n, g));  // three facets at one edge, one at another: TopoDisk's business
}

TEST_CASE("SMOOTH and QUALITY on a triangulation: after DELMESH every vertex and facet passes; a tighter g fails some") {
  const Vec3 c{10.3, 9.7, 10.1};
  FunctionSurface s(test::box(21, 21, 21), [&](const Vec3& p) { return test::sphere_f(p, c, 6.3); });
  RestrictedDelaunayOptions o;
  o.roughness = M_PI / 4;
  o.ratio = 1.6;
  DelMesh m(s, o);
  m.prepare();
  m.seeds();
  m.refine();
  Smooth smooth;
  int rough_at_tighter = 0;
  for (Vh v : m.vertices()) {
    Facet worst;
    CHECK(smooth(m.triangulation(), v, o.roughness, &worst));
    rough_at_tighter += !smooth(m.triangulation(), v, o.roughness / 4, &worst);
  }
  CHECK(rough_at_tighter > 0);
  const Tr& tr = m.triangulation();
  for (auto it = tr.finite_facets_begin(); it != tr.finite_facets_end(); ++it) {
    if (!(it->first->facet[it->second].state & kRestricted)) continue;
    const auto v = facet_vertices(it->first, it->second);
    CHECK_FALSE(quality_refines(vec(v[0]->point()), vec(v[1]->point()), vec(v[2]->point()), o.ratio));
  }
}

TEST_CASE("termination limits (k = 0.06)") {
  CHECK(min_ratio_bound() == Approx(1.1236));
  CHECK(min_roughness_bound() == Approx(0.2587).margin(1e-4));
}
