// implicit2mesh's guarantees on analytic surfaces (sampled on a grid, so that
// the certificate compares with the voxel boundary of {f < 0}).
#include "checks.hpp"
#include "surface/restricted_delaunay.hpp"
#include "util/error.hpp"

#include <catch2/catch.hpp>
#include <cmath>
#include <memory>
#include <random>
#ifdef __GLIBC__
#include <malloc.h>
#endif

using namespace imgmesh;

namespace {

Geometry grid(std::size_t nx, std::size_t ny, std::size_t nz) {
  Geometry g;
  g.size = {nx, ny, nz};
  return g;
}

double sphere(const Vec3& p, const Vec3& c, double r) {
  return std::sqrt(test::dist2(p, c)) - r;
}
double torus(const Vec3& p, const Vec3& c, double R, double r) {
  const double dx = p[0] - c[0], dy = p[1] - c[1], dz = p[2] - c[2];
  const double q = std::sqrt(dx * dx + dy * dy) - R;
  return std::sqrt(q * q + dz * dz) - r;
}

// Every guarantee of the "Done when", checked from the output alone.
void check_guarantees(const ImplicitSurface& s, const RestrictedDelaunayResult& r, double rho0) {
  INFO("failure: " << r.failed_guarantee());
  CHECK(r.failed_guarantee().empty());
  REQUIRE(!r.mesh.triangles.empty());
  const MeshTopology t = mesh_topology(r.mesh);
  CHECK(t.closed);
  CHECK(t.manifold);
  CHECK(t.oriented);
  const MeshTopology expected = voxel_boundary_topology(s.samples());
  CHECK(t.sorted_euler() == expected.sorted_euler());
  CHECK(triangle_quality_report(r.mesh).largest_radius_edge_ratio() <= rho0 * (1 + 1e-9));
  double max_f = 0;
  for (const Vec3& p : r.mesh.points) max_f = std::max(max_f, std::abs(s.value(s.to_local(p))));
  CHECK(max_f < 1e-6);
  CHECK(test::empty_ball_violations(r.mesh, r.centers) == 0);
  // The thesis's TOPOLOGY steps suffice: the final fallback never acts.
  CHECK(r.to_json().at("topology_fallback_rounds").number() == 0);
  // Voxel centres: inside the mesh exactly when inside S (away from S by
  // more than the mesh's deviation, i.e. |g| > half a voxel).
  const SampleGrid& g = s.samples();
  // The mesh deviates from S by about its facets' distance to their surface
  // Delaunay ball centres: test the voxel centres farther than that.
  const double margin = std::max(0.5, 2 * r.to_json().at("max_distance_to_plane").number());
  INFO("margin " << margin);
  int wrong = 0, tested = 0;
  for (std::size_t z = 0; z < g.size[2]; ++z)
    for (std::size_t y = 0; y < g.size[1]; ++y)
      for (std::size_t x = 0; x < g.size[0]; ++x) {
        if (std::abs(g(x, y, z)) < margin) continue;
        ++tested;
        const double w = test::winding_number(r.mesh, g.world(double(x), double(y), double(z)));
        if ((g(x, y, z) < 0) != (w > 0.5)) ++wrong;
      }
  CHECK(tested > 0);
  CHECK(wrong == 0);
}

} // namespace

TEST_CASE("ball: one sphere, chi 2") {
  const Vec3 c{10.3, 9.7, 10.1};
  FunctionSurface s(grid(21, 21, 21), [&](const Vec3& p) { return sphere(p, c, 6.3); });
  RestrictedDelaunayOptions o;
  auto r = restricted_delaunay_mesh(s, o);
  check_guarantees(s, r, o.ratio);
  CHECK(r.topology.sorted_euler() == std::vector<long long>{2});
}

TEST_CASE("solid torus: chi 0, tighter ratio") {
  const Vec3 c{12.2, 11.9, 7.1};
  FunctionSurface s(grid(25, 25, 15), [&](const Vec3& p) { return torus(p, c, 7, 2.6); });
  RestrictedDelaunayOptions o;
  o.ratio = 1.5;
  auto r = restricted_delaunay_mesh(s, o);
  check_guarantees(s, r, o.ratio);
  CHECK(r.topology.sorted_euler() == std::vector<long long>{0});
}

