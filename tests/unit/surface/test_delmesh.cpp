// DELMESH's own work: insertion keeps EdgeSurface's answer for every facet
// current (incrementally), the steps' guarantees, and the input checks.
#include "shapes.hpp"
#include "surface/delmesh.hpp"
#include "surface/edge_surface.hpp"
#include "util/error.hpp"

#include <catch2/catch.hpp>

#include <algorithm>
#include <array>
#include <map>
#include <random>
#include <vector>

using namespace imgmesh;
using namespace imgmesh::surface_detail;

namespace {
// Every finite facet holds what EdgeSurface says of it now (the incremental
// updates missed none); a surface centre kept from before its Voronoi edge
// shrank (DelMesh::shrunk_edge) is the same root, within the root
// finder's tolerance (1e-11 voxel) of EdgeSurface's on the shorter edge.
int stale_facets(const DelMesh& m) {
  const Tr& tr = m.triangulation();
  int stale = 0;
  for (auto it = tr.finite_facets_begin(); it != tr.finite_facets_end(); ++it) {
    const FacetInfo now = edge_surface_of(tr, m.sampler(), it->first, it->second);
    const FacetInfo& kept = it->first->facet[it->second];
    const Ch n = it->first->neighbor(it->second);
    const FacetInfo& other = n->facet[n->index(it->first)];
    if (now.state != kept.state || other.state != kept.state) ++stale;
    // The state read from the record numbers alone, on both sides.
    else if (it->first->facet.restricted(it->second) != bool(kept.state & kRestricted) ||
             n->facet.restricted(n->index(it->first)) != bool(kept.state & kRestricted) ||
             !it->first->facet.computed(it->second) || !n->facet.computed(n->index(it->first)))
      ++stale;
    else if ((now.state & kRestricted) &&
             dist2(Vec3{now.x[0], now.x[1], now.x[2]}, Vec3{kept.x[0], kept.x[1], kept.x[2]}) > 1e-18 * m.grid().delta * m.grid().delta)
      ++stale;
  }
  return stale;
}

// Two components of S, one of genus 1, on a 29x19x15 grid.
double sphere_and_torus(const Vec3& p) {
  const Vec3 a{6.4, 8.3, 7.2}, c{20.1, 9.2, 7.4};
  return std::min(test::sphere_f(p, a, 3.9), test::torus_f(p, c, 5.2, 2.1));
}
} // namespace

TEST_CASE("DELMESH: seeds on S, refinement keeps every facet's EdgeSurface answer current, points on S") {
  FunctionSurface s(test::box(29, 19, 15), sphere_and_torus);
  RestrictedDelaunayOptions o;
  DelMesh m(s, o);
  m.prepare();
  REQUIRE(m.grid().components == 2);
  m.seeds();
  CHECK(m.inserted(kSeed) == long(m.vertices().size()));
  CHECK(stale_facets(m) == 0);
  m.refine();
  CHECK(m.vertices().size() > 100);
  CHECK(stale_facets(m) == 0);
  long long total = 0;
  for (int origin = 0; origin < kOrigins; ++origin) total += m.inserted(Origin(origin));
  CHECK(total == long(m.vertices().size()));
  for (Vh v : m.vertices()) {
    REQUIRE(v != Vh());
    CHECK(std::abs(s.value(vec(v->point()))) < 1e-9);
    CHECK(v->info().comp >= 0);
  }
}

TEST_CASE("DELMESH's insert: a point outside the hull at the infinite vertex's point goes in") {
  const Vec3 c{8.3, 8.1, 7.7};
  FunctionSurface s(test::box(17, 17, 17), [&](const Vec3& p) { return test::sphere_f(p, c, 5.1); });
  DelMesh m(s, RestrictedDelaunayOptions{});
  m.prepare();
  m.seeds();
  // The origin is outside the seeds' hull: its conflict zone holds infinite
  // cells. CGAL leaves the infinite vertex's point as it was constructed
  // (zeros, or whatever the memory held): made (0,0,0) here.
  m.triangulation().infinite_vertex()->set_point(Point(0, 0, 0));
  CHECK(m.insert(Vec3{0, 0, 0}, kBox));
  CHECK(m.vertices().back()->point() == Point(0, 0, 0));
  CHECK_FALSE(m.insert(Vec3{0, 0, 0}, kBox));  // a vertex now
}

