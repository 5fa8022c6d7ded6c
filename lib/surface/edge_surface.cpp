// EdgeSurface (8.2) and VorEdge's Voronoi edges: where the Voronoi edge dual to
// a Delaunay facet meets S, found on the cube grid.
#include "surface/edge_surface.hpp"

#include <algorithm>
#include <cmath>

namespace imgmesh::surface_detail {

bool clip_to_box(const CubeGrid& grid, const Vec3& a, const Vec3& d, double& t0, double& t1) {
  t0 = 0, t1 = 1;
  for (int i = 0; i < 3; ++i) {
    if (d[i] == 0) {
      if (a[i] < 0 || a[i] > grid.hi[i]) return false;
      continue;
    }
    double ta = (0 - a[i]) / d[i], tb = (grid.hi[i] - a[i]) / d[i];
    if (ta > tb) std::swap(ta, tb);
    t0 = std::max(t0, ta);
    t1 = std::min(t1, tb);
  }
  return t0 < t1;
}

void plane_crossings(const Vec3& a, const Vec3& d, double ta, double tb, const double step[3], std::vector<double>& ts) {
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
}

namespace {

// How far x lies outside the box of voxel centres (0 inside), per axis at most.
double beyond_box(const CubeGrid& grid, const Vec3& x) {
  double out = 0;
  for (int i = 0; i < 3; ++i) out = std::max({out, -x[i], x[i] - grid.hi[i]});
  return out;
}

// The circumcentre of triangle (p, q, r), from p.
Vec3 circumcentre(const Vec3& p, const Vec3& q, const Vec3& r) {
  const Vec3 u = sub(q, p), v = sub(r, p), n = cross(u, v);
  const double n2 = dot(n, n);
  const Vec3 a = cross(v, n), b = cross(n, u);
  const double su = dot(u, u), sv = dot(v, v);
  return {p[0] + (su * a[0] + sv * b[0]) / (2 * n2), p[1] + (su * a[1] + sv * b[1]) / (2 * n2),
          p[2] + (su * a[2] + sv * b[2]) / (2 * n2)};
}

} // namespace

bool walk_ends(const CubeGrid& grid, const Vec3& a, const Vec3& b, const std::array<Vec3, 3>* sites, Vec3& a0, Vec3& b0) {
  // Beyond 2^16 delta an end's rounding (2^-53 of its distance) exceeds
  // the root finder's tolerance (1e-11 delta); nearer, the ends stay as
  // they are (the outputs on isotropic images, which have such ends up to
  // ~10^6 voxels away, unchanged).
  const double far = 65536 * grid.delta;
  a0 = a;
  b0 = b;
  if (!(beyond_box(grid, a) > far)) return true;
  if (!(beyond_box(grid, b) > far)) {
    std::swap(a0, b0);
    return true;
  }
  if (!sites) return true;
  // Both far: the line through the facet's circumcentre c (within the box's
  // diameter of its sites when the line meets the box), along b - a; the
  // box lies within `reach` of c.
  const Vec3 c = circumcentre((*sites)[0], (*sites)[1], (*sites)[2]);
  const Vec3 d = sub(b, a);
  const double len = norm(d);
  if (!(len > 0) || !std::isfinite(c[0] + c[1] + c[2])) return false;
  const Vec3 u{d[0] / len, d[1] / len, d[2] / len};
  double reach2 = 0;
  for (int i = 0; i < 3; ++i) reach2 += std::pow(std::max(std::abs(c[i]), std::abs(c[i] - grid.hi[i])), 2);
  const double reach = std::sqrt(reach2) + grid.delta;
  const double sa = std::max(dot(sub(a, c), u), -reach), sb = std::min(dot(sub(b, c), u), reach);
  if (!(sa < sb)) return false;
  a0 = {c[0] + sa * u[0], c[1] + sa * u[1], c[2] + sa * u[2]};
  b0 = {c[0] + sb * u[0], c[1] + sb * u[1], c[2] + sb * u[2]};
  return true;
}

namespace {

// A piece [ta, tb] of the edge in an active cube left to sample; monotone:
// f is monotone along it (one root or none).
struct EdgePiece {
  double ta, tb;
  bool monotone;
};
// The sign changes of f found along the edge, as pairs (t before, t after)
// with f at both (the root finder needs no evaluation of its own at the
// ends); a tangency's double root is a pair (t, t), twice.
struct SignChanges {
  std::vector<std::pair<double, double>> ch;
  std::vector<std::pair<double, double>> fv;
  void clear() { ch.clear(), fv.clear(); }
  void add(double ta, double tb, double fa, double fb) { ch.emplace_back(ta, tb), fv.emplace_back(fa, fb); }
};

// EdgeSurface's walk along segment [a, b] = a + t d: the pieces of it in
// active cubes that may hold a root, then their sign changes and roots.
// Scratch reused across calls (no allocation per facet).
struct EdgeWalk {
  EdgeWalk(const SurfaceSampler& f, const Vec3& a, const Vec3& b, const Vec3& d, std::vector<EdgePiece>& pieces)
      : f(f), grid(f.grid()), a(a), b(b), d(d), len(norm(d)), dir{d[0] / len, d[1] / len, d[2] / len}, pieces(pieces) {}
  const SurfaceSampler& f;
  const CubeGrid& grid;
  const Vec3& a;
  const Vec3& b;
  const Vec3 d;  // b - a
  const double len;
  const Vec3 dir;
  std::vector<EdgePiece>& pieces;

