// VoxelSides' query (issue 38): the centres it calls wrong are those whose
// Delaunay cell lies on the other side of S, whatever it remembers from
// earlier passes (the centres found right, where their walks start).
#include "shapes.hpp"
#include "mesh/located_cells.hpp"
#include "surface/delmesh.hpp"
#include "surface/voxel_side_points.hpp"

#include <catch2/catch.hpp>

#include <set>
#include <vector>

using namespace imgmesh;
using namespace imgmesh::surface_detail;

namespace {
// The corners of the active cubes on the wrong side of W's cells, each
// located anew from the infinite cell: on a facet, edge or vertex, wrong
// if any cell holding it is; outside W's hull, outside.
long long wrong_by_walks(const DelMesh& m) {
  const Tr& tr = m.triangulation();
  const CubeGrid& g = m.grid();
  std::set<long long> centres;
  for (const ActiveCube& kc : g.sorted_cubes()) {
    const auto [x, y, z] = g.cube_of_key(kc.key());
    for (int e = 0; e < 8; ++e) centres.insert(g.key(x + (e & 1), y + (e >> 1 & 1), z + (e >> 2 & 1)));
  }
  long long wrong = 0;
  for (long long k : centres) {
    const auto [x, y, z] = g.cube_of_key(k);
    const Point p(double(x) * g.s[0], double(y) * g.s[1], double(z) * g.s[2]);
    Tr::Locate_type lt;
    int li, lj;
    const Ch c = tr.locate(p, lt, li, lj);
    std::vector<Ch> cells;
    located_cells(tr, c, lt, li, lj, cells);
    bool bad = false;
    for (Ch h : cells) bad = bad || (!tr.is_infinite(h) && m.sampler().inside_at(vec(tr.dual(h)))) != g.neg(x, y, z);
    wrong += bad;
  }
  return wrong;
}
// A sphere beside a torus (test_delmesh.cpp's), DELMESH seeded on them.
struct Seeded {
  FunctionSurface s{test::box(29, 19, 15), [](const Vec3& p) {
                      return std::min(test::sphere_f(p, {6.4, 8.3, 7.2}, 3.9), test::torus_f(p, {20.1, 9.2, 7.4}, 5.2, 2.1));
                    }};
  RestrictedDelaunayOptions o;
  DelMesh m{s, o};
  Seeded() {
    m.prepare();
    m.seeds();
  }
};
} // namespace

TEST_CASE("VoxelSides: the wrong centres of a pass that remembers the last are those a walk to each finds") {
  Seeded seeded;
  DelMesh& m = seeded.m;
  const double guard = 1e-3 * m.grid().delta;
  VoxelSidePoints kept;
  long long wrong = 0, refused = 0;
  // The seeds alone: most foreground centres lie outside W's hull.
  Candidates pts = kept(m.triangulation(), m.sampler(), m.vertices(), m.vertices()[0], guard, wrong, refused);
  CHECK(wrong == wrong_by_walks(m));
  REQUIRE(wrong > 10);
  // Passes on a changing W: each remembers the last.
  for (int pass = 0; pass < 4 && !pts.empty(); ++pass) {
    for (std::size_t k = 0; k < pts.size(); k += 2) m.insert(pts[k].first, kVoxelSide);
    wrong = 0;
    pts = kept(m.triangulation(), m.sampler(), m.vertices(), m.vertices().back(), guard, wrong, refused);
    CHECK(wrong == wrong_by_walks(m));
  }
  // Every point found lies on S.
  for (const auto& [x, clearance2] : pts) {
    CHECK(std::abs(seeded.s.value(x)) < 1e-6);
    CHECK(clearance2 > 0);
  }
}

TEST_CASE("VoxelSides: where a centre's walk starts changes no point, order or count") {
  Seeded seeded;
  DelMesh& m = seeded.m;
  const double guard = 1e-3 * m.grid().delta;
  // From the cells centres were last found in, and from the last centre's
  // cell alone, on the same W pass after pass. The seeds alone leave many
  // foreground centres outside W's hull, where the walk picks the cell.
  VoxelSidePoints near(true), last(false);
  Candidates pts;
  int passes = 0;
  for (; passes < 6; ++passes) {
    long long wrong_near = 0, wrong_last = 0, refused_near = 0, refused_last = 0;
    pts = near(m.triangulation(), m.sampler(), m.vertices(), m.vertices().back(), guard, wrong_near, refused_near);
    const Candidates ref = last(m.triangulation(), m.sampler(), m.vertices(), m.vertices().back(), guard, wrong_last, refused_last);
    CHECK(wrong_near == wrong_last);
    CHECK(refused_near == refused_last);
    REQUIRE(pts.size() == ref.size());
    for (std::size_t k = 0; k < pts.size(); ++k) {
      CHECK(pts[k].first == ref[k].first);
      CHECK(pts[k].second == ref[k].second);
    }
    if (pts.empty()) break;
    for (std::size_t k = 0; k < pts.size(); k += 3) m.insert(pts[k].first, kVoxelSide);
  }
  CHECK(passes >= 2);
}
