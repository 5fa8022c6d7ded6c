// FacetCycle (8.2) alone: a closed curve of S inside the Voronoi facet of
// one Delaunay edge, which no Voronoi edge sees.
#include "shapes.hpp"
#include "surface/delmesh.hpp"
#include "surface/facet_cycle.hpp"
#include "surface/facet_cycle_raster.hpp"

#include <catch2/catch.hpp>

using namespace imgmesh;
using namespace imgmesh::surface_detail;

namespace {
// W = p, q and `others` (DELMESH inserts them); the Delaunay edge pq.
Tr::Edge edge_pq(DelMesh& m, const Vec3& p, const Vec3& q, const std::vector<Vec3>& others) {
  m.prepare();
  for (const Vec3& x : others) REQUIRE(m.insert(x, kSeed));
  REQUIRE(m.insert(p, kSeed));
  REQUIRE(m.insert(q, kSeed));
  const Vh vp = m.vertices()[m.vertices().size() - 2], vq = m.vertices().back();
  Ch c;
  int i, j;
  REQUIRE(m.triangulation().is_edge(vp, vq, c, i, j));
  return Tr::Edge(c, i, j);
}
// Four points far outside the grid: pq's Voronoi facet is then the whole
// bisector plane inside the grid's box.
const std::vector<Vec3> kFar{{-900, -900, -900}, {900, -800, -700}, {100, 900, -600}, {50, 80, 950}};
const Vec3 kMid{10.2, 9.8, 10.1};
const Vec3 kP{kMid[0], kMid[1], kMid[2] - 6}, kQ{kMid[0], kMid[1], kMid[2] + 6};
} // namespace

TEST_CASE("FacetCycle: a small sphere or a thin torus around the middle of pq is a cycle in pq's Voronoi facet") {
  RestrictedDelaunayOptions o;
  FunctionSurface s(test::box(21, 21, 21), [&](const Vec3& x) { return test::sphere_f(x, kMid, 2.2); });
  DelMesh m(s, o);
  const Tr::Edge pq = edge_pq(m, kP, kQ, kFar);
  Vec3 x;
  REQUIRE(facet_cycle(m.triangulation(), m.sampler(), pq, x) == FacetAnswer::kCycle);
  CHECK(std::abs(s.value(x)) < 1e-9);                                  // on S
  CHECK(std::abs(dist2(x, kP) - dist2(x, kQ)) < 1e-6 * dist2(x, kP));  // on the bisector
  // The torus lies in the bisector plane: S meets it in two circles.
  FunctionSurface t(test::box(21, 21, 21), [&](const Vec3& y) { return test::torus_f(y, kMid, 4.5, 1.0); });
  DelMesh mt(t, o);
  const Tr::Edge pq2 = edge_pq(mt, kP, kQ, kFar);
  REQUIRE(facet_cycle(mt.triangulation(), mt.sampler(), pq2, x) == FacetAnswer::kCycle);
  CHECK(std::abs(t.value(x)) < 1e-9);
  CHECK(std::abs(x[2] - kMid[2]) < 1e-6);
}

// The samples' step (delta/4) is FacetCycle's resolution: a cycle whose
// disk holds a circle of radius more than the step / sqrt 2 holds a sample
// wherever the raster falls. A ball of radius 0.215 voxel around the voxel
// centre (10, 10, 10), cut 0.1 from its centre: a circle of radius 0.19
// (> 0.177). pq's facet, a disk of radius ~0.9 (a ring of W 7 voxels out,
// as below), and with it the raster, moved to 25 places around it.
TEST_CASE("FacetCycle: a cycle of S wider than two samples is found wherever the raster falls") {
  RestrictedDelaunayOptions o;
  FunctionSurface s(test::box(21, 21, 21), [&](const Vec3& y) { return test::sphere_f(y, Vec3{10, 10, 10}, 0.215); });
  for (int k = 0; k < 25; ++k) {
    const Vec3 mid{10 + 0.11 * (k % 5 - 2), 10 + 0.13 * (k / 5 - 2), 10.1};
    std::vector<Vec3> ring = kFar;
    for (int r = 0; r < 6; ++r)
      ring.push_back({mid[0] + 7 * std::cos(r * M_PI / 3 + 0.2), mid[1] + 7 * std::sin(r * M_PI / 3 + 0.2), mid[2] + 0.3});
    DelMesh m(s, o);
    const Tr::Edge pq = edge_pq(m, {mid[0], mid[1], mid[2] - 6}, {mid[0], mid[1], mid[2] + 6}, ring);
    Vec3 x;
    INFO("place " << k);
    REQUIRE(facet_cycle(m.triangulation(), m.sampler(), pq, x) == FacetAnswer::kCycle);
    CHECK(std::abs(s.value(x)) < 1e-9);
  }
}