TEST_CASE("two balls and a hollow ball: several components") {
  const Vec3 a{7.1, 8.2, 8.3}, b{17.3, 8.9, 8.1};
  FunctionSurface two(grid(26, 17, 17), [&](const Vec3& p) { return std::min(sphere(p, a, 4.1), sphere(p, b, 3.7)); });
  RestrictedDelaunayOptions o;
  auto r = restricted_delaunay_mesh(two, o);
  check_guarantees(two, r, o.ratio);
  CHECK(r.topology.sorted_euler() == std::vector<long long>{2, 2});

  const Vec3 c{10.2, 9.9, 10.3};
  FunctionSurface shell(grid(21, 21, 21), [&](const Vec3& p) { const double d = sphere(p, c, 5.4); return std::abs(d) - 2.2; });
  auto h = restricted_delaunay_mesh(shell, o);
  check_guarantees(shell, h, o.ratio);
  CHECK(h.topology.sorted_euler() == std::vector<long long>{2, 2});
}

TEST_CASE("world geometry: anisotropic spacing, rotated and reflected axes") {
  Geometry g = grid(17, 17, 13);
  g.spacing = {1.0, 1.0, 1.5};
  g.origin = {-5, 3, 2};
  // D = Rz(30 deg) Rx(40 deg) S, S swapping x and y (a reflection): D is not
  // symmetric, so D and D^T (its inverse) differ and a mix-up shows.
  const double a = M_PI / 6, b = 2 * M_PI / 9;
  const double rz[9] = {std::cos(a), -std::sin(a), 0, std::sin(a), std::cos(a), 0, 0, 0, 1};
  const double rx[9] = {1, 0, 0, 0, std::cos(b), -std::sin(b), 0, std::sin(b), std::cos(b)};
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) {
      double rij = 0;  // (Rz Rx)_ij
      for (int k = 0; k < 3; ++k) rij += rz[3 * i + k] * rx[3 * k + j];
      g.direction[3 * i + (j == 0 ? 1 : j == 1 ? 0 : 2)] = rij;  // times S: columns 0 and 1 swapped
    }
  REQUIRE(std::abs(g.direction[1] - g.direction[3]) > 0.1);
  const Vec3 c = g.world(8.3, 7.9, 6.2);
  FunctionSurface s(g, [&](const Vec3& p) { return sphere(p, c, 5.3); });
  RestrictedDelaunayOptions o;
  auto r = restricted_delaunay_mesh(s, o);
  check_guarantees(s, r, o.ratio);
  CHECK(test::winding_number(r.mesh, c) == Approx(1).margin(1e-6));  // outward orientation
  // Normals from grad f in world coordinates: unit and along p - c.
  add_normals(s, r.mesh);
  REQUIRE(r.mesh.normals.size() == r.mesh.points.size());
  double worst = 1;
  for (std::size_t k = 0; k < r.mesh.points.size(); ++k) {
    const Vec3& p = r.mesh.points[k];
    const Vec3& n = r.mesh.normals[k];
    const double l = std::sqrt(test::dist2(p, c));
    CHECK(n[0] * n[0] + n[1] * n[1] + n[2] * n[2] == Approx(1).margin(1e-9));
    worst = std::min(worst, (n[0] * (p[0] - c[0]) + n[1] * (p[1] - c[1]) + n[2] * (p[2] - c[2])) / l);
  }
  CHECK(worst > 0.999);
}

TEST_CASE("limits: refused parameters, max points, deterministic output") {
  const Vec3 c{8.3, 8.1, 7.7};
  FunctionSurface s(grid(17, 17, 17), [&](const Vec3& p) { return sphere(p, c, 5.1); });
  RestrictedDelaunayOptions o;
  o.ratio = 1.12;
  CHECK_THROWS_AS(restricted_delaunay_mesh(s, o), UsageError);
  o.ratio = 2;
  o.roughness = 0.25;
  CHECK_THROWS_AS(restricted_delaunay_mesh(s, o), UsageError);
  o.roughness = M_PI / 3;
  o.max_points = 12;
  auto r = restricted_delaunay_mesh(s, o);
  CHECK(r.max_points_hit);
  CHECK_FALSE(r.failed_guarantee().empty());
  o.max_points = 1000000;
  auto a = restricted_delaunay_mesh(s, o), b = restricted_delaunay_mesh(s, o);
  CHECK(a.mesh.points == b.mesh.points);
  CHECK(a.mesh.triangles == b.mesh.triangles);

  FunctionSurface empty(grid(8, 8, 8), [](const Vec3&) { return 1.0; });
  CHECK_THROWS_AS(restricted_delaunay_mesh(empty, o), Error);
  FunctionSurface touching(grid(8, 8, 8), [](const Vec3& p) { return p[0] - 3.5; });
  CHECK_THROWS_AS(restricted_delaunay_mesh(touching, o), Error);
}

