// FacetCycle's raster (8.2): h's samples on Pi at delta/4, row by row, as
// runs of one sign. facet_cycle.cpp has the driver and the stages after.
#include "surface/facet_cycle_raster.hpp"

#include <algorithm>
#include <cmath>

namespace imgmesh::surface_detail {

// h's edge dual to facet pqw: |x-p|^2 <= |x-w|^2  <=>  2 x.d <= |w|^2 - |p|^2.
void FacetRaster::add_neighbour(const Vec3& pw) {
  const Vec3 d = sub(pw, pp);
  const double C = dot(pw, pw) - dot(pp, pp) - 2 * dot(m, d);
  s.hp.push_back({2 * dot(u, d), 2 * dot(v, d), C});
}

bool FacetRaster::extent(bool bounded, double va0, double va1, double vb0, double vb1) {
  for (int i = 0; i < 3; ++i) {  // 0 <= m_i + a u_i + b v_i <= hi_i
    s.hp.push_back({u[i], v[i], grid.hi[i] - m[i]});
    s.hp.push_back({-u[i], -v[i], m[i]});
  }
  // The box's corners projected (h lies in the box).
  double ba0 = INFINITY, ba1 = -INFINITY, bb0 = INFINITY, bb1 = -INFINITY;
  for (int k = 0; k < 8; ++k) {
    const Vec3 c{(k & 1) ? grid.hi[0] : 0, (k & 2) ? grid.hi[1] : 0, (k & 4) ? grid.hi[2] : 0};
    const double a = dot(sub(c, m), u), b = dot(sub(c, m), v);
    ba0 = std::min(ba0, a); ba1 = std::max(ba1, a); bb0 = std::min(bb0, b); bb1 = std::max(bb1, b);
  }
  this->bounded = bounded;
  if (!bounded) { va0 = ba0; va1 = ba1; vb0 = bb0; vb1 = bb1; }
  a0 = std::max(va0, ba0); a1 = std::min(va1, ba1); b0 = std::max(vb0, bb0); b1 = std::min(vb1, bb1);
  if (!(a0 < a1 && b0 < b1)) return false;
  step = grid.delta / 4;
  nb = long(std::ceil((b1 - b0) / step)) + 1;
  b_last = b0 + double(nb - 1) * step;
  // Rounding of the samples' coordinates: far below this.
  eps = 1e-9 * (grid.hi[0] + grid.hi[1] + grid.hi[2] + std::abs(a0) + std::abs(a1) + std::abs(b0) + std::abs(b_last));
  for (int k = 0; k < 3; ++k) inv_s[k] = 1 / grid.s[k];
  inv_step = 1 / step;
  return true;
}

// No active cube in any block (CubeGrid::kBlock^3 cubes) that the samples'
// rectangle [a0, a1] x [b0, b_last] on Pi meets: every sample lies in an
// inactive cube, and h (convex) passes from cube to cube through shared
// corners, so every sample takes one sign (F1): no cycle. Only where h has
// too few samples to be skipped (kSkipped), so that the answer is kNone
// either way; kCompare checks it at the end.
bool FacetRaster::no_active_block() const {
  if (!((std::floor((a1 - a0) / step) + 1) * double(nb) <= 64000000)) return false;
  long k0[3], k1[3];
  for (int k = 0; k < 3; ++k) {
    double xlo = INFINITY, xhi = -INFINITY;
    for (double a : {a0, a1})
      for (double b : {b0, b_last}) {
        const double x = m[k] + a * u[k] + b * v[k];
        xlo = std::min(xlo, x), xhi = std::max(xhi, x);
      }
    k0[k] = std::clamp(floor_long((xlo - eps) / grid.s[k]), 0L, grid.n[k] - 2) / CubeGrid::kBlock;
    k1[k] = std::clamp(floor_long((xhi + eps) / grid.s[k]), 0L, grid.n[k] - 2) / CubeGrid::kBlock;
  }
  long b0[3], b1[3];  // blocks beyond the box of samples given are inactive
  grid.sampled_cubes(b0, b1);
  for (int k = 0; k < 3; ++k) {
    k0[k] = std::max(k0[k], b0[k] / CubeGrid::kBlock);
    k1[k] = std::min(k1[k], b1[k] / CubeGrid::kBlock);
  }
  for (long z = k0[2]; z <= k1[2]; ++z)
    for (long y = k0[1]; y <= k1[1]; ++y)
      for (long x = k0[0]; x <= k1[0]; ++x)
        if (grid.block(x, y, z)) return false;
  return true;
}

// A box half-plane that holds with room to spare at the rows' rectangle
// [a0, a1] x [b0, b_last] (it is linear: at its corners) changes no row's
// bounds, which start at a0 and a1: skipped unless `all` (most facets lie
// well inside the box, and the box was half of the half-planes).
bool FacetRaster::loose(const FacetHalfPlane& h) const {
  const double a = h.A > 1e-15 ? a1 : h.A < -1e-15 ? a0 : 0;
  for (double b : {b0, b_last})
    if (!(h.C - h.B * b - h.A * a > 1e-9 * (std::abs(h.C) + std::abs(h.B * b) + std::abs(h.A * a)) + 1e-12 * grid.delta))
      return false;
  return true;
}

// Rows: the a-interval where every half-plane holds. The half-planes by the
// sign of A, sorted once (not tested per row): each row's bounds are the
// same min and max, in the same order.
void FacetRaster::rows(bool all) {
  s.lo.assign(nb, 0);
  s.hi.assign(nb, -1);
  s.alo_row.assign(nb, 0);
  s.ahi_row.assign(nb, 0);
  rows_used = 0;
  s.hp_hi.clear();
  s.hp_lo.clear();
  s.hp_flat.clear();
  const std::size_t box_from = s.hp.size() - 6;  // the box's six, last
  for (std::size_t k = 0; k < s.hp.size(); ++k) {
    const FacetHalfPlane& h = s.hp[k];
    if (k >= box_from && !all && loose(h)) continue;
    (h.A > 1e-15 ? s.hp_hi : h.A < -1e-15 ? s.hp_lo : s.hp_flat).push_back(h);
  }
  long j0 = 0, j1 = nb - 1;
  if (!all && !bounded) row_range(j0, j1);
  for (long j = j0; j <= j1; ++j) {
    const double b = b0 + j * step;
    bool empty = false;
    for (const FacetHalfPlane& h : s.hp_flat) empty = empty || h.C - h.B * b < 0;
    if (empty) continue;
    double alo = a0, ahi = a1;
    for (const FacetHalfPlane& h : s.hp_hi) ahi = std::min(ahi, (h.C - h.B * b) / h.A);
    for (const FacetHalfPlane& h : s.hp_lo) alo = std::max(alo, (h.C - h.B * b) / h.A);
    if (!(alo <= ahi)) continue;
    s.alo_row[j] = alo;
    s.ahi_row[j] = ahi;
    s.lo[j] = ceil_long((alo - a0) / step);
    s.hi[j] = floor_long((ahi - a0) / step);
    if (s.hi[j] >= s.lo[j]) ++rows_used;
  }
}

// An unbounded h's extent is the box's, mostly rows that miss h (the
// bunny's: 97% of them): only the rows j0..j1 near h, from the polygon of
// the half-planes each pushed out by a step (it holds every point within a
// step of h, and its rounding is far below that), clipped from the
// rectangle; find_rows(true) checks that the others are empty.
void FacetRaster::row_range(long& j0, long& j1) const {
  std::vector<std::array<double, 2>>& poly = s.poly;
  std::vector<std::array<double, 2>>& next = s.poly_next;
  poly = {{a0 - step, b0 - step}, {a1 + step, b0 - step}, {a1 + step, b_last + step}, {a0 - step, b_last + step}};
  for (const auto* hs : {&s.hp_hi, &s.hp_lo, &s.hp_flat})
    for (const FacetHalfPlane& h : *hs) {
      const double C = h.C + step * std::hypot(h.A, h.B);
      next.clear();
      for (std::size_t i = 0; i < poly.size(); ++i) {
        const auto& x = poly[i];
        const auto& y = poly[(i + 1) % poly.size()];
        const double dx = h.A * x[0] + h.B * x[1] - C, dy = h.A * y[0] + h.B * y[1] - C;
        if (dx <= 0) next.push_back(x);
        if ((dx < 0 && dy > 0) || (dx > 0 && dy < 0)) {
          const double t = dx / (dx - dy);
          next.push_back({x[0] + t * (y[0] - x[0]), x[1] + t * (y[1] - x[1])});
        }
      }
      std::swap(poly, next);
    }
  if (poly.empty()) {  // h is empty
    j1 = j0 - 1;
    return;
  }
  double lo = INFINITY, hi = -INFINITY;
  for (const auto& x : poly) lo = std::min(lo, x[1]), hi = std::max(hi, x[1]);
  j0 = std::max(j0, floor_long((lo - b0) / step) - 1);
  j1 = std::min(j1, ceil_long((hi - b0) / step) + 1);
}

bool FacetRaster::find_rows(bool compare) {
  if (!compare) {
    rows(false);
    return true;
  }
  // The rows with every half-plane: the skipped ones must change nothing.
  rows(true);
  const std::vector<long> lo_all = s.lo, hi_all = s.hi;
  const std::vector<double> alo_all = s.alo_row, ahi_all = s.ahi_row;
  rows(false);
  return s.lo == lo_all && s.hi == hi_all && s.alo_row == alo_all && s.ahi_row == ahi_all;
}

long FacetRaster::sample_count() const {
  long total = 0;
  for (long j = 0; j < nb; ++j) total += std::max(0L, s.hi[j] - s.lo[j] + 1);
  return total;
}

// Only the samples near active cubes need a walk through the cubes: the
// others lie in inactive cubes, and consecutive samples (delta/4 apart) in
// cubes that share a corner, so a stretch of them takes one sign (F1): one
// run. The stretches to walk, per row: each active cube among the samples'
// cubes that Pi meets spans the rows and the samples between its corners'
// extremes along v and u, one sample wider on each side, so that a
// stretch begins and ends in inactive cubes.
void FacetRaster::find_spans(FacetWalk how) {
  s.cube_spans.clear();
  s.spans.clear();
  s.row_span.assign(nb + 1, 0);
  walk_all = true;
  if (how == FacetWalk::kFull) return;
  Vec3 xlo{INFINITY, INFINITY, INFINITY}, xhi{-INFINITY, -INFINITY, -INFINITY};
  double cost = 0;  // the walk's cube steps, about
  for (long j = 0; j < nb; ++j) {
    if (s.hi[j] < s.lo[j]) continue;
    for (const Vec3& x : {point(s.lo[j], j), point(s.hi[j], j)})  // every sample's coordinates lie between these
      for (int k = 0; k < 3; ++k) xlo[k] = std::min(xlo[k], x[k]), xhi[k] = std::max(xhi[k], x[k]);
    cost += double(s.hi[j] - s.lo[j]) / 16 + 1;
  }
  // Only cubes that meet the box of samples given can be active (a crop in
  // its scan: the facets of a small surface span the scan's box).
  long c0[3], c1[3], b0[3], b1[3];
  cube_of(xlo, c0);
  cube_of(xhi, c1);
  grid.sampled_cubes(b0, b1);
  double lines = 1;
  for (int k = 0; k < 3; ++k) {
    c0[k] = std::max(c0[k], b0[k]);
    c1[k] = std::min(c1[k], b1[k]);
    if (k > 0) lines *= double(std::max(0L, c1[k] - c0[k] + 1));
  }
  // collect_cube_spans pays by the box's lines along x (each holds ~3 cubes
  // near Pi, read a word at a time), not by its cubes: a box of many lines
  // against few samples is cheaper walked row by row.
  if (!(lines < 16 * cost || how == FacetWalk::kCompare)) return;
  walk_all = false;
  collect_cube_spans(c0, c1);
  // No active cube that Pi meets among the samples' cubes: every sample
  // lies in an inactive cube, and h (convex) passes from cube to cube
  // through shared corners, so all take one sign (F1): no cycle.
  no_active = no_active || s.cube_spans.empty();
  if (no_active && how == FacetWalk::kSpans) return;  // the driver answers kNone
  deal_spans();
}

// Only the cubes of each line along x that come within the test's reach
// of Pi (twice eps from it, and a cube more on each side) are tested: in a
// facet's box most cubes lie far from its plane. Cube (x, y, z)'s corners
// have signed distances x s_0 n_0 + e(y, z) + an offset in [off_lo, off_hi].
void FacetRaster::collect_cube_spans(const long c0[3], const long c1[3]) {
  const double sn[3] = {grid.s[0] * n[0], grid.s[1] * n[1], grid.s[2] * n[2]};
  const double off_lo = std::min(0.0, sn[0]) + std::min(0.0, sn[1]) + std::min(0.0, sn[2]);
  const double off_hi = std::max(0.0, sn[0]) + std::max(0.0, sn[1]) + std::max(0.0, sn[2]);
  // The lines' x ranges need not round as the test does: a cube of slack.
  const bool slanted = std::abs(sn[0]) > 1e-9 * grid.delta;
  const double inv_sn0 = slanted ? 1 / sn[0] : 0;
  for (long z = c0[2]; z <= c1[2]; ++z) {
    const double ez = -m[0] * n[0] + (double(z) * grid.s[2] - m[2]) * n[2];
    for (long y = c0[1]; y <= c1[1]; ++y) {
      const double e = ez + (double(y) * grid.s[1] - m[1]) * n[1];
      const double lo_d = -2 * eps - off_hi - e, hi_d = 2 * eps - off_lo - e;  // lo_d <= x sn_0 <= hi_d
      long x0 = c0[0], x1 = c1[0];
      if (slanted) {
        double t0 = lo_d * inv_sn0, t1 = hi_d * inv_sn0;
        if (t0 > t1) std::swap(t0, t1);
        x0 = std::max(x0, long(std::max(t0, double(x0 - 1))) - 1);
        x1 = std::min(x1, long(std::min(t1, double(x1 + 1))) + 1);
      } else if (lo_d > 0 || hi_d < 0) {
        continue;
      }
      const double cy[2] = {double(y) * grid.s[1] - m[1], double(y + 1) * grid.s[1] - m[1]};
      const double cz[2] = {double(z) * grid.s[2] - m[2], double(z + 1) * grid.s[2] - m[2]};
      grid.for_active_on_line(x0, x1, y, z, [&](long x) {
        // The 8 corners' extremes along n, u and v (relative to m): a dot
        // product rounds monotonically in each term, so per axis the end
        // that makes its term least (most) gives the least (most) of the
        // corners' dot products, bit for bit, from 2 of them, not 8.
        const double cx[2] = {double(x) * grid.s[0] - m[0], double(x + 1) * grid.s[0] - m[0]};
        const auto extremes = [&](const Vec3& w, double& lo, double& hi) {
          lo = cx[w[0] < 0] * w[0] + cy[w[1] < 0] * w[1] + cz[w[2] < 0] * w[2];
          hi = cx[w[0] >= 0] * w[0] + cy[w[1] >= 0] * w[1] + cz[w[2] >= 0] * w[2];
        };
        double dlo, dhi, alo, ahi, blo, bhi;
        extremes(n, dlo, dhi);
        if (dlo > eps || dhi < -eps) return;  // Pi misses the cube
        extremes(u, alo, ahi);
        extremes(v, blo, bhi);
        const long j0 = std::max(0L, floor_long((blo - eps - b0) / step) - 1);
        const long j1 = std::min(nb - 1, ceil_long((bhi + eps - b0) / step) + 1);
        const long s0 = floor_long((alo - eps - a0) / step) - 1, e0 = ceil_long((ahi + eps - a0) / step) + 1;
        if (j0 <= j1) s.cube_spans.push_back({j0, j1, s0, e0});
      });
    }
  }
}

// Per row (row_span[j] .. row_span[j + 1]) the (s, e) of the cubes over it,
// by s: the cubes sorted by s once and dealt to their rows (a sort of every
// row's spans by (row, s) cost 2% of the run).
void FacetRaster::deal_spans() {
  std::sort(s.cube_spans.begin(), s.cube_spans.end(), [](const FacetCubeSpan& x, const FacetCubeSpan& y) { return x.s < y.s; });
  for (const FacetCubeSpan& c : s.cube_spans)
    for (long j = c.j0; j <= c.j1; ++j) ++s.row_span[j + 1];
  for (long j = 0; j < nb; ++j) s.row_span[j + 1] += s.row_span[j];
  s.spans.resize(std::size_t(s.row_span[nb]));
  s.fill_at.assign(s.row_span.begin(), s.row_span.end() - 1);
  for (const FacetCubeSpan& c : s.cube_spans)
    for (long j = c.j0; j <= c.j1; ++j) s.spans[std::size_t(s.fill_at[j]++)] = {c.s, c.e};
}

void FacetRaster::append(long j, long s0, long e0, bool in) {
  (in ? any_neg : any_pos) = true;
  if (long(s.runs.size()) > s.row_run[j] && s.runs.back().sg == static_cast<signed char>(in)) s.runs.back().e = e0;
  else s.runs.push_back({j, s0, e0, static_cast<signed char>(in)});
}

// Samples s0..e0 of row j, in inactive cubes only: their cube's corner sign.
void FacetRaster::fill(long j, long s0, long e0) {
  if (s0 > e0) return;
  long c[3];
  cube_of(point(s0, j), c);
  append(j, s0, e0, grid.neg(c[0], c[1], c[2]));
}

// Samples s0..e0 of row j in one active cube (xs: sample s0): one run of
// the enclosure's sign where the enclosure of f on their bounding box
// excludes 0 (tried for 2 samples or more: it costs about 2/5 of a value
// of f; from 4, the bunny's FacetCycle took 3% more instructions), else
// halved while 8 or more (where S crosses near one end, the other half is
// often decided), else f's sign at each.
void FacetRaster::decide(long j, long s0, long e0, const Vec3& xs) {
  if (e0 >= s0 + 1) {
    const Vec3 xe = point(e0, j);
    Vec3 blo, bhi;
    for (int k = 0; k < 3; ++k) {
      blo[k] = std::min(xs[k], xe[k]);
      bhi[k] = std::max(xs[k], xe[k]);
    }
    double flo, fhi;
    if (f.range(blo, bhi, flo, fhi)) {
      if (flo > 0 || fhi < 0) return append(j, s0, e0, fhi < 0);
      if (e0 >= s0 + 7) {
        const long mid = s0 + (e0 - s0) / 2;
        decide(j, s0, mid, xs);
        return decide(j, mid + 1, e0, point(mid + 1, j));
      }
    }
  }
  for (long k = s0; k <= e0; ++k) append(j, k, k, SurfaceSampler::inside(f.value(k == s0 ? xs : point(k, j))));
}

// Samples s0..e0 of row j, cube by cube. Reciprocals, not divisions: a
// sample counted in the wrong cube at a face keeps its sign (see cube_of),
// and one counted past the exit is caught below.
void FacetRaster::walk(long j, long s0, long e0) {
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
    if (!grid.active(c[0], c[1], c[2])) append(j, i, last, grid.neg(c[0], c[1], c[2]));
    else decide(j, i, last, x);
    i = last + 1;
  }
}

