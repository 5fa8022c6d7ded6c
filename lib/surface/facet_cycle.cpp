#include "surface/facet_cycle.hpp"

#include "implicit/parallel.hpp"
#include "util/error.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <string>

namespace imgmesh::surface_detail {

// FacetCycle (8.2): does S have a closed curve inside the Voronoi facet h
// dual to the Delaunay edge pq (a piece of S that no Voronoi edge sees)?
// h = bisector plane Pi cut by V(p)'s half-spaces and the box: convex, so
// it is rasterised row by row on Pi at delta/4, into runs of one sign
// (delta/16 took 59% more of the bunny's instructions for the same mesh,
// and no benchmark image needs a certificate fallback at delta/4, even at
// the thesis's looser bounds: doc/benchmarks.md). The sign of f at a
// sample is the corner sign in an inactive cube (F1), the enclosure's in
// an active cube where the enclosure of f excludes 0, and f's sign
// elsewhere. A sign region that does not reach the border of h is
// enclosed by a cycle of S; its point farthest from p is found on the
// sample pair (region, neighbour) farthest from p that brackets a root, by
// root finding along that segment, i.e. on S inside Pi. Cycles narrower
// than the step are missed (like EdgeSurface); the final certificate
// catches what they would change. Facets of more than 64M samples are not
// rasterised: kSkipped, and DELMESH checks them again after later insertions.
// A cell has six edges, three at p: each centre once for p's edges (a
// cell keeps no centre of its own).
Vec3 CentreMemo::operator()(const Tr& tr, Ch c) {
  for (const auto& [d, x] : kept)
    if (d == c) return x;
  kept.emplace_back(c, vec(tr.dual(c)));
  return kept.back().second;
}

FacetAnswer facet_cycle(const Tr& tr, const SurfaceSampler& f, const Tr::Edge& e, Vec3& out, FacetWalk how, CentreMemo* memo) {
  constexpr FacetAnswer kNone = FacetAnswer::kNone;
  const CubeGrid& grid = f.grid();
  const Vh p = e.first->vertex(e.second), q = e.first->vertex(e.third);
  const Vec3 pp = vec(p->point()), pq = vec(q->point());
  Vec3 n = sub(pq, pp);
  const double nl = norm(n);
  if (!(nl > 0)) return kNone;
  n = {n[0] / nl, n[1] / nl, n[2] / nl};
  const Vec3 m{(pp[0] + pq[0]) / 2, (pp[1] + pq[1]) / 2, (pp[2] + pq[2]) / 2};
  Vec3 u = std::abs(n[0]) < 0.6 ? cross(n, Vec3{1, 0, 0}) : cross(n, Vec3{0, 1, 0});
  const double ul = norm(u);
  u = {u[0] / ul, u[1] / ul, u[2] / ul};
  const Vec3 v = cross(n, u);
  // Half-planes A a + B b <= C on Pi (x = m + a u + b v): h's edges and the
  // box. h is convex, so it is cut out by the lines of its own edges, each
  // dual to a facet pqw of the cells around pq: the ring of w's, not all of
  // p's neighbours (the other faces of V(p) only touch h, at most).
  struct HP { double A, B, C; };
  // Scratch reused across checks (no allocation per edge).
  thread_local std::vector<HP> hp;
  thread_local std::vector<Vh> ring;
  hp.clear();
  ring.clear();
  // Extent on Pi: the finite Voronoi vertices of h (circumcentres of the
  // cells around pq), or the box's corners when h is unbounded.
  double a0 = INFINITY, a1 = -INFINITY, b0 = INFINITY, b1 = -INFINITY;
  bool bounded = true;
  {
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
      const double a = dot(sub(c, m), u), b = dot(sub(c, m), v);
      a0 = std::min(a0, a); a1 = std::max(a1, a); b0 = std::min(b0, b); b1 = std::max(b1, b);
    } while (++cc != done);
  }
  for (Vh w : ring) {
    const Vec3 pw = vec(w->point());
    const Vec3 d = sub(pw, pp);  // |x-p|^2 <= |x-w|^2  <=>  2 x.d <= |w|^2 - |p|^2
    const double C = dot(pw, pw) - dot(pp, pp) - 2 * dot(m, d);
    hp.push_back({2 * dot(u, d), 2 * dot(v, d), C});
  }
  for (int i = 0; i < 3; ++i) {  // 0 <= m_i + a u_i + b v_i <= hi_i
    hp.push_back({u[i], v[i], grid.hi[i] - m[i]});
    hp.push_back({-u[i], -v[i], m[i]});
  }
  // The box's corners projected (h lies in the box).
  double ba0 = INFINITY, ba1 = -INFINITY, bb0 = INFINITY, bb1 = -INFINITY;
  for (int k = 0; k < 8; ++k) {
    const Vec3 c{(k & 1) ? grid.hi[0] : 0, (k & 2) ? grid.hi[1] : 0, (k & 4) ? grid.hi[2] : 0};
    const double a = dot(sub(c, m), u), b = dot(sub(c, m), v);
    ba0 = std::min(ba0, a); ba1 = std::max(ba1, a); bb0 = std::min(bb0, b); bb1 = std::max(bb1, b);
  }
  if (!bounded) { a0 = ba0; a1 = ba1; b0 = bb0; b1 = bb1; }
  a0 = std::max(a0, ba0); a1 = std::min(a1, ba1); b0 = std::max(b0, bb0); b1 = std::min(b1, bb1);
  if (!(a0 < a1 && b0 < b1)) return kNone;
  // Tighten b by the polygon: rows where the a-interval is empty are skipped anyway.
  const double step = grid.delta / 4;
  const long nb = long(std::ceil((b1 - b0) / step)) + 1;
  // No active cube in any block (CubeGrid::kBlock^3 cubes) that the
  // samples' rectangle [a0, a1] x [b0, b_last] on Pi meets: every sample
  // lies in an inactive cube, and h (convex) passes from cube to cube
  // through shared corners, so every sample takes one sign (F1): no cycle.
  // Only where h has too few samples to be skipped (kSkipped below), so
  // that the answer is kNone either way; kCompare checks it at the end.
  const double b_end = b0 + double(nb - 1) * step;  // the last row
  // Rounding of the samples' coordinates: far below this.
  const double eps = 1e-9 * (grid.hi[0] + grid.hi[1] + grid.hi[2] + std::abs(a0) + std::abs(a1) + std::abs(b0) + std::abs(b_end));
  bool no_active = false;
  if (how != FacetWalk::kFull && (std::floor((a1 - a0) / step) + 1) * double(nb) <= 64000000) {
    long k0[3], k1[3];
    for (int k = 0; k < 3; ++k) {
      double xlo = INFINITY, xhi = -INFINITY;
      for (double a : {a0, a1})
        for (double b : {b0, b_end}) {
          const double x = m[k] + a * u[k] + b * v[k];
          xlo = std::min(xlo, x), xhi = std::max(xhi, x);
        }
      k0[k] = std::clamp(floor_long((xlo - eps) / grid.s[k]), 0L, grid.n[k] - 2) / CubeGrid::kBlock;
      k1[k] = std::clamp(floor_long((xhi + eps) / grid.s[k]), 0L, grid.n[k] - 2) / CubeGrid::kBlock;
    }
    no_active = true;
    for (long z = k0[2]; z <= k1[2] && no_active; ++z)
      for (long y = k0[1]; y <= k1[1] && no_active; ++y)
        for (long x = k0[0]; x <= k1[0] && no_active; ++x) no_active = !grid.block(x, y, z);
    if (no_active && how == FacetWalk::kSpans) return kNone;
  }
  // Rows: the a-interval where every half-plane holds.
  thread_local std::vector<long> lo, hi;
  thread_local std::vector<double> alo_row, ahi_row;  // h's exact border on each row
  // The half-planes by the sign of A, sorted once (not tested per row):
  // each row's bounds are the same min and max, in the same order.
  thread_local std::vector<HP> hp_hi, hp_lo, hp_flat;
  const double b_last = b0 + double(nb - 1) * step;
  // A box half-plane that holds with room to spare at the rows' rectangle
  // [a0, a1] x [b0, b_last] (it is linear: at its corners) changes no row's
  // bounds, which start at a0 and a1: skipped unless `all` (most facets lie
  // well inside the box, and the box was half of the half-planes).
  auto loose = [&](const HP& h) {
    const double a = h.A > 1e-15 ? a1 : h.A < -1e-15 ? a0 : 0;
    for (double b : {b0, b_last})
      if (!(h.C - h.B * b - h.A * a > 1e-9 * (std::abs(h.C) + std::abs(h.B * b) + std::abs(h.A * a)) + 1e-12 * grid.delta))
        return false;
    return true;
  };
  const std::size_t box_from = hp.size() - 6;  // the box's six, last
  long rows_used = 0;
  auto rows = [&](bool all) {
    lo.assign(nb, 0);
    hi.assign(nb, -1);
    alo_row.assign(nb, 0);
    ahi_row.assign(nb, 0);
    rows_used = 0;
    hp_hi.clear();
    hp_lo.clear();
    hp_flat.clear();
    for (std::size_t k = 0; k < hp.size(); ++k) {
      const HP& h = hp[k];
      if (k >= box_from && !all && loose(h)) continue;
      (h.A > 1e-15 ? hp_hi : h.A < -1e-15 ? hp_lo : hp_flat).push_back(h);
    }
    for (long j = 0; j < nb; ++j) {
      const double b = b0 + j * step;
      bool empty = false;
      for (const HP& h : hp_flat) empty = empty || h.C - h.B * b < 0;
      if (empty) continue;
      double alo = a0, ahi = a1;
      for (const HP& h : hp_hi) ahi = std::min(ahi, (h.C - h.B * b) / h.A);
      for (const HP& h : hp_lo) alo = std::max(alo, (h.C - h.B * b) / h.A);
      if (!(alo <= ahi)) continue;
      alo_row[j] = alo;
      ahi_row[j] = ahi;
      lo[j] = ceil_long((alo - a0) / step);
      hi[j] = floor_long((ahi - a0) / step);
      if (hi[j] >= lo[j]) ++rows_used;
    }
  };
  if (how == FacetWalk::kCompare) {
    // The rows with every half-plane: the skipped ones must change nothing.
    rows(true);
    const std::vector<long> lo_all = lo, hi_all = hi;
    const std::vector<double> alo_all = alo_row, ahi_all = ahi_row;
    rows(false);
    if (lo != lo_all || hi != hi_all || alo_row != alo_all || ahi_row != ahi_all)
      throw Error("FacetCycle: the rows without the box's loose half-planes differ (edge " + std::to_string(p->info().id) +
                  "-" + std::to_string(q->info().id) + ")");
  } else {
    rows(false);
  }
  if (rows_used < 3) return kNone;
  // Samples inside h, with their signs, as runs of one sign per row: an
  // inactive cube's samples all take its corner sign (F1), so the raster
  // jumps to the cube's exit; f is evaluated only in active cubes.
  long total = 0;
  for (long j = 0; j < nb; ++j) total += std::max(0L, hi[j] - lo[j] + 1);
  if (total < 9) return kNone;
  if (total > 64000000) return FacetAnswer::kSkipped;  // the caller checks it again later
  // Inlined (called per sample and per cube step). cube_of multiplies by
  // 1/s: a sample within rounding of a face may go to either cube, and
  // takes the same sign in both (f's sign on an inactive cube's faces is
  // its corners', F1).
  auto point = [&](long i, long j) __attribute__((always_inline)) {
    const double a = a0 + i * step, b = b0 + j * step;
    return Vec3{m[0] + a * u[0] + b * v[0], m[1] + a * u[1] + b * v[1], m[2] + a * u[2] + b * v[2]};
  };
  const double inv_s[3] = {1 / grid.s[0], 1 / grid.s[1], 1 / grid.s[2]};
  auto cube_of = [&](const Vec3& x, long c[3]) __attribute__((always_inline)) {
    for (int k = 0; k < 3; ++k) c[k] = std::clamp(floor_long(x[k] * inv_s[k]), 0L, grid.n[k] - 2);
  };
  // Only the samples near active cubes need a walk through the cubes: the
  // others lie in inactive cubes, and consecutive samples (delta/4 apart) in
  // cubes that share a corner, so a stretch of them takes one sign (F1): one
  // run. The stretches to walk, per row: each active cube among the samples'
  // cubes that Pi meets spans the rows and the samples between its corners'
  // extremes along v and u, one sample wider on each side, so that a
  // stretch begins and ends in inactive cubes.
  // Each cube's span of rows and samples; then per row (row_span[j] ..
  // row_span[j + 1]) the (s, e) of the cubes over it, by s: the cubes
  // sorted by s once and dealt to their rows (a sort of every row's spans
  // by (row, s) cost 2% of the run).
  struct CubeSpan { long j0, j1, s, e; };
  thread_local std::vector<CubeSpan> cube_spans;
  thread_local std::vector<std::pair<long, long>> spans;
  thread_local std::vector<long> row_span;
  cube_spans.clear();
  spans.clear();
  row_span.assign(nb + 1, 0);
  bool walk_all = true;
  if (how != FacetWalk::kFull) {
    Vec3 xlo{INFINITY, INFINITY, INFINITY}, xhi{-INFINITY, -INFINITY, -INFINITY};
    double cost = 0;  // the walk's cube steps, about
    for (long j = 0; j < nb; ++j) {
      if (hi[j] < lo[j]) continue;
      for (const Vec3& x : {point(lo[j], j), point(hi[j], j)})  // every sample's coordinates lie between these
        for (int k = 0; k < 3; ++k) xlo[k] = std::min(xlo[k], x[k]), xhi[k] = std::max(xhi[k], x[k]);
      cost += double(hi[j] - lo[j]) / 16 + 1;
    }
    long c0[3], c1[3];
    cube_of(xlo, c0);
    cube_of(xhi, c1);
    const double cubes = double(c1[0] - c0[0] + 1) * double(c1[1] - c0[1] + 1) * double(c1[2] - c0[2] + 1);
    if (cubes < 16 * cost || how == FacetWalk::kCompare) {  // else walking every row is cheaper
      walk_all = false;
      // Only the cubes of each line along x that come within the test's
      // reach of Pi (twice eps from it, and a cube more on each side) are
      // tested: in a facet's box most cubes lie far from its plane. Cube
      // (x, y, z)'s corners have signed distances x s_0 n_0 + e(y, z) + an
      // offset in [off_lo, off_hi].
      const double sn[3] = {grid.s[0] * n[0], grid.s[1] * n[1], grid.s[2] * n[2]};
      const double off_lo = std::min(0.0, sn[0]) + std::min(0.0, sn[1]) + std::min(0.0, sn[2]);
      const double off_hi = std::max(0.0, sn[0]) + std::max(0.0, sn[1]) + std::max(0.0, sn[2]);
      for (long z = c0[2]; z <= c1[2]; ++z)
        for (long y = c0[1]; y <= c1[1]; ++y) {
          const double e = -m[0] * n[0] + (double(y) * grid.s[1] - m[1]) * n[1] + (double(z) * grid.s[2] - m[2]) * n[2];
          const double lo_d = -2 * eps - off_hi - e, hi_d = 2 * eps - off_lo - e;  // lo_d <= x sn_0 <= hi_d
          long x0 = c0[0], x1 = c1[0];
          if (std::abs(sn[0]) > 1e-9 * grid.delta) {
            double t0 = lo_d / sn[0], t1 = hi_d / sn[0];
            if (t0 > t1) std::swap(t0, t1);
            x0 = std::max(x0, long(std::max(t0, double(x0 - 1))) - 1);
            x1 = std::min(x1, long(std::min(t1, double(x1 + 1))) + 1);
          } else if (lo_d > 0 || hi_d < 0) {
            continue;
          }
          for (long x = x0; x <= x1; ++x) {
            if (!grid.active(x, y, z)) continue;
            double dlo = INFINITY, dhi = -INFINITY, alo = INFINITY, ahi = -INFINITY, blo = INFINITY, bhi = -INFINITY;
            for (int k = 0; k < 8; ++k) {
              const Vec3 c{double(x + (k & 1)) * grid.s[0] - m[0], double(y + ((k >> 1) & 1)) * grid.s[1] - m[1],
                           double(z + ((k >> 2) & 1)) * grid.s[2] - m[2]};
              const double dn = dot(c, n), au = dot(c, u), bv = dot(c, v);
              dlo = std::min(dlo, dn), dhi = std::max(dhi, dn);
              alo = std::min(alo, au), ahi = std::max(ahi, au), blo = std::min(blo, bv), bhi = std::max(bhi, bv);
            }
            if (dlo > eps || dhi < -eps) continue;  // Pi misses the cube
            const long j0 = std::max(0L, floor_long((blo - eps - b0) / step) - 1);
            const long j1 = std::min(nb - 1, ceil_long((bhi + eps - b0) / step) + 1);
            const long s0 = floor_long((alo - eps - a0) / step) - 1, e0 = ceil_long((ahi + eps - a0) / step) + 1;
            if (j0 <= j1) cube_spans.push_back({j0, j1, s0, e0});
          }
        }
      // No active cube that Pi meets among the samples' cubes: every sample
      // lies in an inactive cube, and h (convex) passes from cube to cube
      // through shared corners, so all take one sign (F1): no cycle.
      no_active = no_active || cube_spans.empty();
      if (no_active && how == FacetWalk::kSpans) return kNone;
      std::sort(cube_spans.begin(), cube_spans.end(), [](const CubeSpan& x, const CubeSpan& y) { return x.s < y.s; });
      for (const CubeSpan& c : cube_spans)
        for (long j = c.j0; j <= c.j1; ++j) ++row_span[j + 1];
      for (long j = 0; j < nb; ++j) row_span[j + 1] += row_span[j];
      spans.resize(std::size_t(row_span[nb]));
      thread_local std::vector<long> fill_at;
      fill_at.assign(row_span.begin(), row_span.end() - 1);
      for (const CubeSpan& c : cube_spans)
        for (long j = c.j0; j <= c.j1; ++j) spans[std::size_t(fill_at[j]++)] = {c.s, c.e};
    }
  }
  struct Run { long j, s, e; signed char sg; };
  thread_local std::vector<Run> runs;
  thread_local std::vector<long> row_run;  // runs of row j: [row_run[j], row_run[j + 1])
  runs.clear();
  row_run.assign(nb + 1, 0);
  bool any_neg = false, any_pos = false;
  long j = 0;
  auto append = [&](long s0, long e0, bool in) {
    (in ? any_neg : any_pos) = true;
    if (long(runs.size()) > row_run[j] && runs.back().sg == static_cast<signed char>(in)) runs.back().e = e0;
    else runs.push_back({j, s0, e0, static_cast<signed char>(in)});
  };
  // Samples s0..e0 of row j, in inactive cubes only: their cube's corner sign.
  auto fill = [&](long s0, long e0) {
    if (s0 > e0) return;
    long c[3];
    cube_of(point(s0, j), c);
    append(s0, e0, grid.neg(c[0], c[1], c[2]));
  };
  // Samples s0..e0 of row j in one active cube (xs: sample s0): one run of
  // the enclosure's sign where the enclosure of f on their bounding box
  // excludes 0 (tried for 4 samples or more), else halved while 8 or more
  // (where S crosses near one end, the other half is often decided),
  // else f's sign at each.
  auto decide = [&](auto&& self, long s0, long e0, const Vec3& xs) -> void {
    if (e0 >= s0 + 3) {
      const Vec3 xe = point(e0, j);
      Vec3 blo, bhi;
      for (int k = 0; k < 3; ++k) {
        blo[k] = std::min(xs[k], xe[k]);
        bhi[k] = std::max(xs[k], xe[k]);
      }
      double flo, fhi;
      if (f.range(blo, bhi, flo, fhi)) {
        if (flo > 0 || fhi < 0) return append(s0, e0, fhi < 0);
        if (e0 >= s0 + 7) {
          const long mid = s0 + (e0 - s0) / 2;
          self(self, s0, mid, xs);
          return self(self, mid + 1, e0, point(mid + 1, j));
        }
      }
    }
    for (long k = s0; k <= e0; ++k) append(k, k, SurfaceSampler::inside(f.value(k == s0 ? xs : point(k, j))));
  };
  // Samples s0..e0 of row j, cube by cube. Reciprocals, not divisions: a
  // sample counted in the wrong cube at a face keeps its sign (see
  // cube_of), and one counted past the exit is caught below.
  const double inv_u[3] = {1 / u[0], 1 / u[1], 1 / u[2]}, inv_step = 1 / step;
  auto walk = [&](long s0, long e0) {
    for (long i = s0; i <= e0;) {
      const Vec3 x = point(i, j);
      long c[3];
      cube_of(x, c);
      long last = i;
      // The samples i..last of the row in this cube: they take one sign, the
      // corners' in an inactive cube (F1); in an active one, see decide.
      {
        // The row leaves the cube at a_exit; the samples before it are in it
        // (a cube is convex; the floor test settles rounding at its faces).
        double a_exit = INFINITY;
        const double b = b0 + j * step;
        for (int k = 0; k < 3; ++k) {
          if (u[k] > 1e-15) a_exit = std::min(a_exit, ((c[k] + 1) * grid.s[k] - m[k] - b * v[k]) * inv_u[k]);
          else if (u[k] < -1e-15) a_exit = std::min(a_exit, (c[k] * grid.s[k] - m[k] - b * v[k]) * inv_u[k]);
        }
        const double t = (a_exit - a0) * inv_step;
        if (!std::isfinite(t) || t >= 1e18) last = e0;
        else last = t <= -1e18 ? i : std::clamp(floor_long(t), i, e0);
        for (long c2[3]; last > i; --last) {
          cube_of(point(last, j), c2);
          if (c2[0] == c[0] && c2[1] == c[1] && c2[2] == c[2]) break;
        }
      }
      if (!grid.active(c[0], c[1], c[2])) append(i, last, grid.neg(c[0], c[1], c[2]));
      else decide(decide, i, last, x);
      i = last + 1;
    }
  };
  // The runs of every row: kSpans walks the spans, kFull every row, and
  // kCompare (the reference) gives each sample its sign by definition: its
  // cube's corner sign if inactive, else f's.
  auto build_runs = [&](FacetWalk mode) {
    runs.clear();
    any_neg = any_pos = false;
    for (j = 0; j < nb; ++j) {
      row_run[j] = long(runs.size());
      if (hi[j] < lo[j]) continue;
      if (mode == FacetWalk::kCompare) {
        for (long i = lo[j]; i <= hi[j]; ++i) {
          const Vec3 x = point(i, j);
          long c[3];
          cube_of(x, c);
          append(i, i, grid.active(c[0], c[1], c[2]) ? SurfaceSampler::inside(f.value(x)) : grid.neg(c[0], c[1], c[2]));
        }
        continue;
      }
      if (mode == FacetWalk::kFull) {
        walk(lo[j], hi[j]);
        continue;
      }
      long pos = lo[j];  // samples before pos are done
      for (long sp = row_span[j]; sp < row_span[j + 1];) {
        long s0 = std::max(spans[std::size_t(sp)].first, pos), e0 = spans[std::size_t(sp)].second;
        for (++sp; sp < row_span[j + 1] && spans[std::size_t(sp)].first <= e0 + 1; ++sp) e0 = std::max(e0, spans[std::size_t(sp)].second);
        e0 = std::min(e0, hi[j]);
        if (s0 > e0) continue;
        fill(pos, s0 - 1);
        walk(s0, e0);
        pos = e0 + 1;
      }
      fill(pos, hi[j]);
    }
    row_run[nb] = long(runs.size());
  };
  if (how == FacetWalk::kCompare) {
    // Both walks must give the reference's runs, sample for sample.
    build_runs(FacetWalk::kCompare);
    thread_local std::vector<Run> reference;
    reference.assign(runs.begin(), runs.end());
    const auto same = [](const Run& x, const Run& y) { return x.j == y.j && x.s == y.s && x.e == y.e && x.sg == y.sg; };
    for (FacetWalk mode : {FacetWalk::kFull, FacetWalk::kSpans}) {
      build_runs(mode);
      if (!std::equal(runs.begin(), runs.end(), reference.begin(), reference.end(), same))
        throw Error(std::string("FacetCycle: the ") + (mode == FacetWalk::kFull ? "full" : "span") +
                    " walk's runs differ from the samples' signs (edge " + std::to_string(p->info().id) + "-" +
                    std::to_string(q->info().id) + ")");
    }
  } else {
    build_runs(walk_all ? FacetWalk::kFull : FacetWalk::kSpans);
  }
  if (no_active && any_neg && any_pos)  // kCompare only: kSpans returned above
    throw Error("FacetCycle: samples of both signs though no block of the facet's rectangle, or no cube, is active (edge " +
                std::to_string(p->info().id) + "-" + std::to_string(q->info().id) + ")");
  if (!(any_neg && any_pos)) return kNone;
  // Sign regions (4-connected): runs of one sign overlapping in adjacent rows,
  // joined by union-find. A region touching h's border is open; one that
  // never does is enclosed by a cycle of S.
  thread_local std::vector<long> parent;
  thread_local std::vector<char> open;
  parent.resize(runs.size());
  open.assign(runs.size(), 0);
  for (std::size_t r = 0; r < runs.size(); ++r) parent[r] = long(r);
  auto find = [&](long r) {
    while (parent[std::size_t(r)] != r) r = parent[std::size_t(r)] = parent[std::size_t(parent[std::size_t(r)])];
    return r;
  };
  auto inside_row = [&](long j, long s0, long e0) { return j >= 0 && j < nb && lo[j] <= s0 && e0 <= hi[j]; };
  for (long j = 0; j < nb; ++j)
    for (long r = row_run[j]; r < row_run[j + 1]; ++r) {
      const Run& x = runs[std::size_t(r)];
      if (j + 1 >= nb) continue;
      for (long r2 = row_run[j + 1]; r2 < row_run[j + 2]; ++r2) {
        const Run& y = runs[std::size_t(r2)];
        if (y.e < x.s) continue;
        if (y.s > x.e) break;
        if (y.sg == x.sg) parent[std::size_t(find(r))] = find(r2);
      }
    }
  // A region is open where it reaches h's border itself: the sign at the
  // exact border point beyond a sample next to the border must be the
  // region's (else S passes in between and the region may be enclosed, as
  // when a thin feature's cross-section nearly fills a narrow facet).
  auto sign_at = [&](double a, double b) {
    const Vec3 x{m[0] + a * u[0] + b * v[0], m[1] + a * u[1] + b * v[1], m[2] + a * u[2] + b * v[2]};
    long c[3];
    cube_of(x, c);
    return grid.active(c[0], c[1], c[2]) ? SurfaceSampler::inside(f.value(x)) : grid.neg(c[0], c[1], c[2]);
  };
  auto column_end = [&](double a, int dir) {  // h's border above (dir 1) or below (-1) a
    double bmin = -INFINITY, bmax = INFINITY;
    for (const HP& h : hp) {
      const double r = h.C - h.A * a;
      if (h.B > 1e-15) bmax = std::min(bmax, r / h.B);
      else if (h.B < -1e-15) bmin = std::max(bmin, r / h.B);
    }
    return dir > 0 ? std::min(bmax, b1) : std::max(bmin, b0);
  };
  auto exits = [&](const Run& x) {
    const long j = x.j;
    const double b = b0 + j * step;
    const bool sg = x.sg;
    if (x.s == lo[j] && sign_at(alo_row[j], b) == sg) return true;
    if (x.e == hi[j] && sign_at(ahi_row[j], b) == sg) return true;
    for (int dir : {-1, 1}) {
      const long j2 = j + dir;
      if (inside_row(j2, x.s, x.e)) continue;
      for (long i = x.s; i <= x.e; ++i) {
        if (j2 >= 0 && j2 < nb && lo[j2] <= i && i <= hi[j2]) continue;  // that neighbour is in h
        const double a = a0 + i * step;
        if (sign_at(a, column_end(a, dir)) == sg) return true;
      }
    }
    return false;
  };
  for (std::size_t r = 0; r < runs.size(); ++r) {
    const long root = find(long(r));
    if (!open[std::size_t(root)] && exits(runs[r])) open[std::size_t(root)] = 1;
  }
  // Enclosed regions: the sample pairs (region, neighbour), farthest from p
  // first; along a row or an overlap of two rows the distance is convex, so
  // only the ends of runs and overlaps are candidates. Every point is in h:
  // a run at its row's end pairs with the exact border point (of the other
  // sign, or the region would be open).
  thread_local std::vector<std::pair<double, std::array<Vec3, 2>>> cands;
  cands.clear();
  auto add = [&](const Vec3& xa, const Vec3& xb) {
    const Vec3 mid{(xa[0] + xb[0]) / 2, (xa[1] + xb[1]) / 2, (xa[2] + xb[2]) / 2};
    cands.push_back({-dist2(mid, pp), {xa, xb}});
  };
  auto candidate = [&](long i, long j, long i2, long j2) { add(point(i, j), point(i2, j2)); };
  auto border_point = [&](double a, long j) {
    const double b = b0 + j * step;
    return Vec3{m[0] + a * u[0] + b * v[0], m[1] + a * u[1] + b * v[1], m[2] + a * u[2] + b * v[2]};
  };
  for (long j = 0; j < nb; ++j)
    for (long r = row_run[j]; r < row_run[j + 1]; ++r) {
      if (open[std::size_t(find(r))]) continue;
      const Run& x = runs[std::size_t(r)];
      if (x.s > lo[j]) candidate(x.s, j, x.s - 1, j);
      else add(point(x.s, j), border_point(alo_row[j], j));
      if (x.e < hi[j]) candidate(x.e, j, x.e + 1, j);
      else add(point(x.e, j), border_point(ahi_row[j], j));
      for (long j2 : {j - 1, j + 1})
        for (long r2 = row_run[j2]; r2 < row_run[j2 + 1]; ++r2) {
          const Run& y = runs[std::size_t(r2)];
          if (y.e < x.s) continue;
          if (y.s > x.e) break;
          if (y.sg == x.sg) continue;
          const long s0 = std::max(x.s, y.s), e0 = std::min(x.e, y.e);
          candidate(s0, j, s0, j2);
          candidate(e0, j, e0, j2);
        }
    }
  // The farthest pair that brackets a root of f (signs are f's own, or F1's
  // corner sign, which f has in an inactive cube; the check makes sure).
  std::sort(cands.begin(), cands.end(), [](const auto& x, const auto& y) { return x.first < y.first; });
  for (const auto& c : cands) {
    if (f.bisect(c.second[0], c.second[1], f.value(c.second[0]), out)) return FacetAnswer::kCycle;
  }
  return kNone;
}