TEST_CASE("VoxelSides' count: a failed guarantee when on and a centre is left, reported either way") {
  RestrictedDelaunayResult r;
  r.topology_ok = r.ratio_ok = r.roughness_ok = r.distance_ok = true;
  r.voxel_sides_counted = true;
  r.voxel_sides.checked = 100;
  r.voxel_sides.background_inside = 2;
  r.voxel_sides.on_surface = 1;
  CHECK(r.failed_guarantee().empty());  // off: counted only
  CHECK(r.to_json().at("voxel_sides").at("wrong_side").number() == 3);
  r.voxel_sides_on = true;
  CHECK(r.failed_guarantee() == "3 voxel centre(s) on the wrong side of the surface");
  r.voxel_sides = VoxelSides();
  CHECK(r.failed_guarantee().empty());
}

TEST_CASE("max-distance bounds the surface Delaunay ball centre's distance to the facet plane") {
  const Vec3 c{10.3, 9.7, 10.1};
  FunctionSurface s(grid(21, 21, 21), [&](const Vec3& p) { return sphere(p, c, 6.3); });
  RestrictedDelaunayOptions o;
  o.max_distance = 0.05;
  auto r = restricted_delaunay_mesh(s, o);
  check_guarantees(s, r, o.ratio);
  CHECK(r.distance_ok);
  CHECK(r.to_json().at("max_distance_to_plane").number() <= 0.05);
}

TEST_CASE("FacetCycle: a thin torus sampled sparsely needs it (without it, HandleDetection must act), and then no fallback") {
  // Tube radius 1.1 voxels: the six extremal seeds and TopoDisk leave whole
  // cycles of S inside Voronoi facets that no Voronoi edge crosses.
  const Vec3 c{11.6, 11.3, 4.6};
  FunctionSurface s(grid(24, 24, 10), [&](const Vec3& p) { return torus(p, c, 8.1, 1.1); });
  RestrictedDelaunayOptions o;
  o.roughness = 0.9 * M_PI;  // coarse: SMOOTH would otherwise add the samples
  // VoxelSides runs before FacetCycle and HandleDetection, and its points
  // would put the cycles right themselves (measured): off, to see those two.
  o.voxel_sides = false;
  o.facet_cycle = false;
  auto without = restricted_delaunay_mesh(s, o);
  // The cycles left in Voronoi facets make S inside those Voronoi cells an
  // annulus or two pieces: HandleDetection, the last step of TOPOLOGY, sees
  // them and repairs the topology before the certificate.
  CHECK(without.to_json().at("points_inserted").at("handle_detection").number() > 0);
  CHECK(without.topology_ok);
  CHECK(without.to_json().at("topology_fallback_rounds").number() == 0);
  o.facet_cycle = true;
  for (std::uint64_t seed : {0, 1, 2}) {
    o.seed = seed;
    auto r = restricted_delaunay_mesh(s, o);
    check_guarantees(s, r, o.ratio);
    CHECK(r.to_json().at("points_inserted").at("facet_cycle").number() > 0);
    CHECK(r.topology.sorted_euler() == std::vector<long long>{0});
  }
}

