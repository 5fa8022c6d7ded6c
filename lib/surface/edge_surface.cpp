// EdgeSurface (8.2) and VorEdge's Voronoi edges: where the Voronoi edge dual to
// a Delaunay facet meets S, found on the cube grid.
#include "surface/edge_surface.hpp"

#include <algorithm>
#include <cmath>

namespace imgmesh::surface_detail {

// EdgeSurface (8.2): clip the Voronoi edge to the box of voxel centres, walk
// the cubes it crosses, look for roots only in active cubes (F1), and find the
// first and the last crossing. Where the surface gives enclosures (the
// partition of unity does), each piece of the edge in an active cube is
// decided by them, halving it up to kSplits times: where the enclosure of f
// excludes 0 the piece certainly holds no root; where the enclosure of f's
// derivative along the edge excludes 0, f is monotone there and the piece
// holds exactly one root if its ends differ in sign, none otherwise. Only
// the pieces left undecided are sampled at delta/8 (with the dip search);
// two roots closer than that there are missed (see the man page).
EdgeCrossing edge_surface(const SurfaceSampler& f, const Vec3& a, const Vec3& b, const Vec3& site) {
  const CubeGrid& grid = f.grid();
  EdgeCrossing out;
  const Vec3 d = sub(b, a);
  double t0 = 0, t1 = 1;
  for (int i = 0; i < 3; ++i) {
    if (d[i] == 0) {
      if (a[i] < 0 || a[i] > grid.hi[i]) return out;
      continue;
    }
    double ta = (0 - a[i]) / d[i], tb = (grid.hi[i] - a[i]) / d[i];
    if (ta > tb) std::swap(ta, tb);
    t0 = std::max(t0, ta);
    t1 = std::min(t1, tb);
  }
  if (!(t0 < t1)) return out;
  auto at = [&](double t) -> Vec3 {
    if (t == 0) return a;  // Voronoi vertices bit-exact: consistent signs (8.4(1))
    if (t == 1) return b;
    return {a[0] + t * d[0], a[1] + t * d[1], a[2] + t * d[2]};
  };
  // Pieces of [t0, t1] inside active cubes, in order: where the segment
  // crosses planes spaced `step` (Amanatides-Woo's events), first at the
  // block level, then cube by cube inside active blocks.
  auto breakpoints = [&](double ta, double tb, const double step[3], std::vector<double>& ts) {
    ts.assign({ta, tb});
    for (int i = 0; i < 3; ++i) {
      if (d[i] == 0) continue;
      const double lo = std::min(a[i] + ta * d[i], a[i] + tb * d[i]);
      const double hi = std::max(a[i] + ta * d[i], a[i] + tb * d[i]);
      for (long k = ceil_long(lo / step[i]); k <= floor_long(hi / step[i]); ++k) {
        const double t = (double(k) * step[i] - a[i]) / d[i];
        if (t > ta && t < tb) ts.push_back(t);
      }
    }
    std::sort(ts.begin(), ts.end());
  };
  // Scratch reused across calls (no allocation per facet).
  thread_local std::vector<double> tblock, tcube;
  struct Piece { double ta, tb; bool monotone; };
  thread_local std::vector<Piece> pieces;
  pieces.clear();
  const double len = norm(d);
  const Vec3 dir{d[0] / len, d[1] / len, d[2] / len};
  // The piece [ta, tb] of an active cube by the enclosures (halved up to
  // kSplits times); what they leave undecided joins the pieces to sample.
  constexpr int kSplits = 2;
  auto decide = [&](auto&& self, double ta, double tb, int depth) -> void {
    const Vec3 xa = at(ta), xb = at(tb);
    Vec3 lo, hi;
    for (int i = 0; i < 3; ++i) {
      lo[i] = std::min(xa[i], xb[i]);
      hi[i] = std::max(xa[i], xb[i]);
    }
    double flo, fhi;
    if (!f.range(lo, hi, flo, fhi)) flo = -1, fhi = 1;  // no enclosures: sample
    else if (flo > 0 || fhi < 0) return;                  // no root
    else if (f.slope_range(lo, hi, dir, flo, fhi) && (flo > 0 || fhi < 0)) {
      pieces.push_back({ta, tb, true});  // monotone: one root or none
      return;
    } else if (depth < kSplits) {
      const double tm = (ta + tb) / 2;
      self(self, ta, tm, depth + 1);
      self(self, tm, tb, depth + 1);
      return;
    }
    if (!pieces.empty() && !pieces.back().monotone && pieces.back().tb == ta) pieces.back().tb = tb;  // merge runs
    else pieces.push_back({ta, tb, false});
  };
  const double bstep[3] = {grid.s[0] * CubeGrid::kBlock, grid.s[1] * CubeGrid::kBlock, grid.s[2] * CubeGrid::kBlock};
  breakpoints(t0, t1, bstep, tblock);
  for (std::size_t kb = 0; kb + 1 < tblock.size(); ++kb) {
    if (!(tblock[kb + 1] > tblock[kb])) continue;
    const Vec3 mb = at((tblock[kb] + tblock[kb + 1]) / 2);
    long cb[3];
    for (int i = 0; i < 3; ++i) cb[i] = std::clamp(floor_long(mb[i] / bstep[i]), 0L, grid.nb[i] - 1);
    if (!grid.block(cb[0], cb[1], cb[2])) continue;
    breakpoints(tblock[kb], tblock[kb + 1], grid.s, tcube);
    for (std::size_t k = 0; k + 1 < tcube.size(); ++k) {
      const double ta = tcube[k], tb = tcube[k + 1];
      if (!(tb > ta)) continue;
      const Vec3 m = at((ta + tb) / 2);
      long c[3];
      for (int i = 0; i < 3; ++i) c[i] = std::clamp(floor_long(m[i] / grid.s[i]), 0L, grid.n[i] - 2);
      if (!grid.active(c[0], c[1], c[2])) continue;
      decide(decide, ta, tb, 0);
    }
  }
  if (pieces.empty()) return out;
  const double step = grid.delta / 8;
  // All sign changes of one piece, as sample pairs.
  // Near-tangential crossings (8.4(2)): where |f| has a local minimum between
  // three samples of one sign that may dip through zero, search the minimum
  // (golden section). A sign change there gives two crossings; a minimum at
  // |f| ~ 0 is a tangency, reported as a double root at that point (VorEdge
  // inserts it, Lemma 8.4.1).
  auto dip = [&](double ta, double tb, bool in, std::vector<std::pair<double, double>>& ch, std::vector<double>& fv) {
    const double g = 0.6180339887498949;
    const double s = in ? -1 : 1;  // minimise s * f
    double a = ta, b = tb, c = b - g * (b - a), d = a + g * (b - a);
    double fc = f.value(at(c)), fd = f.value(at(d));
    for (int it = 0; it < 40; ++it) {
      for (double tt : {c, d}) {
        const double ft = tt == c ? fc : fd;
        if (SurfaceSampler::inside(ft) != in) {  // crossed: two sign changes around tt
          ch.emplace_back(ta, tt);
          fv.push_back(f.value(at(ta)));
          ch.emplace_back(tt, tb);
          fv.push_back(ft);
          return;
        }
      }
      if ((b - a) * len < 1e-9 * grid.delta) break;
      if (s * fc < s * fd) {
        b = d; d = c; fd = fc; c = b - g * (b - a); fc = f.value(at(c));
      } else {
        a = c; c = d; fc = fd; d = a + g * (b - a); fd = f.value(at(d));
      }
    }
    const double tm = s * fc < s * fd ? c : d, fm = std::min(std::abs(fc), std::abs(fd));
    if (fm < 1e-9 * grid.delta) {  // tangency: a double root
      ch.emplace_back(tm, tm);
      fv.push_back(fm);
      ch.emplace_back(tm, tm);
      fv.push_back(fm);
    }
  };
  // All sign changes of one piece, as sample pairs, in order.
  auto changes = [&](const Piece& p, std::vector<std::pair<double, double>>& ch, std::vector<double>& fv) {
    if (p.monotone) {
      const double fa = f.value(at(p.ta));
      if (SurfaceSampler::inside(fa) != SurfaceSampler::inside(f.value(at(p.tb)))) {
        ch.emplace_back(p.ta, p.tb);
        fv.push_back(fa);
      }
      return;
    }
    const int m = std::max(2, int(std::ceil((p.tb - p.ta) * len / step)));
    double tq = p.ta, fq = 0;  // the sample before the previous one
    double tp = p.ta, fp = f.value(at(tp));
    for (int k = 1; k <= m; ++k) {
      const double t = k == m ? p.tb : p.ta + (p.tb - p.ta) * k / m;
      const double fc = f.value(at(t));
      if (SurfaceSampler::inside(fc) != SurfaceSampler::inside(fp)) {
        ch.emplace_back(tp, t);
        fv.push_back(fp);
      } else if (k >= 2 && SurfaceSampler::inside(fq) == SurfaceSampler::inside(fp) && std::abs(fp) < std::abs(fq) && std::abs(fp) < std::abs(fc) &&
                 std::abs(fp) < std::abs(fq - fp) + std::abs(fc - fp)) {
        dip(tq, t, SurfaceSampler::inside(fp), ch, fv);
      }
      tq = tp;
      fq = fp;
      tp = t;
      fp = fc;
    }
  };
  // Forward to the first piece with a root, backward to the last one.
  std::size_t first = pieces.size();
  thread_local std::vector<std::pair<double, double>> ch_first, ch_last;
  thread_local std::vector<double> fv_first, fv_last;
  ch_first.clear(); ch_last.clear(); fv_first.clear(); fv_last.clear();
  for (std::size_t k = 0; k < pieces.size(); ++k) {
    changes(pieces[k], ch_first, fv_first);
    if (!ch_first.empty()) { first = k; break; }
  }
  if (first == pieces.size()) return out;
  for (std::size_t k = pieces.size() - 1; k > first; --k) {
    changes(pieces[k], ch_last, fv_last);
    if (!ch_last.empty()) break;
  }
  // The root of a sign change (a tangency's double root is its point). The
  // pairs come from f's own values, so they bracket; bisect checks it.
  auto root = [&](const std::pair<double, double>& c, double fa, Vec3& x) {
    if (c.first == c.second) {
      x = at(c.first);
      return true;
    }
    return f.bisect(at(c.first), at(c.second), fa, x);
  };
  Vec3 x0, x1;
  if (!root(ch_first.front(), fv_first.front(), x0)) return out;
  out.count = 1;
  out.x = x0;
  if (!ch_last.empty()) {
    if (root(ch_last.back(), fv_last.back(), x1)) out.count = 2;
  } else if (ch_first.size() > 1) {
    if (root(ch_first.back(), fv_first.back(), x1)) out.count = 2;
  }
  // x_t: the crossing farthest from the facet's vertices (7.6: largest ball).
  if (out.count == 2 && dist2(x1, site) > dist2(x0, site)) out.x = x1;
  return out;
}

void CellCentres::assign(const Tr& tr, const std::vector<Ch>& cells) {
  std::size_t size = 16;
  while (size < 2 * cells.size()) size *= 2;
  shift_ = 64 - __builtin_ctzll(size);
  table_.assign(size, {nullptr, Vec3{}});
  for (Ch c : cells) {
    if (tr.is_infinite(c)) continue;
    std::size_t k = slot(&*c);
    while (table_[k].first) k = (k + 1) & (size - 1);
    table_[k] = {&*c, vec(tr.dual(c))};
  }
}

Vec3 CellCentres::operator()(const Tr& tr, Ch c) const {
  if (!table_.empty())
    for (std::size_t k = slot(&*c); table_[k].first; k = (k + 1) & (table_.size() - 1))
      if (table_[k].first == &*c) return table_[k].second;
  return vec(tr.dual(c));
}

FacetInfo edge_surface_of(const Tr& tr, const SurfaceSampler& f, Ch c, int i, const CellCentres& centres) {
  const CubeGrid& grid = f.grid();
  Ch n = c->neighbor(i);
  const int j = n->index(c);
  FacetInfo fi;
  fi.state = kComputed;
  if (!tr.is_infinite(c, i)) {
    const std::array<Vh, 3> fv = facet_vertices(c, i);
    const Vec3 p0 = vec(fv[0]->point());
    const bool ci = tr.is_infinite(c), ni = tr.is_infinite(n);
    Vec3 a, b;
    bool ok = true;
    if (!ci && !ni) {
      a = centres(tr, c);
      b = centres(tr, n);
      if (b < a) std::swap(a, b);  // lexicographic: both sides agree bit for bit
      ok = a != b;                 // zero-length Voronoi edge: not restricted
    } else {
      // A ray from the finite cell's circumcentre, away from its fourth vertex.
      Ch fc = ci ? n : c;
      const int fi_ = ci ? j : i;
      const Vec3 q0 = p0, q1 = vec(fv[1]->point()), q2 = vec(fv[2]->point()), opp = vec(fc->vertex(fi_)->point());
      Vec3 nrm = cross(sub(q1, q0), sub(q2, q0));
      if (dot(nrm, sub(opp, q0)) > 0) nrm = {-nrm[0], -nrm[1], -nrm[2]};
      const double nl = norm(nrm);
      ok = nl > 0;
      if (ok) {
        a = centres(tr, fc);
        double reach = 0;  // far enough to leave the box
        for (int k = 0; k < 3; ++k) reach += std::abs(a[k]) + grid.hi[k];
        b = {a[0] + nrm[0] / nl * reach, a[1] + nrm[1] / nl * reach, a[2] + nrm[2] / nl * reach};
      }
    }
    if (ok) {
      const EdgeCrossing e = edge_surface(f, a, b, p0);
      if (e.count > 0) {
        fi.state |= kRestricted;
        if (e.count > 1) fi.state |= kMulti;
        std::copy(e.x.begin(), e.x.end(), fi.x);
        fi.r2 = dist2(e.x, p0);
        const Vec3 gr = f.gradient(e.x);
        for (int k = 0; k < 3; ++k) fi.grad[k] = float(gr[k]);
      }
    }
  }
  return fi;
}

} // namespace imgmesh::surface_detail