Candidates facet_cycle_points(const Tr& tr, const SurfaceSampler& f, const std::vector<Vh>& vertices, const IdSet& changed,
                              std::uint32_t& stamp, int threads, long long& checks, std::vector<int>& skipped,
                              FacetWalk how, std::size_t chunk) {
  // The edges with a new end (a vertex of `changed`), each once, in the
  // order of their ids (lo, hi): every lower end's edges to higher ids, by
  // id. The lower ends are the new vertices and their older neighbours of
  // smaller id. The edges are checked a chunk at a time (of at least
  // `chunk` edges, a lower end's edges in one chunk), not gathered first:
  // the first pass takes every edge, and its list was the run's peak
  // (brain label 4: 6 MB of edges beside the triangulation).
  std::vector<Ch> cells;
  // take(b, c) for each finite neighbour b of a, once, with a cell c at ab.
  auto neighbours = [&](Vh a, auto&& take) {
    ++stamp;
    cells.clear();
    tr.incident_cells(a, std::back_inserter(cells));
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
    for (int ia : changed.ids) {
      const Vh a = vertices[std::size_t(ia)];
      if (a == Vh()) continue;  // deleted
      low(ia);
      neighbours(a, [&](Vh b, Ch) {
        if (b->info().id < ia && !changed.has(b->info().id)) low(b->info().id);
      });
    }
  }
  std::sort(lows.begin(), lows.end());
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
  std::vector<std::pair<std::size_t, Vec3>> all;
  Candidates pts;
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
      CentreMemo memo;  // of the cells around edges[k].lo
      for (long k = a; k < b; ++k) {
        if (k == a || edges[std::size_t(k)].lo != edges[std::size_t(k - 1)].lo) memo.kept.clear();
        Vec3 x;
        const FacetAnswer answer = facet_cycle(tr, f, edge(edges[std::size_t(k)]), x, how, &memo);
        found[std::size_t(k)] = std::uint8_t(answer);
        if (answer == FacetAnswer::kCycle) cycles[t].emplace_back(std::size_t(k), x);
      }
    });
    for (std::size_t k = 0; k < edges.size(); ++k)
      if (found[k] == std::uint8_t(FacetAnswer::kSkipped)) skipped.push_back(edges[k].lo);
    all.clear();
    for (const auto& c : cycles) all.insert(all.end(), c.begin(), c.end());
    std::sort(all.begin(), all.end(), [](const auto& x, const auto& y) { return x.first < y.first; });
    for (const auto& [k, x] : all) pts.emplace_back(x, dist2(x, vec(vertices[std::size_t(edges[k].lo)]->point())));
  }
  return pts;
}

} // namespace imgmesh::surface_detail
