// The topology certificate by correspondence (match_components): a ball and
// a solid torus side by side in an anisotropic, rotated grid; meshes made
// from their voxel boundary (triangulated quads, exact or jittered inside
// the active cubes) must pass, and meshes with the right sorted Euler list
// but the components in each other's places, a torus meshed as a sphere, a
// missing or a doubled component must be refused, naming the component.
#include "mesh/surface_certificate.hpp"
#include "mesh/topology.hpp"
#include "shapes.hpp"

#include <catch2/catch.hpp>

using namespace imgmesh;
using namespace imgmesh::test;

namespace {

ComponentCorrespondence check(const Tri& m, const BinaryImage& img) {
  const VoxelBoundary b = voxel_boundary(img);
  return match_components(mesh_topology(m.points.size(), m.tris), m.points, img, b, mesh_topology(b),
                          default_place_tolerance(img));
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
    // The sphere lies on the torus's outer faces (euler 2 against 0); the
    // torus where the ball is has its hole's walls inside the ball, farther
    // than the tolerance from its faces.
    for (const auto& c : r.mesh) {
      CHECK(c.verdict == (c.euler == 2 ? "euler differs" : "unplaced"));
      CHECK(c.boundary == (c.euler == 2 ? torus : -1));
    }
    CHECK(r.failed_guarantee().find("euler 2, its bdCA(X) component " + std::to_string(torus) + " has 0") !=
          std::string::npos);
    CHECK(r.boundary[std::size_t(ball)].verdict == "unmatched");
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