  Vec3 at(double t) const {
    if (t == 0) return a;  // Voronoi vertices bit-exact: consistent signs (8.4(1))
    if (t == 1) return b;
    return {a[0] + t * d[0], a[1] + t * d[1], a[2] + t * d[2]};
  }
  void active_pieces(double t0, double t1);
  void decide(double ta, double tb, int depth);
  void changes(const EdgePiece& p, SignChanges& c) const;
  void dip(double ta, double tb, bool in, SignChanges& c) const;
  bool root(const std::pair<double, double>& c, const std::pair<double, double>& fab, Vec3& x) const;
};

} // namespace

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
EdgeCrossing edge_surface(const SurfaceSampler& f, const Vec3& a_in, const Vec3& b_in, const Vec3& site,
                          const std::array<Vec3, 3>* sites) {
  EdgeCrossing out;
  Vec3 a, b;
  if (!walk_ends(f.grid(), a_in, b_in, sites, a, b)) return out;
  const Vec3 d = sub(b, a);
  double t0, t1;
  if (!clip_to_box(f.grid(), a, d, t0, t1)) return out;
  thread_local std::vector<EdgePiece> pieces;
  thread_local SignChanges first_changes, last_changes;
  EdgeWalk w(f, a, b, d, pieces);
  w.active_pieces(t0, t1);
  if (pieces.empty()) return out;
  // Forward to the first piece with a root, backward to the last one.
  first_changes.clear();
  last_changes.clear();
  std::size_t first = pieces.size();
  for (std::size_t k = 0; k < pieces.size() && first == pieces.size(); ++k) {
    w.changes(pieces[k], first_changes);
    if (!first_changes.ch.empty()) first = k;
  }
  if (first == pieces.size()) return out;
  for (std::size_t k = pieces.size() - 1; k > first && last_changes.ch.empty(); --k) w.changes(pieces[k], last_changes);
  // The first crossing, and the last one if it is another.
  Vec3 x0, x1;
  if (!w.root(first_changes.ch.front(), first_changes.fv.front(), x0)) return out;
  out.count = 1;
  out.x = x0;
  if (!last_changes.ch.empty()) {
    if (w.root(last_changes.ch.back(), last_changes.fv.back(), x1)) out.count = 2;
  } else if (first_changes.ch.size() > 1) {
    if (w.root(first_changes.ch.back(), first_changes.fv.back(), x1)) out.count = 2;
  }
  // x_t: the crossing farthest from the facet's vertices (7.6: largest ball).
  if (out.count == 2 && dist2(x1, site) > dist2(x0, site)) out.x = x1;
  return out;
}

// Pieces of [t0, t1] inside active cubes, in order: where the segment
// crosses planes spaced `step` (Amanatides-Woo's events), first at the
// block level, then cube by cube inside active blocks.
void EdgeWalk::active_pieces(double t0, double t1) {
  thread_local std::vector<double> tblock, tcube;
  pieces.clear();
  const double bstep[3] = {grid.s[0] * CubeGrid::kBlock, grid.s[1] * CubeGrid::kBlock, grid.s[2] * CubeGrid::kBlock};
  plane_crossings(a, d, t0, t1, bstep, tblock);
  for (std::size_t kb = 0; kb + 1 < tblock.size(); ++kb) {
    if (!(tblock[kb + 1] > tblock[kb])) continue;
    const Vec3 mb = at((tblock[kb] + tblock[kb + 1]) / 2);
    long cb[3];
    for (int i = 0; i < 3; ++i) cb[i] = std::clamp(floor_long(mb[i] / bstep[i]), 0L, grid.nb[i] - 1);
    if (!grid.block(cb[0], cb[1], cb[2])) continue;
    plane_crossings(a, d, tblock[kb], tblock[kb + 1], grid.s, tcube);
    for (std::size_t k = 0; k + 1 < tcube.size(); ++k) {
      const double ta = tcube[k], tb = tcube[k + 1];
      if (!(tb > ta)) continue;
      const Vec3 m = at((ta + tb) / 2);
      long c[3];
      for (int i = 0; i < 3; ++i) c[i] = std::clamp(floor_long(m[i] / grid.s[i]), 0L, grid.n[i] - 2);
      if (!grid.active(c[0], c[1], c[2])) continue;
      decide(ta, tb, 0);
    }
  }
}

// The piece [ta, tb] of an active cube by the enclosures (halved up to
// kSplits times); what they leave undecided joins the pieces to sample.
void EdgeWalk::decide(double ta, double tb, int depth) {
  constexpr int kSplits = 2;
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
    decide(ta, tm, depth + 1);
    decide(tm, tb, depth + 1);
    return;
  }
  if (!pieces.empty() && !pieces.back().monotone && pieces.back().tb == ta) pieces.back().tb = tb;  // merge runs
  else pieces.push_back({ta, tb, false});
}

