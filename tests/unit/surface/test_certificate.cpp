// The certificate alone: the restricted facets as an oriented mesh, its
// components matched by place with bdCA(X)'s (match_components), wrong
// meshes refused, and the fallback's points.
#include "shapes.hpp"
#include "surface/certificate.hpp"
#include "surface/delmesh.hpp"

#include <catch2/catch.hpp>

using namespace imgmesh;
using namespace imgmesh::surface_detail;

namespace {
// A ball (x = 9.2) and a solid torus (x = 27.8) placed symmetrically about
// the grid's centre plane x = 18.5, so mirroring swaps their places.
constexpr double kBallX = 9.2, kTorusX = 27.8;
double ball_and_torus(const Vec3& p, bool fill_hole) {
  const Vec3 a{kBallX, 8.3, 7.2}, c{kTorusX, 9.2, 7.4};
  double torus = test::torus_f(p, c, 5.2, 2.1);
  if (fill_hole) {  // the torus with its hole closed by a slab: a sphere's topology
    const double q = std::max(std::hypot(p[0] - c[0], p[1] - c[1]) - 5.2, 0.0);
    torus = std::hypot(q, p[2] - c[2]) - 2.1;
  }
  return std::min(test::sphere_f(p, a, 3.9), torus);
}
// DELMESH's certificate of the refined mesh of one of the two shapes.
Certificate refined_certificate(bool fill_hole, ExpectedTopology* expected_out = nullptr) {
  FunctionSurface s(test::box(38, 19, 15), [&](const Vec3& p) { return ball_and_torus(p, fill_hole); });
  // Without VoxelSides: its points would put vertices on the filled hole's
  // disk, and the certificate would refuse that mesh by place before it
  // compares Euler characteristics.
  RestrictedDelaunayOptions o;
  o.voxel_sides = false;
  DelMesh m(s, o);
  m.prepare();
  const ExpectedTopology expected = expected_topology(m.grid());
  m.seeds();
  m.refine();
  if (expected_out) *expected_out = expected;
  return certify(m.triangulation(), m.vertices().size(), m.grid(), expected);
}
} // namespace

TEST_CASE("certificate: refuses the ball and torus in each other's places and a torus meshed as a sphere") {
  FunctionSurface s(test::box(38, 19, 15), [&](const Vec3& p) { return ball_and_torus(p, false); });
  CubeGrid grid(s.samples());
  grid.label();
  ExpectedTopology expected = expected_topology(grid);
  REQUIRE(expected.topology.sorted_euler() == std::vector<long long>{0, 2});
  const Certificate right = refined_certificate(false);
  REQUIRE(right.ok);
  REQUIRE(right.check.topology.sorted_euler() == std::vector<long long>{0, 2});
  {
    // Mirrored in x about the grid's centre, faces flipped to stay outward:
    // the same sorted Euler list, the components in each other's places.
    Certificate swapped = right;
    for (Vec3& p : swapped.mesh.points) p[0] = grid.hi[0] - p[0];
    for (auto& t : swapped.mesh.triangles) std::swap(t[1], t[2]);
    check_certificate(swapped, grid, expected);
    CHECK(swapped.check.topology.sorted_euler() == expected.topology.sorted_euler());
    CHECK(swapped.check.topology.closed);
    CHECK(swapped.check.topology.oriented);
    CHECK_FALSE(swapped.ok);
    CHECK(swapped.bad.size() == 2);  // both S components need repair
    CHECK(!swapped.check.failure().empty());
    // The unmirrored copy, checked the same way, passes.
    Certificate again = right;
    check_certificate(again, grid, expected);
    CHECK(again.ok);
    CHECK(again.bad.empty());
    CHECK(again.check.failure().empty());
  }
  {
    // The torus with its hole closed: a sphere where the torus is.
    const Certificate filled = refined_certificate(true);
    REQUIRE(filled.ok);  // against its own voxel boundary
    REQUIRE(filled.check.topology.sorted_euler() == std::vector<long long>{2, 2});
    Certificate wrong = filled;
    check_certificate(wrong, grid, expected);
    CHECK_FALSE(wrong.ok);
    const int torus = grid.comp_at(Vec3{kTorusX + 5.2 + 2.1, 9.2, 7.4});
    CHECK(wrong.bad == std::vector<int>{torus});
    INFO(wrong.check.failure());
    CHECK(wrong.check.failure().find("euler 2") != std::string::npos);
  }
}

