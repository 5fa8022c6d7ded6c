#include "surface/facet_cycle.hpp"

#include "surface/facet_cycle_raster.hpp"
#include "surface/star.hpp"

#include "implicit/parallel.hpp"
#include "util/error.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <string>

namespace imgmesh::surface_detail {

// A cell keeps no centre of its own; its six edges are checked in one
// pass, by the ids of their ends, mostly one after the other (its four
// vertices' edges).
Vec3 CentreMemo::operator()(const Tr& tr, Ch c) {
  const auto slot = [](const void* p) { return std::size_t((reinterpret_cast<std::uintptr_t>(p) >> 3) * 0x9E3779B97F4A7C15ull >> 52); };
  static_assert(kSlots == std::size_t(1) << 12, "slot(): 64 - 52 bits");
  if (table.empty()) table.assign(kSlots, {nullptr, Vec3{}});
  std::size_t k = slot(&*c);
  for (; table[k].first; k = (k + 1) & (kSlots - 1))
    if (table[k].first == &*c) return table[k].second;
  if (2 * ++used > kSlots) {
    std::fill(table.begin(), table.end(), std::pair<const void*, Vec3>{nullptr, Vec3{}});
    used = 1;
    k = slot(&*c);
  }
  table[k] = {&*c, vec(tr.dual(c))};
  return table[k].second;
}

// h's half-planes on Pi, then its extent. h is convex, so it is cut out by
// the lines of its own edges, each dual to a facet pqw of the cells around
// pq: the ring of w's, not all of p's neighbours (the other faces of V(p)
// only touch h, at most); then the box's. Its extent: its finite Voronoi
// vertices (the circumcentres of the cells around pq), or the box's
// corners when h is unbounded.
static bool facet_polygon(const Tr& tr, const Tr::Edge& e, CentreMemo* memo, FacetRaster& h) {
  const Vh p = e.first->vertex(e.second), q = e.first->vertex(e.third);
  thread_local std::vector<Vh> ring;  // scratch reused across checks
  ring.clear();
  double a0 = INFINITY, a1 = -INFINITY, b0 = INFINITY, b1 = -INFINITY;
  bool bounded = true;
  Tr::Cell_circulator cc = tr.incident_cells(e), done = cc;
  do {
    for (int k = 0; k < 4; ++k) {
      const Vh w = cc->vertex(k);
      if (w != p && w != q && !tr.is_infinite(w) && std::find(ring.begin(), ring.end(), w) == ring.end()) ring.push_back(w);
    }
    if (tr.is_infinite(cc)) {
      bounded = false;
      continue;
    }
    const Vec3 c = memo ? (*memo)(tr, cc) : vec(tr.dual(cc));
    const double a = dot(sub(c, h.m), h.u), b = dot(sub(c, h.m), h.v);
    a0 = std::min(a0, a); a1 = std::max(a1, a); b0 = std::min(b0, b); b1 = std::max(b1, b);
  } while (++cc != done);
  h.s.hp.clear();
  for (Vh w : ring) h.add_neighbour(vec(w->point()));
  return h.extent(bounded, a0, a1, b0, b1);
}

// FacetCycle (8.2): does S have a closed curve inside the Voronoi facet h
// dual to the Delaunay edge pq (a piece of S that no Voronoi edge sees)?
// h = bisector plane Pi cut by V(p)'s half-spaces and the box: convex, so
// it is rasterised row by row on Pi at delta/4, into runs of one sign
// (delta/16 took 59% more of the bunny's instructions for the same mesh,
// and no benchmark image needs a certificate fallback at delta/4, even at
// the thesis's looser bounds: doc/benchmarks-log.md). The sign of f at a
// sample is the corner sign in an inactive cube (F1), the enclosure's in
// an active cube where the enclosure of f excludes 0, and f's sign
// elsewhere. A sign region that does not reach the border of h is
// enclosed by a cycle of S; its point farthest from p is found on the
// sample pair (region, neighbour) farthest from p that brackets a root, by
// root finding along that segment, i.e. on S inside Pi. Cycles narrower
// than the step are missed (like EdgeSurface); the final certificate
// catches what they would change. Facets of more than 64M samples are not
// rasterised: kSkipped, and DELMESH checks them again after later insertions.
// Each stage below either answers (kNone, kSkipped) or leaves what it
// found in `h` for the next.
FacetAnswer facet_cycle(const Tr& tr, const SurfaceSampler& f, const Tr::Edge& e, Vec3& out, FacetWalk how, CentreMemo* memo) {
  constexpr FacetAnswer kNone = FacetAnswer::kNone;
  const Vh p = e.first->vertex(e.second), q = e.first->vertex(e.third);
  const auto fail = [&](const std::string& what) {
    return Error("FacetCycle: " + what + " (edge " + std::to_string(p->info().id) + "-" + std::to_string(q->info().id) + ")");
  };
  thread_local FacetScratch scratch;
  FacetRaster h(f, scratch);
  if (!h.frame(vec(p->point()), vec(q->point()))) return kNone;
  if (!facet_polygon(tr, e, memo, h)) return kNone;
  h.no_active = how != FacetWalk::kFull && h.no_active_block();
  if (h.no_active && how == FacetWalk::kSpans) return kNone;
  if (!h.find_rows(how == FacetWalk::kCompare)) throw fail("the rows without the box's loose half-planes differ");
  if (h.rows_used < 3) return kNone;
  const long total = h.sample_count();
  if (total < 9) return kNone;
  if (total > 64000000) return FacetAnswer::kSkipped;  // the caller checks it again later
  h.find_spans(how);
  if (h.no_active && how == FacetWalk::kSpans) return kNone;
  if (const char* walk = h.sign_runs(how))
    throw fail(std::string("the ") + walk + " walk's runs differ from the samples' signs");
  if (h.no_active && h.any_neg && h.any_pos)  // kCompare only: kSpans returned above
    throw fail("samples of both signs though no block of the facet's rectangle, or no cube, is active");
  if (!(h.any_neg && h.any_pos)) return kNone;
  h.join_regions();
  if (!h.open_regions()) return kNone;  // every region reaches h's border
  h.enclosed_pairs();
  return h.cycle_point(out) ? FacetAnswer::kCycle : kNone;
}

// Pi, the bisector plane of pq: x = m + a u + b v, n its normal.
bool FacetRaster::frame(const Vec3& p, const Vec3& q) {
  pp = p;
  n = sub(q, p);
  const double nl = norm(n);
  if (!(nl > 0)) return false;
  n = {n[0] / nl, n[1] / nl, n[2] / nl};
  m = {(p[0] + q[0]) / 2, (p[1] + q[1]) / 2, (p[2] + q[2]) / 2};
  u = std::abs(n[0]) < 0.6 ? cross(n, Vec3{1, 0, 0}) : cross(n, Vec3{0, 1, 0});
  const double ul = norm(u);
  u = {u[0] / ul, u[1] / ul, u[2] / ul};
  v = cross(n, u);
  for (int k = 0; k < 3; ++k) inv_u[k] = 1 / u[k];
  return true;
}

// Sign regions (4-connected): runs of one sign overlapping in adjacent
// rows, joined by union-find.
long FacetRaster::find(long r) {
  while (s.parent[std::size_t(r)] != r) r = s.parent[std::size_t(r)] = s.parent[std::size_t(s.parent[std::size_t(r)])];
  return r;
}

void FacetRaster::join_regions() {
  s.parent.resize(s.runs.size());
  s.open.assign(s.runs.size(), 0);
  for (std::size_t r = 0; r < s.runs.size(); ++r) s.parent[r] = long(r);
  regions = long(s.runs.size());
  for (long j = 0; j < nb; ++j)
    for (long r = s.row_run[j]; r < s.row_run[j + 1]; ++r) {
      const FacetRun& x = s.runs[std::size_t(r)];
      if (j + 1 >= nb) continue;
      for (long r2 = s.row_run[j + 1]; r2 < s.row_run[j + 2]; ++r2) {
        const FacetRun& y = s.runs[std::size_t(r2)];
        if (y.e < x.s) continue;
        if (y.s > x.e) break;
        if (y.sg != x.sg) continue;
        const long a = find(r), b = find(r2);
        if (a != b) s.parent[std::size_t(a)] = b, --regions;
      }
    }
}

// A region is open where it reaches h's border itself: the sign at the
// exact border point beyond a sample next to the border must be the
// region's (else S passes in between and the region may be enclosed, as
// when a thin feature's cross-section nearly fills a narrow facet).
bool FacetRaster::open_regions() {
  long closed = regions;
  for (std::size_t r = 0; r < s.runs.size() && closed > 0; ++r) {
    const long root = find(long(r));
    if (!s.open[std::size_t(root)] && exits(s.runs[r])) s.open[std::size_t(root)] = 1, --closed;
  }
  return closed > 0;
}

bool FacetRaster::sign_at(double a, double b) const {
  const Vec3 x = at(a, b);
  long c[3];
  cube_of(x, c);
  return grid.active(c[0], c[1], c[2]) ? SurfaceSampler::inside(f.value(x)) : grid.neg(c[0], c[1], c[2]);
}

// h's border above (dir 1) or below (-1) a.
double FacetRaster::column_end(double a, int dir) const {
  double bmin = -INFINITY, bmax = INFINITY;
  for (const FacetHalfPlane& h : s.hp) {
    const double r = h.C - h.A * a;
    if (h.B > 1e-15) bmax = std::min(bmax, r / h.B);
    else if (h.B < -1e-15) bmin = std::max(bmin, r / h.B);
  }
  return dir > 0 ? std::min(bmax, b1) : std::max(bmin, b0);
}

// Does run x reach h's border (at its row's ends, or above or below)?
bool FacetRaster::exits(const FacetRun& x) const {
  const long j = x.j;
  const double b = b0 + j * step;
  const bool sg = x.sg;
  if (x.s == s.lo[j] && sign_at(s.alo_row[j], b) == sg) return true;
  if (x.e == s.hi[j] && sign_at(s.ahi_row[j], b) == sg) return true;
  for (int dir : {-1, 1}) {
    const long j2 = j + dir;
    const bool in_row = j2 >= 0 && j2 < nb;
    if (in_row && s.lo[j2] <= x.s && x.e <= s.hi[j2]) continue;  // every neighbour is in h
    for (long i = x.s; i <= x.e; ++i) {
      if (in_row && s.lo[j2] <= i && i <= s.hi[j2]) continue;  // that neighbour is in h
      const double a = a0 + i * step;
      if (sign_at(a, column_end(a, dir)) == sg) return true;
    }
  }
  return false;
}

// Enclosed regions: the sample pairs (region, neighbour), farthest from p
// first; along a row or an overlap of two rows the distance is convex, so
// only the ends of runs and overlaps are candidates. Every point is in h:
// a run at its row's end pairs with the exact border point (of the other
// sign, or the region would be open).
void FacetRaster::enclosed_pairs() {
  s.cands.clear();
  auto add = [&](const Vec3& xa, const Vec3& xb) {
    const Vec3 mid{(xa[0] + xb[0]) / 2, (xa[1] + xb[1]) / 2, (xa[2] + xb[2]) / 2};
    s.cands.push_back({-dist2(mid, pp), {xa, xb}});
  };
  for (long j = 0; j < nb; ++j)
    for (long r = s.row_run[j]; r < s.row_run[j + 1]; ++r) {
      if (s.open[std::size_t(find(r))]) continue;
      const FacetRun& x = s.runs[std::size_t(r)];
      const double b = b0 + j * step;
      if (x.s > s.lo[j]) add(point(x.s, j), point(x.s - 1, j));
      else add(point(x.s, j), at(s.alo_row[j], b));
      if (x.e < s.hi[j]) add(point(x.e, j), point(x.e + 1, j));
      else add(point(x.e, j), at(s.ahi_row[j], b));
      for (long j2 : {j - 1, j + 1}) {
        if (j2 < 0 || j2 >= nb) continue;  // no row there (row_run has nb + 1 entries)
        for (long r2 = s.row_run[j2]; r2 < s.row_run[j2 + 1]; ++r2) {
          const FacetRun& y = s.runs[std::size_t(r2)];
          if (y.e < x.s) continue;
          if (y.s > x.e) break;
          if (y.sg == x.sg) continue;
          const long s0 = std::max(x.s, y.s), e0 = std::min(x.e, y.e);
          add(point(s0, j), point(s0, j2));
          add(point(e0, j), point(e0, j2));
        }
      }
    }
}

// The farthest pair that brackets a root of f (signs are f's own, or F1's
// corner sign, which f has in an inactive cube; the check makes sure).
bool FacetRaster::cycle_point(Vec3& x) {
  std::sort(s.cands.begin(), s.cands.end(), [](const auto& c, const auto& d) { return c.first < d.first; });
  for (const auto& c : s.cands)
    if (f.bisect(c.second[0], c.second[1], f.value(c.second[0]), x)) return true;
  return false;
}

Candidates facet_cycle_points(const Tr& tr, const SurfaceSampler& f, const std::vector<Vh>& vertices, const IdSet& changed,
                              std::uint32_t& stamp, int threads, long long& checks, std::vector<int>& skipped,
                              FacetWalk how, std::size_t chunk) {
  // The edges with a new end (a vertex of `changed`), each once: every
  // lower end's edges to higher ids, by id (the points come back in the
  // order of the edges' ids (lo, hi)). The lower ends are the new vertices
  // and their older neighbours of smaller id. The edges are checked a
  // chunk at a time (of at least `chunk` edges, a lower end's edges in one
  // chunk), not gathered first:
  // the first pass takes every edge, and its list was the run's peak
  // (brain label 4: 6 MB of edges beside the triangulation).
  std::vector<Ch> cells;
  // take(b, c) for each finite neighbour b of a, once, with a cell c at ab.
  auto neighbours = [&](Vh a, auto&& take) {
    ++stamp;
    cells.clear();
    star_cells(tr, a, cells);
    for (Ch c : cells)
      for (int k = 0; k < 4; ++k) {
        const Vh b = c->vertex(k);
        if (b == a || tr.is_infinite(b) || b->info().stamp == stamp) continue;
        b->info().stamp = stamp;
        take(b, c);
      }
  };
  std::vector<int> lows;
  {
    std::vector<char> is_low(vertices.size(), 0);
    auto low = [&](int id) {
      if (!is_low[std::size_t(id)]) is_low[std::size_t(id)] = 1, lows.push_back(id);
    };
    changed.for_each([&](int ia) {
      const Vh a = vertices[std::size_t(ia)];
      if (a == Vh()) return;  // deleted
      low(ia);
      neighbours(a, [&](Vh b, Ch) {
        if (b->info().id < ia && !changed.has(b->info().id)) low(b->info().id);
      });
    });
  }
  // The lower ends in Morton order of their cubes, not by id (ids follow
  // the refinement's priorities, all over S): an edge's cells are looked at
  // again from its other ends' edges, which then come soon after, while
  // their circumcentres are still in the memo (and their cells in cache).
  // The points are put back in edge order below.
  {
    const CubeGrid& g = f.grid();
    const auto morton = [&](int id) {
      const Vec3 x = vec(vertices[std::size_t(id)]->point());
      std::uint64_t key = 0;
      for (int k = 0; k < 3; ++k) {
        const auto c = std::uint64_t(std::clamp(floor_long(x[k] / g.s[k]), 0L, g.n[k] - 2));
        for (int b = 0; b < 21; ++b) key |= (c >> b & 1) << (3 * b + k);
      }
      return key;
    };
    std::vector<std::pair<std::uint64_t, int>> keyed;
    keyed.reserve(lows.size());
    for (int id : lows) keyed.emplace_back(morton(id), id);
    std::sort(keyed.begin(), keyed.end());
    for (std::size_t k = 0; k < keyed.size(); ++k) lows[k] = keyed[k].second;
  }
  // An edge by the ids of its ends and a cell at it; p (its first vertex): lo.
  struct EdgeAt { int lo, hi; Ch c; };
  std::vector<EdgeAt> edges;
  auto edge = [&](const EdgeAt& e) {
    return Tr::Edge(e.c, e.c->index(vertices[std::size_t(e.lo)]), e.c->index(vertices[std::size_t(e.hi)]));
  };
  // The checks only read the triangulation, so they run on --threads
  // threads; the points go in afterwards, in edge order. The few cycle
  // points are kept per thread, with their edge.
  const unsigned nt = implicit_detail::resolve_threads(unsigned(std::max(1, threads)));
  std::vector<std::uint8_t> found;
  std::vector<std::vector<std::pair<std::size_t, Vec3>>> cycles(nt);
  // The cycle points with their edges' ends (lo, hi), put in edge order at the end.
  std::vector<std::pair<std::pair<int, int>, Vec3>> all;
  skipped.clear();
  for (std::size_t next = 0; next < lows.size();) {
    edges.clear();
    while (next < lows.size() && edges.size() < chunk) {
      const int ia = lows[next++];
      const Vh a = vertices[std::size_t(ia)];
      const bool a_new = changed.has(ia);
      const std::size_t first = edges.size();
      neighbours(a, [&](Vh b, Ch c) {
        const int ib = b->info().id;
        if (ib > ia && (a_new || changed.has(ib))) edges.push_back(EdgeAt{ia, ib, c});
      });
      std::sort(edges.begin() + std::ptrdiff_t(first), edges.end(), [](const EdgeAt& x, const EdgeAt& y) { return x.hi < y.hi; });
    }
    checks += static_cast<long long>(edges.size());
    found.assign(edges.size(), std::uint8_t(FacetAnswer::kNone));
    for (auto& c : cycles) c.clear();
    implicit_detail::parallel_for(long(edges.size()), nt, [&](long a, long b, unsigned t) {
      CentreMemo memo;  // W does not change during the pass
      for (long k = a; k < b; ++k) {
        Vec3 x;
        const FacetAnswer answer = facet_cycle(tr, f, edge(edges[std::size_t(k)]), x, how, &memo);
        found[std::size_t(k)] = std::uint8_t(answer);
        if (answer == FacetAnswer::kCycle) cycles[t].emplace_back(std::size_t(k), x);
      }
    });
    for (std::size_t k = 0; k < edges.size(); ++k)
      if (found[k] == std::uint8_t(FacetAnswer::kSkipped)) skipped.push_back(edges[k].lo);
    for (const auto& c : cycles)
      for (const auto& [k, x] : c) all.push_back({{edges[k].lo, edges[k].hi}, x});
  }
  std::sort(all.begin(), all.end(), [](const auto& x, const auto& y) { return x.first < y.first; });
  Candidates pts;
  for (const auto& [e, x] : all) pts.emplace_back(x, dist2(x, vec(vertices[std::size_t(e.first)]->point())));
  return pts;
}

} // namespace imgmesh::surface_detail
