// The certificate alone: the restricted facets as an oriented mesh, its
// components matched by place with bdCA(X)'s, and the fallback's points.
#include "shapes.hpp"
#include "surface/certificate.hpp"
#include "surface/delmesh.hpp"

#include <catch2/catch.hpp>

using namespace imgmesh;
using namespace imgmesh::surface_detail;

namespace {
// A closed triangle mesh: the boundary of a tetrahedron (chi 2) or an
// n x m torus grid (chi 0), its vertex ids shifted by `first`.
void add_tetrahedron(SurfaceMesh& mesh) {
  const int o = int(mesh.points.size());
  mesh.points.insert(mesh.points.end(), {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}});
  for (std::array<int, 3> t : {std::array<int, 3>{0, 2, 1}, {0, 1, 3}, {0, 3, 2}, {1, 2, 3}})
    mesh.triangles.push_back({t[0] + o, t[1] + o, t[2] + o});
}
void add_torus(SurfaceMesh& mesh, int n = 4, int m = 3) {
  const int o = int(mesh.points.size());
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < m; ++j) {
      const double u = 2 * M_PI * i / n, v = 2 * M_PI * j / m;
      mesh.points.push_back({(3 + std::cos(v)) * std::cos(u), (3 + std::cos(v)) * std::sin(u), std::sin(v)});
    }
  auto id = [&](int i, int j) { return o + (i % n) * m + (j % m); };
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < m; ++j) {
      mesh.triangles.push_back({id(i, j), id(i + 1, j), id(i + 1, j + 1)});
      mesh.triangles.push_back({id(i, j), id(i + 1, j + 1), id(i, j + 1)});
    }
}
// One mesh component per S component, component k's triangles in order.
Certificate certificate_of(const SurfaceMesh& mesh, const std::vector<int>& tri_comp) {
  Certificate cert;
  cert.mesh = mesh;
  cert.tri_comp = tri_comp;
  for (int k : tri_comp)
    if (cert.mesh_comps[k].empty()) cert.mesh_comps[k].push_back(k);
  return cert;
}
} // namespace

TEST_CASE("certificate: components in each other's places are refused though the sorted lists agree") {
  SurfaceMesh mesh;
  add_tetrahedron(mesh);  // 4 triangles: mesh component 0
  add_torus(mesh);        // 24 triangles: mesh component 1
  std::vector<int> tri_comp(4, 0);
  tri_comp.resize(28, 1);
  ExpectedTopology right, swapped;
  right.by_component = {2, 0};
  swapped.by_component = {0, 2};
  const Certificate cert = certificate_of(mesh, tri_comp);
  CHECK(euler_mismatches(cert, right).empty());
  CHECK(euler_mismatches(cert, swapped) == std::vector<int>{0, 1});
  ExpectedTopology genus2;
  genus2.by_component = {2, -2};
  CHECK(euler_mismatches(cert, genus2) == std::vector<int>{1});
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
  REQUIRE(expected.by_component.size() == 2);
  const int ball = m.grid().comp_at(Vec3{a[0] + 3.9, a[1], a[2]});
  const int torus = m.grid().comp_at(Vec3{c[0] + 5.2 + 2.1, c[1], c[2]});
  REQUIRE(ball >= 0);
  REQUIRE(torus >= 0);
  REQUIRE(ball != torus);
  CHECK(expected.by_component[std::size_t(ball)] == 2);
  CHECK(expected.by_component[std::size_t(torus)] == 0);
  m.seeds();
  const Certificate seeds_only = certify(m.triangulation(), m.vertices().size(), expected);
  CHECK_FALSE(seeds_only.ok);
  // The fallback's points on a refused component lie on S.
  const std::vector<Facet> fs = restricted_facets(m.triangulation());
  for (int comp = 0; comp < 2; ++comp) {
    const Candidates pts = fallback_points(m.triangulation(), m.sampler(), fs, comp);
    CHECK(!pts.empty());
    for (const auto& [x, clearance] : pts) CHECK(std::abs(s.value(x)) < 1e-9);
  }
  m.refine();
  const Certificate cert = certify(m.triangulation(), m.vertices().size(), expected);
  CHECK(cert.ok);
  CHECK(cert.bad.empty());
  CHECK(euler_mismatches(cert, expected).empty());
  CHECK(cert.topology.sorted_euler() == std::vector<long long>{0, 2});
  REQUIRE(cert.facets.size() == cert.mesh.triangles.size());
  // Restricted facets in vertex-id order, each restricted.
  for (std::size_t k = 0; k < cert.facets.size(); ++k)
    CHECK((cert.facets[k].first->facet[cert.facets[k].second].state & kRestricted));
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