TEST_CASE("certificate: refuses DELMESH's seeds alone on a ball and a torus, accepts the refined mesh, oriented outward") {
  const Vec3 a{6.4, 8.3, 7.2}, c{20.1, 9.2, 7.4};
  auto fn = [&](const Vec3& p) { return std::min(test::sphere_f(p, a, 3.9), test::torus_f(p, c, 5.2, 2.1)); };
  FunctionSurface s(test::box(29, 19, 15), fn);
  RestrictedDelaunayOptions o;
  DelMesh m(s, o);
  m.prepare();
  const ExpectedTopology expected = expected_topology(m.grid());
  REQUIRE(expected.topology.sorted_euler() == std::vector<long long>{0, 2});
  // Each voxel-boundary component counts for the S component where it is.
  REQUIRE(expected.s_component.size() == 2);
  const int ball = m.grid().comp_at(Vec3{a[0] + 3.9, a[1], a[2]});
  const int torus = m.grid().comp_at(Vec3{c[0] + 5.2 + 2.1, c[1], c[2]});
  REQUIRE(ball >= 0);
  REQUIRE(torus >= 0);
  REQUIRE(ball != torus);
  for (std::size_t b = 0; b < 2; ++b)
    CHECK(expected.s_component[b] == (expected.topology.components[b].euler == 2 ? ball : torus));
  m.seeds();
  const Certificate seeds_only = certify(m.triangulation(), m.vertices().size(), m.grid(), expected);
  CHECK_FALSE(seeds_only.ok);
  // The fallback's points on a refused component lie on S.
  for (int comp = 0; comp < 2; ++comp) {
    const Candidates pts = fallback_points(m.triangulation(), m.sampler(), comp);
    CHECK(!pts.empty());
    for (const auto& [x, clearance] : pts) CHECK(std::abs(s.value(x)) < 1e-9);
  }
  m.refine();
  const Certificate cert = certify(m.triangulation(), m.vertices().size(), m.grid(), expected);
  CHECK(cert.ok);
  CHECK(cert.bad.empty());
  CHECK(cert.check.correspondence.matches());
  CHECK(cert.check.topology.sorted_euler() == std::vector<long long>{0, 2});
  REQUIRE(cert.facets.size() == cert.mesh.triangles.size());
  // Restricted facets in vertex-id order, each restricted.
  const std::vector<Facet> restricted = restricted_facets(m.triangulation());
  REQUIRE(restricted.size() == cert.facets.size());
  for (std::size_t k = 0; k < cert.facets.size(); ++k) {
    const Facet f = cert.facets[k].facet();  // packed in 8 bytes and back
    CHECK(f == restricted[k]);
    CHECK((f.first->facet[f.second].state & kRestricted));
  }
  // Outward: the winding number is 1 inside S and 0 outside.
  CHECK(test::winding_number(cert.mesh, a) == Approx(1).margin(1e-6));
  CHECK(test::winding_number(cert.mesh, Vec3{c[0] + 5.2, c[1], c[2]}) == Approx(1).margin(1e-6));
  CHECK(test::winding_number(cert.mesh, c) == Approx(0).margin(1e-6));  // the torus' hole
  const MeasuredGuarantees g = measure_guarantees(m.triangulation(), m.sampler(), cert);
  CHECK(g.restricted_delaunay_violations == 0);
  CHECK(g.max_abs_f_at_vertices < 1e-9);
  CHECK(g.quality.largest_radius_edge_ratio() <= o.ratio * (1 + 1e-9));
  CHECK(g.max_roughness <= o.roughness + 1e-9);
}

TEST_CASE("certificate: the fallback acts when TOPOLOGY is skipped, and its failure names the component") {
  FunctionSurface s(test::box(38, 19, 15), [&](const Vec3& p) { return ball_and_torus(p, false); });
  RestrictedDelaunayOptions o;
  o.topology_steps = false;  // QUALITY and SMOOTH alone leave the topology wrong
  o.voxel_sides = false;     // VoxelSides needs TOPOLOGY (the closed ball property) and is skipped with it
  const RestrictedDelaunayResult r = restricted_delaunay_mesh(s, o);
  CHECK(r.topology_fallback_rounds > 0);
  CHECK(r.inserted("topology_fallback") > 0);
  CHECK(r.inserted("vor_edge") + r.inserted("topo_disk") + r.inserted("facet_cycle") + r.inserted("handle_detection") == 0);
  CHECK(r.topology_ok);
  CHECK(r.topology.sorted_euler() == std::vector<long long>{0, 2});
  CHECK(r.failed_guarantee().empty());
  // No repair round allowed: the certificate fails and says where.
  o.fallback_rounds = 0;
  const RestrictedDelaunayResult f = restricted_delaunay_mesh(s, o);
  CHECK(f.topology_fallback_rounds == 0);
  CHECK_FALSE(f.topology_ok);
  CHECK(f.failed_guarantee().find("component") != std::string::npos);
  CHECK(f.to_json().at("topology_failure").string() == f.topology_failure);
}
