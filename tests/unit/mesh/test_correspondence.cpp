// The topology certificate by correspondence (match_components): a ball and
// a solid torus side by side in an anisotropic, rotated grid; meshes made
// from their voxel boundary (triangulated quads, exact or jittered inside
// the active cubes) must pass, and meshes with the right sorted Euler list
// but the components in each other's places, a torus meshed as a sphere, a
// missing or a doubled component must be refused, naming the component.
#include "mesh/meshinfo.hpp"
#include "mesh/topology.hpp"

#include <catch2/catch.hpp>

#include <random>
#include <set>

using namespace imgmesh;

namespace {

constexpr int kNx = 40, kNy = 16, kNz = 16;

// A box "ball" at x 4..13 and a box ring "solid torus" at x 26..35 with the
// same outer box, so that mirroring x -> 39 - x puts each on the other's
// outer surface. Spacing and direction are not the identity.
BinaryImage two_solids(bool fill_hole) {
  Geometry g;
  g.dimension = 3;
  g.size = {kNx, kNy, kNz};
  g.origin = {-5, 3, 7};
  g.spacing = {0.8, 1.2, 2.0};
  g.direction = {0, -1, 0, 1, 0, 0, 0, 0, 1};  // a quarter turn about z
  BinaryImage img(g, 0);
  for (int z = 3; z <= 12; ++z)
    for (int y = 3; y <= 12; ++y)
      for (int x = 0; x < kNx; ++x) {
        const bool ball = x >= 4 && x <= 13;
        const bool ring = x >= 26 && x <= 35 && (fill_hole || !(x >= 29 && x <= 32 && y >= 6 && y <= 9));
        img(x, y, z) = ball || ring;
      }
  return img;
}

struct Tri {
  std::vector<Vec3> points;
  std::vector<std::array<int, 3>> tris;
  void add(const Tri& o) {
    const int n = int(points.size());
    points.insert(points.end(), o.points.begin(), o.points.end());
    for (auto t : o.tris) tris.push_back({t[0] + n, t[1] + n, t[2] + n});
  }
};

// bdCA(X)'s quads as triangles in world coordinates, the components in
// `keep` only; mirrored in x about the grid's centre (faces flipped to stay
// outward) and each vertex moved by up to `jitter` lattice steps per axis.
Tri triangulate(const BinaryImage& img, const std::set<int>& keep, bool mirror, double jitter = 0,
                unsigned seed = 1) {
  const VoxelBoundary b = voxel_boundary(img);
  const MeshTopology bt = mesh_topology(b);
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-jitter, jitter);
  Tri t;
  for (std::size_t v = 0; v < b.lattice_ids.size(); ++v) {
    const auto c = b.corner(v);
    double i = double(c[0]) - 0.5, j = double(c[1]) - 0.5, k = double(c[2]) - 0.5;
    if (mirror) i = double(kNx - 1) - i;
    t.points.push_back(img.world(i + u(rng), j + u(rng), k + u(rng)));
  }
  for (std::size_t f = 0; f + 1 < b.offsets.size(); ++f) {
    const int* q = &b.corners[b.offsets[f]];
    if (!keep.count(bt.component_of[std::size_t(q[0])])) continue;
    if (mirror) { t.tris.push_back({q[0], q[2], q[1]}); t.tris.push_back({q[0], q[3], q[2]}); }
    else { t.tris.push_back({q[0], q[1], q[2]}); t.tris.push_back({q[0], q[2], q[3]}); }
  }
  return t;
}

ComponentCorrespondence check(const Tri& m, const BinaryImage& img) {
  const VoxelBoundary b = voxel_boundary(img);
  return match_components(mesh_topology(m.points.size(), m.tris), m.points, img, b, mesh_topology(b));
}

// The bdCA(X) component index of the ball (euler 2) and of the torus (euler 0).
std::pair<int, int> ball_and_torus(const BinaryImage& img) {
  const MeshTopology bt = mesh_topology(voxel_boundary(img));
  REQUIRE(bt.components.size() == 2);
  REQUIRE(bt.manifold);
  const int ball = bt.components[0].euler == 2 ? 0 : 1;
  REQUIRE(bt.components[std::size_t(ball)].euler == 2);
  REQUIRE(bt.components[std::size_t(1 - ball)].euler == 0);
  return {ball, 1 - ball};
}

} // namespace