// Near-tangential crossings (8.4(2)): where |f| has a local minimum between
// three samples of one sign that may dip through zero, search the minimum
// (golden section). A sign change there gives two crossings; a minimum at
// |f| ~ 0 is a tangency, reported as a double root at that point (VorEdge
// inserts it, Lemma 8.4.1).
void EdgeWalk::dip(double ta, double tb, bool in, SignChanges& ch) const {
  const double g = 0.6180339887498949;
  const double s = in ? -1 : 1;  // minimise s * f
  double a = ta, b = tb, c = b - g * (b - a), d = a + g * (b - a);
  double fc = f.value(at(c)), fd = f.value(at(d));
  for (int it = 0; it < 40; ++it) {
    for (double tt : {c, d}) {
      const double ft = tt == c ? fc : fd;
      if (SurfaceSampler::inside(ft) != in) {  // crossed: two sign changes around tt
        ch.add(ta, tt, f.value(at(ta)), ft);
        ch.add(tt, tb, ft, std::nan(""));  // f(tb): evaluated if this root is wanted
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
    ch.add(tm, tm, fm, fm);
    ch.add(tm, tm, fm, fm);
  }
}

// All sign changes of one piece, in order: a monotone piece's ends, else
// samples at delta/8 (and the dips between them).
void EdgeWalk::changes(const EdgePiece& p, SignChanges& ch) const {
  if (p.monotone) {
    const double fa = f.value(at(p.ta)), fb = f.value(at(p.tb));
    if (SurfaceSampler::inside(fa) != SurfaceSampler::inside(fb)) ch.add(p.ta, p.tb, fa, fb);
    return;
  }
  const double step = grid.delta / 8;
  const int m = std::max(2, int(std::ceil((p.tb - p.ta) * len / step)));
  double tq = p.ta, fq = 0;  // the sample before the previous one
  double tp = p.ta, fp = f.value(at(tp));
  for (int k = 1; k <= m; ++k) {
    const double t = k == m ? p.tb : p.ta + (p.tb - p.ta) * k / m;
    const double fc = f.value(at(t));
    if (SurfaceSampler::inside(fc) != SurfaceSampler::inside(fp)) {
      ch.add(tp, t, fp, fc);
    } else if (k >= 2 && SurfaceSampler::inside(fq) == SurfaceSampler::inside(fp) && std::abs(fp) < std::abs(fq) &&
               std::abs(fp) < std::abs(fc) && std::abs(fp) < std::abs(fq - fp) + std::abs(fc - fp)) {
      dip(tq, t, SurfaceSampler::inside(fp), ch);
    }
    tq = tp;
    fq = fp;
    tp = t;
    fp = fc;
  }
}

// The root of a sign change (a tangency's double root is its point). The
// pairs come from f's own values, so they bracket; bisect checks it. f at
// the far end is known but after a dip's crossing (NaN there).
bool EdgeWalk::root(const std::pair<double, double>& c, const std::pair<double, double>& fab, Vec3& x) const {
  if (c.first == c.second) {
    x = at(c.first);
    return true;
  }
  const Vec3 b = at(c.second);
  return f.bisect(at(c.first), b, fab.first, std::isnan(fab.second) ? f.value(b) : fab.second, x);
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
      // A ray from the finite cell's circumcentre, away from its fourth
      // vertex: the side by the exact predicate (a flat cell's fourth vertex
      // lies within rounding of the facet's plane, and the ray pointed back
      // through the cell: surface centres on the wrong half of the line,
      // which their insertion did not destroy; issue 35).
      Ch fc = ci ? n : c;
      const int fi_ = ci ? j : i;
      const Vec3 q0 = p0, q1 = vec(fv[1]->point()), q2 = vec(fv[2]->point());
      Vec3 nrm = cross(sub(q1, q0), sub(q2, q0));
      if (CGAL::orientation(fv[0]->point(), fv[1]->point(), fv[2]->point(), fc->vertex(fi_)->point()) == CGAL::POSITIVE)
        nrm = {-nrm[0], -nrm[1], -nrm[2]};
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
      const std::array<Vec3, 3> sites{p0, vec(fv[1]->point()), vec(fv[2]->point())};
      const EdgeCrossing e = edge_surface(f, a, b, p0, &sites);
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