TEST_CASE("FacetCycle: no cycle where S crosses the facet to its border, or misses it") {
  RestrictedDelaunayOptions o;
  // Two close sheets x = 9.85 and 10.55 (a flat box): six points of W 7
  // voxels around pq's middle make pq's Voronoi facet a disk of radius ~0.9,
  // which the sheets cross from border to border.
  FunctionSurface sheets(test::box(21, 21, 21), [](const Vec3& y) { return test::sheets_f(y, 10.2, 0.35, 2, 18); });
  std::vector<Vec3> ring = kFar;
  for (int k = 0; k < 6; ++k)
    ring.push_back({kMid[0] + 7 * std::cos(k * M_PI / 3 + 0.2), kMid[1] + 7 * std::sin(k * M_PI / 3 + 0.2), kMid[2] + 0.3});
  DelMesh m(sheets, o);
  const Tr::Edge pq = edge_pq(m, kP, kQ, ring);
  Vec3 x;
  CHECK(facet_cycle(m.triangulation(), m.sampler(), pq, x) == FacetAnswer::kNone);
  // The same sheets with the whole plane as pq's facet: their cross-section
  // is a closed rectangle, a cycle.
  DelMesh all(sheets, o);
  const Tr::Edge pq_all = edge_pq(all, kP, kQ, kFar);
  CHECK(facet_cycle(all.triangulation(), all.sampler(), pq_all, x) == FacetAnswer::kCycle);
  // A wider facet (a disk of radius ~5: W's ring 12.8 voxels out) that the
  // sheets cross from border to border: most of its samples lie in inactive
  // cubes, away from the sheets, and are not walked cube by cube; still no cycle.
  std::vector<Vec3> wide = kFar;
  for (int k = 0; k < 6; ++k)
    wide.push_back({kMid[0] + 12.8 * std::cos(k * M_PI / 3 + 0.2), kMid[1] + 12.8 * std::sin(k * M_PI / 3 + 0.2), kMid[2] + 0.3});
  DelMesh mw(sheets, o);
  const Tr::Edge pq_wide = edge_pq(mw, kP, kQ, wide);
  CHECK(facet_cycle(mw.triangulation(), mw.sampler(), pq_wide, x) == FacetAnswer::kNone);
  // A ball beside the plane: S does not meet the facet.
  FunctionSurface ball(test::box(21, 21, 21), [&](const Vec3& y) { return test::sphere_f(y, Vec3{10, 10, 15}, 2.5); });
  DelMesh mb(ball, o);
  const Tr::Edge pq_ball = edge_pq(mb, kP, kQ, kFar);
  CHECK(facet_cycle(mb.triangulation(), mb.sampler(), pq_ball, x) == FacetAnswer::kNone);
}

TEST_CASE("FacetCycle's pass: on a thin torus after the seeds it finds cycle points on S, each in its facet") {
  const Vec3 c{11.6, 11.3, 4.6};
  FunctionSurface s(test::box(24, 24, 10), [&](const Vec3& p) { return test::torus_f(p, c, 8.1, 1.1); });
  RestrictedDelaunayOptions o;
  DelMesh m(s, o);
  m.prepare();
  m.seeds();
  IdSet all;
  for (Vh v : m.vertices()) all.add(v->info().id);
  std::uint32_t stamp = 1000;
  long long checks = 0;
  std::vector<int> skipped;
  const Candidates pts = facet_cycle_points(m.triangulation(), m.sampler(), m.vertices(), all, stamp, 2, checks, skipped);
  CHECK(skipped.empty());
  CHECK(checks == long(m.triangulation().number_of_finite_edges()));  // every edge once
  REQUIRE(!pts.empty());
  for (const auto& [x, clearance2] : pts) {
    CHECK(std::abs(s.value(x)) < 1e-9);
    // x's nearest sites: at least two of W at the same distance (a Voronoi facet).
    const Vh n = m.triangulation().nearest_vertex(Point(x[0], x[1], x[2]));
    CHECK(dist2(x, vec(n->point())) == Approx(clearance2).epsilon(1e-6));
  }
}

