// The quad-mesh state (lib/quadsmooth/smooth_mesh.cpp): the input contract
// and a patch's rollback.
#include "smooth_test_support.hpp"

#include "quadsmooth/smooth.hpp"
#include "quadsmooth/smooth_mesh.hpp"
#include "util/error.hpp"

#include <catch2/catch.hpp>

#include <cmath>

using namespace imgmesh;
using namespace quadsmooth_test;

TEST_CASE("bad input is refused with a clear error", "[smooth]") {
  PlanarMesh m;
  m.points = {{0, 0}, {1, 0}, {1, 1}, {0, 1}, {2, 0}, {2, 1}};
  m.elements = {{0, 3, 2, 1}};  // clockwise
  CHECK_THROWS_AS(check_quad_mesh(m), Error);
  m.elements = {{0, 1, 2, 7}};  // id out of range
  CHECK_THROWS_AS(check_quad_mesh(m), Error);
  m.elements = {{0, 1, 2, 3}, {1, 4, 5, 2}, {0, 1, 2, 3}};  // edge in three elements... and same direction
  CHECK_THROWS_AS(check_quad_mesh(m), Error);
  m.elements = {{0, 1, 2, 3}, {0, 1, 5, 2}};  // 0-1 used twice in the same direction
  CHECK_THROWS_AS(check_quad_mesh(m), Error);
  m.elements = {};
  CHECK_THROWS_AS(check_quad_mesh(m), Error);
  m.elements = {{0, 1, 2, 3}};
  m.points[2][0] = std::nan("");
  CHECK_THROWS_AS(check_quad_mesh(m), Error);
  m.points[2][0] = 1;
  CHECK_NOTHROW(check_quad_mesh(m));
}

TEST_CASE("a patch rolls back the stars, points and quads it saved and drops what was added", "[smooth]") {
  PlanarMesh m = jittered_grid(4, 3);
  const SmoothOptions opt;
  quadsmooth_detail::QuadMesh qm(m, opt, quadsmooth_detail::conforming_stars(m, {}));
  const State before = snapshot(qm);
  const int v = 6;  // an interior grid node
  REQUIRE_FALSE(qm.fixed[v]);
  quadsmooth_detail::Patch pt;
  qm.save_patch({v}, pt);
  qm.points[v][0] += 0.01;
  const int q0 = qm.vertex_quads[v][0];
  const quadsmooth_detail::Quad old = qm.quads[q0];
  const int e = qm.add_vertex({0.5, 0.5});
  pt.verts.push_back(e);
  const int q = qm.add_quad(q0);
  pt.quads.push_back(q);
  qm.set_quad(q0, {old[0], old[1], old[2], e});
  qm.set_quad(q, {old[2], old[3], old[0], e});
  quadsmooth_detail::relax(qm, pt);
  qm.rollback(pt);
  check_same(snapshot(qm), before);
  CHECK(m.points.size() == before.points.size());
}