TEST_CASE("DELMESH's insert: refuses a vertex twice and non-seed points beyond --max-points") {
  const Vec3 c{8.3, 8.1, 7.7};
  FunctionSurface s(test::box(17, 17, 17), [&](const Vec3& p) { return test::sphere_f(p, c, 5.1); });
  RestrictedDelaunayOptions o;
  o.max_points = 12;
  DelMesh m(s, o);
  m.prepare();
  m.seeds();
  const std::size_t n = m.triangulation().number_of_vertices();
  const Vec3 x = vec(m.vertices()[0]->point());
  CHECK_FALSE(m.insert(x, kQuality));
  CHECK(m.triangulation().number_of_vertices() == n);
  while (m.triangulation().number_of_vertices() < o.max_points) REQUIRE(m.insert(Vec3{c[0] + 0.01 * double(m.vertices().size()), c[1], c[2] - 5.1}, kQuality));
  CHECK_FALSE(m.insert(Vec3{c[0], c[1] + 5.1, c[2]}, kQuality));
  CHECK(m.insert(Vec3{c[0], c[1] + 5.1, c[2]}, kSeed));  // seeds always go in
  CHECK(stale_facets(m) == 0);
}

TEST_CASE("DELMESH's input checks: empty S, S touching the grid's border, non-finite samples") {
  RestrictedDelaunayOptions o;
  FunctionSurface empty(test::box(8, 8, 8), [](const Vec3&) { return 1.0; });
  CHECK_THROWS_AS(DelMesh(empty, o).prepare(), Error);
  FunctionSurface touching(test::box(8, 8, 8), [](const Vec3& p) { return p[0] - 3.5; });
  CHECK_THROWS_AS(DelMesh(touching, o).prepare(), Error);
  FunctionSurface nan(test::box(8, 8, 8), [](const Vec3& p) { return p[0] > 6 ? NAN : 1.0; });
  CHECK_THROWS_AS(DelMesh(nan, o).prepare(), Error);
}

TEST_CASE("FacetRefs: four 30-bit record numbers in 15 bytes, each read back as written, its neighbours untouched") {
  // Only put/ref (no FacetPool records are taken or released).
  const std::uint32_t top = FacetPool::kLimit - 1;
  const std::uint32_t values[] = {0, 1, 2, top, top - 1, 0x2aaaaaaau, 0x15555555u, 12345678};
  for (std::uint32_t a : values)
    for (std::uint32_t b : values) {
      std::uint32_t want[4];
      for (int k = 0; k < 4; ++k) want[k] = (k & 1) ? b : a;
      for (int shifted = 0; shifted < 4; ++shifted) {
        FacetRefs r;
        for (int k = 0; k < 4; ++k) r.put(k, want[(k + shifted) & 3]);
        for (int k = 0; k < 4; ++k) CHECK(r.ref(k) == want[(k + shifted) & 3]);
        // Rewrite one number: the others keep theirs.
        for (int k = 0; k < 4; ++k) {
          r.put(k, top ^ want[(k + shifted) & 3]);
          for (int m = 0; m < 4; ++m) CHECK(r.ref(m) == (m <= k ? top ^ want[(m + shifted) & 3] : want[(m + shifted) & 3]));
        }
        for (int k = 0; k < 4; ++k) r.put(k, FacetPool::kUncomputed);  // nothing to release at destruction
      }
    }
  // The cell stays 80 bytes (static_assert in delaunay_types.hpp).
  CHECK(sizeof(Tds::Cell) == 80);
}