// The runs of every row: kSpans walks the spans, kFull every row, and
// kCompare (the reference) gives each sample its sign by definition: its
// cube's corner sign if inactive, else f's.
void FacetRaster::build_runs(FacetWalk mode) {
  s.runs.clear();
  any_neg = any_pos = false;
  const std::vector<long>& lo = s.lo;
  const std::vector<long>& hi = s.hi;
  for (long j = 0; j < nb; ++j) {
    s.row_run[j] = long(s.runs.size());
    if (hi[j] < lo[j]) continue;
    if (mode == FacetWalk::kCompare) {
      for (long i = lo[j]; i <= hi[j]; ++i) {
        const Vec3 x = point(i, j);
        long c[3];
        cube_of(x, c);
        append(j, i, i, grid.active(c[0], c[1], c[2]) ? SurfaceSampler::inside(f.value(x)) : grid.neg(c[0], c[1], c[2]));
      }
      continue;
    }
    if (mode == FacetWalk::kFull) {
      walk(j, lo[j], hi[j]);
      continue;
    }
    long pos = lo[j];  // samples before pos are done
    for (long sp = s.row_span[j]; sp < s.row_span[j + 1];) {
      long s0 = std::max(s.spans[std::size_t(sp)].first, pos), e0 = s.spans[std::size_t(sp)].second;
      for (++sp; sp < s.row_span[j + 1] && s.spans[std::size_t(sp)].first <= e0 + 1; ++sp)
        e0 = std::max(e0, s.spans[std::size_t(sp)].second);
      e0 = std::min(e0, hi[j]);
      if (s0 > e0) continue;
      fill(j, pos, s0 - 1);
      walk(j, s0, e0);
      pos = e0 + 1;
    }
    fill(j, pos, hi[j]);
  }
  s.row_run[nb] = long(s.runs.size());
}

const char* FacetRaster::sign_runs(FacetWalk how) {
  s.runs.clear();
  s.row_run.assign(nb + 1, 0);
  any_neg = any_pos = false;
  if (how != FacetWalk::kCompare) {
    build_runs(walk_all ? FacetWalk::kFull : FacetWalk::kSpans);
    return nullptr;
  }
  // Both walks must give the reference's runs, sample for sample.
  build_runs(FacetWalk::kCompare);
  s.reference.assign(s.runs.begin(), s.runs.end());
  const auto same = [](const FacetRun& x, const FacetRun& y) { return x.j == y.j && x.s == y.s && x.e == y.e && x.sg == y.sg; };
  for (FacetWalk mode : {FacetWalk::kFull, FacetWalk::kSpans}) {
    build_runs(mode);
    if (!std::equal(s.runs.begin(), s.runs.end(), s.reference.begin(), s.reference.end(), same))
      return mode == FacetWalk::kFull ? "full" : "span";
  }
  return nullptr;
}

} // namespace imgmesh::surface_detail