TEST_CASE("seed deletion (7.6.2): TOPOLOGY restores the topology without the seeds") {
  // A ball beside a torus: every seed goes, and the guarantees hold.
  RestrictedDelaunayOptions o;
  o.seed_deletion = true;
  const Vec3 a{6.4, 8.3, 7.2}, c{20.1, 9.2, 7.4};
  FunctionSurface s(grid(29, 19, 15), [&](const Vec3& p) { return std::min(sphere(p, a, 3.9), torus(p, c, 5.2, 2.1)); });
  auto r = restricted_delaunay_mesh(s, o);
  check_guarantees(s, r, o.ratio);
  CHECK(r.topology.sorted_euler() == std::vector<long long>{0, 2});
  CHECK(r.to_json().at("seeds_deleted").number() == r.to_json().at("points_inserted").at("seed").number());
  // CGAL's vertex removal orders its new cells by address: the mesh must not
  // depend on that, nor on the thread count. Blocks of random sizes kept
  // between the runs move CGAL's cells to other addresses (without them,
  // runs in one process often reuse the same ones and agree by luck).
  std::mt19937 rng(7);
  std::vector<std::vector<char>> junk;
  for (int run = 0; run < 8; ++run) {
    for (int k = 0; k < 50; ++k) junk.emplace_back(rng() % 200000);
    for (int k = 0; k < 20; ++k) junk.erase(junk.begin() + long(rng() % junk.size()));
    o.threads = 1 + run % 2;
    auto again = restricted_delaunay_mesh(s, o);
    INFO("run " << run);
    CHECK(again.mesh.points == r.mesh.points);
    CHECK(again.mesh.triangles == r.mesh.triangles);
  }
}

TEST_CASE("seed deletion also deletes HandleDetection's points, and puts back those whose handle returns (8.3)") {
  // The thin torus without FacetCycle: HandleDetection finds the cycles.
  const Vec3 c{11.6, 11.3, 4.6};
  FunctionSurface s(grid(24, 24, 10), [&](const Vec3& p) { return torus(p, c, 8.1, 1.1); });
  RestrictedDelaunayOptions o;
  o.roughness = 0.9 * M_PI;
  o.facet_cycle = false;
  o.seed_deletion = true;
  // Only deleted points can be put back. Whether a handle returns depends
  // on the seed (the order of the seeds), so over several seeds some must
  // come back: a mesher that never puts one back fails here.
  double restored = 0;
  for (std::uint64_t seed : {0, 1, 2, 3}) {
    o.seed = seed;
    auto r = restricted_delaunay_mesh(s, o);
    check_guarantees(s, r, o.ratio);
    CHECK(r.topology.sorted_euler() == std::vector<long long>{0});
    const Json j = r.to_json();
    INFO("seed " << seed << ": " << j.at("handle_points_restored").number() << " of "
                 << j.at("handle_points_deleted").number() << " put back");
    CHECK(j.at("handle_points_deleted").number() > 0);
    CHECK(j.at("handle_points_restored").number() <= j.at("handle_points_deleted").number());
    restored += j.at("handle_points_restored").number();
  }
  CHECK(restored > 0);
}

// The mesh depends on the data only: not on where the allocator puts CGAL's
// cells (their handles compare by address), nor on the thread count. A
// solid torus is meshed, then meshed again after the heap was
// rearranged, so that CGAL's growing blocks land in other places and in
// another address order (glibc: every large block mmapped, at decreasing
// addresses), on 2 threads.
TEST_CASE("deterministic: the same mesh after another allocation pattern and on other thread counts") {
  const Vec3 c{12.2, 11.9, 7.1};
  FunctionSurface s(grid(25, 25, 15), [&](const Vec3& p) { return torus(p, c, 7, 2.6); });
  RestrictedDelaunayOptions o;
  const auto a = restricted_delaunay_mesh(s, o);
  // Holes of decreasing size at increasing addresses, each after a block
  // kept: best fit puts CGAL's small first blocks high, its later ones low.
  std::vector<std::unique_ptr<char[]>> holes, kept;
  for (int k = 48; k > 0; --k) {
    holes.emplace_back(new char[std::size_t(k) * 1024]);
    kept.emplace_back(new char[48]);
  }
  holes.clear();
#ifdef __GLIBC__
  mallopt(M_MMAP_THRESHOLD, 4096);
#endif
  o.threads = 2;
  const auto b = restricted_delaunay_mesh(s, o);
#ifdef __GLIBC__
  mallopt(M_MMAP_THRESHOLD, 128 * 1024);
#endif
  INFO(a.mesh.points.size() << " and " << b.mesh.points.size() << " vertices");
  CHECK(a.mesh.points == b.mesh.points);
  CHECK(a.mesh.triangles == b.mesh.triangles);
  CHECK(a.centers == b.centers);
}