TEST_CASE("circumcentres: the same bits from any insertion order; CellCentres gives them for kept and other cells") {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(0, 10);
  std::vector<Point> pts;
  for (int k = 0; k < 300; ++k) pts.emplace_back(u(rng), u(rng), u(rng));
  Tr a(pts.begin(), pts.end());
  std::shuffle(pts.begin(), pts.end(), rng);
  Tr b;
  for (const Point& p : pts) b.insert(p);  // other cells' vertex orders
  using Key = std::array<Point, 4>;
  auto key = [](Ch c) {
    Key k{c->vertex(0)->point(), c->vertex(1)->point(), c->vertex(2)->point(), c->vertex(3)->point()};
    std::sort(k.begin(), k.end());
    return k;
  };
  std::map<Key, Point> centre_a;
  for (auto c = a.finite_cells_begin(); c != a.finite_cells_end(); ++c) centre_a[key(c)] = c->circumcenter();
  int same = 0, cells = 0, reordered = 0;
  for (auto c = b.finite_cells_begin(); c != b.finite_cells_end(); ++c) {
    ++cells;
    const auto it = centre_a.find(key(c));
    REQUIRE(it != centre_a.end());
    const Point x = c->circumcenter();
    same += x.x() == it->second.x() && x.y() == it->second.y() && x.z() == it->second.z();
    reordered += key(c)[0] != c->vertex(0)->point();
  }
  CHECK(same == cells);
  CHECK(reordered > 0);
  // Kept: the cells at one vertex (more than the table's first 16 slots);
  // every finite cell, kept or not, gets tr.dual's bits.
  std::vector<Ch> kept;
  b.incident_cells(b.finite_vertices_begin(), std::back_inserter(kept));
  for (int k = 0; k < 3; ++k) b.incident_cells(std::next(b.finite_vertices_begin(), 5 * k + 1), std::back_inserter(kept));
  std::sort(kept.begin(), kept.end());
  kept.erase(std::unique(kept.begin(), kept.end()), kept.end());
  CHECK(kept.size() > 16);
  CellCentres centres;
  centres.assign(b, kept);
  int agree = 0;
  for (auto c = b.finite_cells_begin(); c != b.finite_cells_end(); ++c) agree += centres(b, c) == vec(b.dual(c));
  CHECK(agree == cells);
}

TEST_CASE("points off S: a Voronoi cell proved to miss S skips EdgeSurface, every facet still current") {
  const Vec3 c{12.3, 12.1, 11.7};
  const double R = 8.2;
  FunctionSurface s(test::box(25, 25, 25), [&](const Vec3& p) { return test::sphere_f(p, c, R); });
  DelMesh m(s, RestrictedDelaunayOptions{});
  m.prepare();
  m.seeds();
  m.refine();
  // Volume points on a lattice inside S, from its centre to near S, as
  // implicit2tet inserts its circumcentres (no REFINE between them).
  int inserted = 0;
  for (double z = -R + 0.35; z < R; z += 1.3)
    for (double y = -R + 0.35; y < R; y += 1.3)
      for (double x = -R + 0.35; x < R; x += 1.3)
        if (std::sqrt(x * x + y * y + z * z) < R - 0.1) inserted += m.insert(Vec3{c[0] + x, c[1] + y, c[2] + z}, kVolume);
  CHECK(inserted > 500);
  // Cells deep inside are proved (the inner fifth of the ball's volume
  // lies over 3.4 voxels from S); those reaching S are not.
  CHECK(m.cells_missed() > inserted / 10);
  CHECK(m.cells_missed() < inserted);
  CHECK(stale_facets(m) == 0);  // (break: every cell "proved" -> restricted facets missed)
}

TEST_CASE("DELMESH: a cavity's boundary facet whose Voronoi edge shrank keeps its answer, EdgeSurface agrees") {
  // Every facet skipped so is checked by EdgeSurface as it is skipped
  // (compare_missed_cells throws on a restricted one), and every facet's
  // answer is current at the end.
  FunctionSurface s(test::box(29, 19, 15), sphere_and_torus);
  RestrictedDelaunayOptions o;
  o.compare_missed_cells = true;
  DelMesh m(s, o);
  m.prepare();
  m.seeds();
  REQUIRE_NOTHROW(m.refine());
  CHECK(m.vertices().size() > 100);
  CHECK(stale_facets(m) == 0);  // (break: shrunk_edge kMisses for every restricted facet -> throws)
}

TEST_CASE("DELMESH: TopoDisk and SMOOTH run only where a vertex's restricted facets changed, the others would pass") {
  // Every check skipped as not stale runs all the same (compare_stale_checks
  // throws where one fails): an insertion near a vertex that changed none of
  // its restricted facets (a cavity's boundary facet kept) leaves its answers.
  FunctionSurface s(test::box(29, 19, 15), sphere_and_torus);
  RestrictedDelaunayOptions o;
  o.compare_stale_checks = true;
  DelMesh m(s, o);
  m.prepare();
  m.seeds();
  REQUIRE_NOTHROW(m.refine());
  CHECK(m.vertices().size() > 200);
  CHECK(m.checks_skipped() > 100);  // (break: a boundary facet's change not marked -> a skipped check fails, throws)
}