TEST_CASE("certificate by correspondence: the right mesh passes", "[topology][correspondence]") {
  const BinaryImage img = two_solids(false);
  ball_and_torus(img);
  SECTION("the triangulated voxel boundary") {
    const auto r = check(triangulate(img, {0, 1}, false), img);
    CHECK(r.matches());
    CHECK(r.failed_guarantee().empty());
    REQUIRE(r.mesh.size() == 2);
    CHECK(r.mesh[0].boundary != r.mesh[1].boundary);
    for (const auto& m : r.mesh) CHECK(m.placed == m.vertices);
  }
  SECTION("vertices moved inside their active cubes (as a mesher's on S)") {
    const auto r = check(triangulate(img, {0, 1}, false, 0.49, 7), img);
    CHECK(r.matches());
    CHECK(r.to_json().at("matches").boolean());
  }
}

TEST_CASE("certificate by correspondence refuses wrong meshes", "[topology][correspondence]") {
  const BinaryImage img = two_solids(false);
  const auto [ball, torus] = ball_and_torus(img);
  const MeshTopology it = mesh_topology(voxel_boundary(img));
  SECTION("mirrored in x: the sphere where the torus is, the torus where the ball is") {
    const Tri m = triangulate(img, {0, 1}, true);
    const MeshTopology mt = mesh_topology(m.points.size(), m.tris);
    REQUIRE(mt.closed);
    REQUIRE(mt.oriented);
    CHECK(same_topology(mt, it));  // the sorted Euler lists agree: the old check passed this
    const auto r = check(m, img);
    CHECK_FALSE(r.matches());
    REQUIRE(r.mesh.size() == 2);
    for (const auto& c : r.mesh) {
      CHECK(c.verdict == "euler differs");
      CHECK(c.boundary == (c.euler == 2 ? torus : ball));
    }
    CHECK(r.failed_guarantee().find("euler 2, its bdCA(X) component " + std::to_string(torus) + " has 0") !=
          std::string::npos);
  }
  SECTION("the torus meshed as a sphere (its hole filled)") {
    const auto r = check(triangulate(two_solids(true), {0, 1}, false), img);
    CHECK_FALSE(r.matches());
    int differs = 0;
    for (const auto& c : r.mesh)
      if (c.verdict == "euler differs") { ++differs; CHECK(c.boundary == torus); }
    CHECK(differs == 1);
    CHECK(r.boundary[std::size_t(ball)].verdict == "ok");
  }
  SECTION("a missing component") {
    // Keep only the ball's quads.
    const auto r = check(triangulate(img, {ball}, false), img);
    CHECK_FALSE(r.matches());
    CHECK(r.boundary[std::size_t(torus)].verdict == "unmatched");
    CHECK(r.boundary[std::size_t(ball)].verdict == "ok");
    CHECK(r.failed_guarantee().find("bdCA(X) component " + std::to_string(torus) + " (euler 0): no mesh component") !=
          std::string::npos);
  }
  SECTION("a component meshed twice") {
    Tri m = triangulate(img, {0, 1}, false);
    m.add(triangulate(img, {ball}, false, 0.3, 3));
    const auto r = check(m, img);
    CHECK_FALSE(r.matches());
    CHECK(r.boundary[std::size_t(ball)].verdict == "matched twice");
    CHECK(r.boundary[std::size_t(ball)].matched_by.size() == 2);
    CHECK(r.boundary[std::size_t(torus)].verdict == "ok");
  }
}

TEST_CASE("meshinfo --image: the swapped mesh fails with a per-component verdict", "[meshinfo][correspondence]") {
  const BinaryImage img = two_solids(false);
  auto poly = [](const Tri& t) {
    PolyMesh m;
    m.points = t.points;
    for (const auto& f : t.tris) m.faces.push_back({f[0], f[1], f[2]});
    return m;
  };
  const MeshInfo right = mesh_info(poly(triangulate(img, {0, 1}, false)), "m.off", &img, "wc.nrrd");
  CHECK(right.failed_guarantee().empty());
  CHECK(right.report.at("image").at("correspondence").at("matches").boolean());
  const MeshInfo swapped = mesh_info(poly(triangulate(img, {0, 1}, true)), "s.off", &img, "wc.nrrd");
  CHECK_FALSE(swapped.to_json().at("matches_image").boolean());
  CHECK_FALSE(swapped.report.at("image").at("matches").boolean());
  CHECK(swapped.failed_guarantee().find("mesh component 0: euler") != std::string::npos);
  const std::string text = format_report(swapped.report);
  CHECK(text.find("DOES NOT MATCH") != std::string::npos);
  CHECK(text.find("mesh #0: euler differs") != std::string::npos);
}