TEST_CASE("FacetCycle's pass in chunks: every edge with a new end checked once, the same points in the same order for any chunk") {
  // Six tori (components, each seeded): cycles all over the box, so that
  // the points' order (by their edges' ids) is not the checks' order.
  FunctionSurface s(test::box(40, 28, 10), [&](const Vec3& p) {
    double d = INFINITY;
    for (int k = 0; k < 6; ++k)
      d = std::min(d, test::torus_f(p, Vec3{7.6 + 12.3 * (k % 3), 7.3 + 12.6 * (k / 3), 4.6 + 0.2 * (k % 2)}, 4.3 + 0.2 * k, 1.1));
    return d;
  });
  RestrictedDelaunayOptions o;
  DelMesh m(s, o);
  m.prepare();
  m.seeds();
  const Tr& tr = m.triangulation();
  // The new vertices: every third id, and the edges with a new end.
  IdSet changed;
  for (Vh v : m.vertices())
    if (v->info().id % 3 == 1) changed.add(v->info().id);
  // The reference: those edges by (lower id, higher id), one check each.
  std::vector<std::pair<std::pair<int, int>, Tr::Edge>> edges;
  for (auto e = tr.finite_edges_begin(); e != tr.finite_edges_end(); ++e) {
    int a = e->first->vertex(e->second)->info().id, b = e->first->vertex(e->third)->info().id;
    if (a > b) std::swap(a, b);
    if (!changed.has(a) && !changed.has(b)) continue;
    const Tr::Edge pq(e->first, e->first->index(m.vertices()[std::size_t(a)]), e->first->index(m.vertices()[std::size_t(b)]));
    edges.push_back({{a, b}, pq});
  }
  std::sort(edges.begin(), edges.end(), [](const auto& x, const auto& y) { return x.first < y.first; });
  Candidates reference;
  for (const auto& [ids, pq] : edges) {
    Vec3 x;
    if (facet_cycle(tr, m.sampler(), pq, x) == FacetAnswer::kCycle)
      reference.emplace_back(x, dist2(x, vec(m.vertices()[std::size_t(ids.first)]->point())));
  }
  const long long want = static_cast<long long>(edges.size());
  REQUIRE(want > 0);
  REQUIRE(want < long(tr.number_of_finite_edges()));
  std::uint32_t stamp = 1000;
  std::vector<Candidates> runs;
  for (std::size_t chunk : {std::size_t(1), std::size_t(7), std::size_t(1) << 20}) {
    long long checks = 0;
    std::vector<int> skipped;
    runs.push_back(facet_cycle_points(tr, m.sampler(), m.vertices(), changed, stamp, 2, checks, skipped, FacetWalk::kSpans, chunk));
    CHECK(checks == want);
    CHECK(skipped.empty());
  }
  REQUIRE(!reference.empty());
  CHECK(runs[0] == reference);
  CHECK(runs[1] == runs[0]);
  CHECK(runs[2] == runs[0]);
}

// The rows alone (facet_cycle_raster.hpp): a sample of Pi is in its row's
// range iff it is in h, i.e. no farther from p than from any neighbour w
// given and inside the box, judged here by the distances themselves.
TEST_CASE("FacetCycle's rows: a row's samples are exactly those nearer p than every neighbour, inside the box") {
  FunctionSurface s(test::box(21, 21, 21), [](const Vec3& y) { return test::sphere_f(y, Vec3{10, 10, 10}, 3); });
  CubeGrid grid(s.samples());
  SurfaceSampler f(s, grid);
  struct Case {
    Vec3 p, q;
    std::vector<Vec3> ring;
  };
  // A hexagon inside the box on a tilted plane; a strip the box cuts
  // (two neighbours, pq near a corner of the box).
  std::vector<Vec3> hexagon;
  for (int k = 0; k < 6; ++k) hexagon.push_back({10 + 7 * std::cos(k * M_PI / 3 + 0.3), 10 + 7 * std::sin(k * M_PI / 3 + 0.3), 10.4 + 0.3 * (k % 2)});
  const std::vector<Case> cases{{{10.3, 9.1, 6.2}, {9.9, 10.8, 14.1}, hexagon},
                                {{2.1, 1.7, 0.4}, {1.3, 2.2, 3.9}, {{5.5, 1.1, 2.0}, {-1.9, 2.4, 2.1}}}};
  for (const Case& c : cases) {
    FacetScratch scratch;
    FacetRaster h(f, scratch);
    REQUIRE(h.frame(c.p, c.q));
    for (const Vec3& w : c.ring) h.add_neighbour(w);
    REQUIRE(h.extent(false, 0, 0, 0, 0));  // unbounded: the box's extent
    REQUIRE(h.find_rows(true));            // the box's loose half-planes change no row
    long inside = 0, rows = 0;
    for (long j = 0; j < h.nb; ++j) {
      rows += scratch.hi[std::size_t(j)] >= scratch.lo[std::size_t(j)];
      for (long i = -2; i <= long((h.a1 - h.a0) / h.step) + 2; ++i) {
        const Vec3 x = h.point(i, j);
        double margin = INFINITY;  // > 0 inside h, < 0 outside
        for (const Vec3& w : c.ring) margin = std::min(margin, dist2(x, w) - dist2(x, c.p));
        for (int k = 0; k < 3; ++k) margin = std::min({margin, x[k], grid.hi[k] - x[k]});
        if (std::abs(margin) < 1e-9) continue;  // on h's border: either way
        INFO("row " << j << " sample " << i << " margin " << margin);
        CHECK((scratch.lo[std::size_t(j)] <= i && i <= scratch.hi[std::size_t(j)]) == (margin > 0));
        inside += margin > 0;
      }
    }
    CHECK(inside > 100);
    CHECK(h.rows_used == rows);
    CHECK(h.sample_count() >= inside);
  }
}
