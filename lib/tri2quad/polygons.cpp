// Appendix B of the thesis and the triangle splits, as constructions that
// place Steiner points in floating point and verify every quad exactly.
// The reconstructions follow doc/tri2quad.md (sections 1, 3.2-3.4, 3.8).
#include "tri2quad/polygons.hpp"

#include "quad/quality.hpp"

#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>

namespace imgmesh::tri2quad_detail {

namespace {
double cross2(double ux, double uy, double vx, double vy) { return ux * vy - uy * vx; }
P2 lerp(const P2& a, const P2& b, double t) { return {a[0] + t * (b[0] - a[0]), a[1] + t * (b[1] - a[1])}; }
P2 mid(const P2& a, const P2& b) { return lerp(a, b, 0.5); }

bool good_local(const LocalPatch& lp, const Quad& q) {
  return good_quad(lp.p[q[0]], lp.p[q[1]], lp.p[q[2]], lp.p[q[3]]);
}

double quad_mu(const LocalPatch& lp, const Quad& q) {
  return joe_mu(lp.p[q[0]], lp.p[q[1]], lp.p[q[2]], lp.p[q[3]]);
}

// Candidate points of a region: centroid, then toward each vertex.
std::vector<P2> candidates(const std::vector<P2>& region) {
  std::vector<P2> out;
  if (region.size() < 3) return out;
  const P2 c = centroid(region);
  out.push_back(c);
  for (double f : {0.5, 0.85, 0.25})
    for (const P2& v : region) out.push_back(lerp(c, v, f));
  return out;
}

// The placement rule: x is the only unknown of each quad of qs and each
// triangle of ts (x last in the triangle). For every candidate that passes
// the local exact checks, call then(); stop at the first success.
bool place(LocalPatch& lp, int x, const std::vector<P2>& bound, const std::vector<Quad>& qs,
           const std::vector<std::array<int, 3>>& ts, std::vector<HalfPlane> hp,
           const std::function<bool()>& then) {
  for (const Quad& q : qs) {
    int i = 0;
    while (q[i] != x) ++i;
    const P2& B = lp.p[q[(i + 1) % 4]];
    const P2& D = lp.p[q[(i + 2) % 4]];
    const P2& A = lp.p[q[(i + 3) % 4]];
    hp.push_back({B, A});  // turn at x
    hp.push_back({D, A});  // turn at A
    hp.push_back({B, D});  // turn at B
  }
  for (const auto& t : ts) hp.push_back({lp.p[t[0]], lp.p[t[1]]});
  const auto region = clip(bound, hp);
  // Every valid candidate, best shaped first (Joe's mu of the quads it
  // makes, the smallest angle of its triangles), so the point is not merely
  // valid but as good as we can cheaply get.
  std::vector<std::pair<double, P2>> valid;
  for (const P2& c : candidates(region)) {
    lp.p[x] = c;
    bool ok = true;
    for (const Quad& q : qs) ok = ok && good_local(lp, q);
    for (const auto& t : ts) ok = ok && good_triangle(lp.p[t[0]], lp.p[t[1]], lp.p[t[2]]);
    if (!ok) continue;
    // The triangles count too: a leftover sliver makes a poor quad later.
    double score = 90;
    for (const Quad& q : qs) score = std::min(score, joe_mu(lp.p[q[0]], lp.p[q[1]], lp.p[q[2]], lp.p[q[3]]));
    for (const auto& t : ts) score = std::min(score, min_triangle_angle(lp.p[t[0]], lp.p[t[1]], lp.p[t[2]]));
    valid.push_back({score, c});
  }
  std::stable_sort(valid.begin(), valid.end(), [](const auto& a, const auto& b) { return a.first > b.first; });
  for (const auto& [score, c] : valid) {
    lp.p[x] = c;
    if (then()) return true;
  }
  return false;
}

std::vector<P2> pts(const LocalPatch& lp, const Ring& r) {
  std::vector<P2> v;
  for (int i : r) v.push_back(lp.p[i]);
  return v;
}

std::vector<P2> bbox_poly(const std::vector<P2>& v, double grow) {
  double x0 = v[0][0], x1 = x0, y0 = v[0][1], y1 = y0;
  for (const P2& p : v) {
    x0 = std::min(x0, p[0]); x1 = std::max(x1, p[0]);
    y0 = std::min(y0, p[1]); y1 = std::max(y1, p[1]);
  }
  const double g = grow * std::max(x1 - x0, y1 - y0);
  return {{x0 - g, y0 - g}, {x1 + g, y0 - g}, {x1 + g, y1 + g}, {x0 - g, y1 + g}};
}

// Parameter t > 0 where the ray o + t d leaves the convex polygon k.
double exit_param(const std::vector<P2>& k, const P2& o, const P2& d) {
  double best = std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i < k.size(); ++i) {
    const P2& u = k[i];
    const P2& v = k[(i + 1) % k.size()];
    const double ex = v[0] - u[0], ey = v[1] - u[1];
    const double den = cross2(ex, ey, d[0], d[1]);
    if (den < 0) {
      const double t = -cross2(ex, ey, o[0] - u[0], o[1] - u[1]) / den;
      if (t > 0) best = std::min(best, t);
    }
  }
  return best;
}

// Parameter rho of o + rho w on the line (u, v); NaN when parallel.
double line_param(const P2& o, const P2& w, const P2& u, const P2& v) {
  const double ex = v[0] - u[0], ey = v[1] - u[1];
  const double den = cross2(ex, ey, w[0], w[1]);
  if (den == 0) return std::numeric_limits<double>::quiet_NaN();
  return -cross2(ex, ey, o[0] - u[0], o[1] - u[1]) / den;
}

// Half-planes for the unknown x from the turns of qs in which x is the only
// point not yet placed (the ids in `later` are not).
std::vector<HalfPlane> turns_of(const LocalPatch& lp, int x, const std::vector<int>& later,
                                const std::vector<Quad>& qs) {
  auto unplaced = [&](int v) { return std::find(later.begin(), later.end(), v) != later.end(); };
  std::vector<HalfPlane> hp;
  for (const Quad& q : qs)
    for (int i = 0; i < 4; ++i) {
      const int A = q[(i + 3) % 4], B = q[i], C = q[(i + 1) % 4];
      if (unplaced(A) || unplaced(B) || unplaced(C)) continue;
      if (A == x) hp.push_back({lp.p[B], lp.p[C]});
      else if (B == x) hp.push_back({lp.p[C], lp.p[A]});
      else if (C == x) hp.push_back({lp.p[A], lp.p[B]});
    }
  return hp;
}

// The new points xs[i..] one after another, each in `bound` by the turns
// of qs that involve it and no point placed after it; done() once all are
// placed. True at the first success.
bool place_seq(LocalPatch& lp, const std::vector<int>& xs, std::size_t i, const std::vector<P2>& bound,
               const std::vector<Quad>& qs, const std::function<bool()>& done) {
  if (i == xs.size()) return done();
  const std::vector<int> later(xs.begin() + std::ptrdiff_t(i) + 1, xs.end());
  return place(lp, xs[i], bound, {}, {}, turns_of(lp, xs[i], later, qs),
               [&] { return place_seq(lp, xs, i + 1, bound, qs, done); });
}

bool quads_good(const LocalPatch& lp, const std::vector<Quad>& qs) {
  for (const Quad& q : qs)
    if (!good_local(lp, q)) return false;
  return true;
}

bool all_good(const LocalPatch& lp, std::size_t from) {
  for (std::size_t i = from; i < lp.quads.size(); ++i)
    if (!good_local(lp, lp.quads[i])) return false;
  return true;
}

// The nested template of B.1.2: ring quads (c_i, c_i+1, in_i+1, in_i) and
// the inner quad, with in_i = h + lambda_i (c_i - h).
bool nested_homothety(LocalPatch& lp, const Ring& c, int k, int q, const P2& h,
                      const std::array<double, 4>& lambda) {
  const auto m = lp.mark();
  std::array<int, 4> in{};
  for (int i = 0; i < 4; ++i)
    in[i] = (i == k) ? q : lp.add_new(lerp(h, lp.p[c[i]], lambda[i]));
  for (int i = 0; i < 4; ++i) lp.quads.push_back({c[i], c[(i + 1) % 4], in[(i + 1) % 4], in[i]});
  lp.quads.push_back({in[0], in[1], in[2], in[3]});
  if (all_good(lp, m.nq)) return true;
  lp.rollback(m);
  return false;
}

std::vector<P2> kernel(const LocalPatch& lp, const Ring& c) {
  const auto v = pts(lp, c);
  std::vector<HalfPlane> hp;
  for (std::size_t i = 0; i < c.size(); ++i) hp.push_back({v[i], v[(i + 1) % v.size()]});
  return clip(bbox_poly(v, 1.0), hp);
}

// Pushed homothety about h for a quad whose corner r is reflex or flat
// (doc/tri2quad.md 3.3), with in_r = h + sigma (c_r - h).
bool pushed_homothety(LocalPatch& lp, const Ring& c, int r, int q, const P2& h, double sigma) {
  const P2 cr = lp.p[c[r]];
  const P2 w = {cr[0] - h[0], cr[1] - h[1]};
  const P2 cm = lp.p[c[(r + 3) % 4]];
  const P2 cp = lp.p[c[(r + 1) % 4]];
  const P2 co = lp.p[c[(r + 2) % 4]];
  const double rx = line_param(h, w, cm, cp);
  if (!(rx > 0)) return false;
  double rhi = std::numeric_limits<double>::infinity();
  for (double t : {line_param(h, w, co, cm), line_param(h, w, cp, co)})
    if (t > rx) rhi = std::min(rhi, t);
  for (double f : {0.5, 0.25, 0.75, 0.1, 0.9}) {
    const double rho = std::isfinite(rhi) ? rx + f * (rhi - rx) : rx * (1 + 2 * f);
    std::array<double, 4> lam{};
    for (int i = 0; i < 4; ++i) lam[i] = sigma / rho;
    lam[r] = sigma;
    if (nested_homothety(lp, c, q >= 0 ? r : -1, q, h, lam)) return true;
  }
  return false;
}

int reflex_corner(const LocalPatch& lp, const Ring& c) {
  for (int i = 0; i < 4; ++i)
    if (orientation(lp.p[c[(i + 3) % 4]], lp.p[c[i]], lp.p[c[(i + 1) % 4]]) <= 0) return i;
  return -1;
}
} // namespace

// ---------------------------------------------------------------- B.1.1
bool hexagon(LocalPatch& lp, const Ring& h, int budget) {
  auto H = [&](int i) { return h[((i % 6) + 6) % 6]; };
  auto P = [&](int i) -> const P2& { return lp.p[H(i)]; };
  const auto m = lp.mark();
  // T0: a diagonal between opposite vertices, two quads, no point; of the
  // valid diagonals the one whose worse quad has the larger Joe's mu.
  int best = -1;
  double best_mu = -1;
  for (int i = 0; i < 3; ++i) {
    const Quad a{H(i), H(i + 1), H(i + 2), H(i + 3)}, b{H(i + 3), H(i + 4), H(i + 5), H(i)};
    if (!good_local(lp, a) || !good_local(lp, b)) continue;
    const double mu = std::min(quad_mu(lp, a), quad_mu(lp, b));
    if (mu > best_mu) { best_mu = mu; best = i; }
  }
  if (best >= 0) {
    lp.quads.push_back({H(best), H(best + 1), H(best + 2), H(best + 3)});
    lp.quads.push_back({H(best + 3), H(best + 4), H(best + 5), H(best)});
    return true;
  }
  if (budget < 1) return false;
  // T1: one point joined to alternate vertices, three quads.
  for (int pi = 0; pi < 2; ++pi) {
    if (!good_triangle(P(pi), P(pi + 2), P(pi + 4))) continue;
    const int s = lp.add_new();
    std::vector<Quad> qs;
    for (int j = pi; j < pi + 6; j += 2) qs.push_back({H(j), H(j + 1), H(j + 2), s});
    if (place(lp, s, {P(pi), P(pi + 2), P(pi + 4)}, qs, {}, {}, [] { return true; })) {
      for (const Quad& q : qs) lp.quads.push_back(q);
      return true;
    }
    lp.rollback(m);
  }
  if (budget < 2) return false;
  const auto hv = pts(lp, h);
  // S2 (doc/tri2quad.md 3.2): two adjacent points s (near h_j) and t (near h_{j+3}),
  // both h_j and h_{j+3} convex; four quads. s first (its own quad and the
  // half-planes that keep its neighbours usable), then t by the same rule.
  for (int j = 0; j < 6; ++j) {
    if (orientation(P(j - 1), P(j), P(j + 1)) <= 0 || orientation(P(j + 2), P(j + 3), P(j + 4)) <= 0) continue;
    const int s = lp.add_new(), t = lp.add_new();
    const Quad q1{H(j - 1), H(j), H(j + 1), s}, q2{s, H(j + 1), H(j + 2), t}, q3{H(j + 2), H(j + 3), H(j + 4), t},
        q4{H(j + 4), H(j + 5), s, t};
    const bool ok = place(lp, s, hv, {q1}, {}, {{P(j + 1), P(j + 2)}, {P(j - 2), P(j - 1)}}, [&] {
      return place(lp, t, hv, {q2, q3, q4}, {}, {}, [&] {
        return good_local(lp, q1) && good_local(lp, q2) && good_local(lp, q3) && good_local(lp, q4);
      });
    });
    if (ok) {
      for (const Quad& q : {q1, q2, q3, q4}) lp.quads.push_back(q);
      return true;
    }
    lp.rollback(m);
  }
  // PEEL: cut one quad off a convex corner, recurse on the hexagon left.
  for (int j = 0; j < 6; ++j) {
    if (orientation(P(j - 1), P(j), P(j + 1)) <= 0) continue;
    for (int variant = 0; variant < 2; ++variant) {
      const int s = lp.add_new();
      std::vector<HalfPlane> hp = {{P(j - 1), P(j)}, {P(j), P(j + 1)}, {P(j - 1), P(j + 1)}};
      if (variant == 0) {
        hp.push_back({P(j - 2), P(j - 1)});
        hp.push_back({P(j + 1), P(j + 2)});
      }
      const auto region = clip(hv, hp);
      if (region.size() < 3) { lp.rollback(m); continue; }
      const P2 X = centroid(region), M = mid(P(j - 1), P(j + 1));
      for (double f : {1.0, 0.5, 0.25, 0.1, 0.03}) {
        lp.p[s] = lerp(M, X, f);
        const Quad q{H(j - 1), H(j), H(j + 1), s};
        if (!good_local(lp, q)) continue;
        Ring rest = h;
        rest[((j % 6) + 6) % 6] = s;
        if (!simple_ccw(pts(lp, rest))) continue;
        const auto m2 = lp.mark();
        lp.quads.push_back(q);
        if (hexagon(lp, rest, budget - 1)) return true;
        lp.rollback(m2);
      }
      lp.rollback(m);
    }
  }
  return false;
}

// ---------------------------------------------------------------- B.1.2
bool quad_with_point(LocalPatch& lp, const Ring& c, int q) {
  const P2 qp = lp.p[q];
  const int r = reflex_corner(lp, c);
  if (r < 0) {
    // Convex: closed form, each corner in turn as the one joined to q.
    const auto poly = pts(lp, c);
    for (int k = 0; k < 4; ++k) {
      const P2& ck = lp.p[c[k]];
      const P2 d = {qp[0] - ck[0], qp[1] - ck[1]};
      const double ts = exit_param(poly, qp, d);
      if (!std::isfinite(ts)) continue;
      for (double frac : {0.5, 0.3, 0.7}) {
        const double mu = ts * frac;
        const P2 hc = {qp[0] + mu * d[0], qp[1] + mu * d[1]};
        const double lam = mu / (1 + mu);
        if (nested_homothety(lp, c, k, q, hc, {lam, lam, lam, lam})) return true;
      }
    }
  } else {
    const auto K = kernel(lp, c);
    bool inK = K.size() >= 3;
    for (int i = 0; i < 4 && inK; ++i)
      inK = orientation(lp.p[c[i]], lp.p[c[(i + 1) % 4]], qp) > 0;
    if (inK) {
      const P2& cr = lp.p[c[r]];
      const P2 d = {qp[0] - cr[0], qp[1] - cr[1]};
      const double ts = exit_param(K, qp, d);
      if (std::isfinite(ts))
        for (double frac : {0.5, 0.3, 0.7}) {
          const double mu = ts * frac;
          const P2 hc = {qp[0] + mu * d[0], qp[1] + mu * d[1]};
          if (pushed_homothety(lp, c, r, q, hc, mu / (1 + mu))) return true;
        }
    }
  }
  // Search (the "arm" case, and a safety net): q joined to corner k, the
  // other three inner points placed one at a time by the placement rule,
  // in a few orders (a needle's inner point is the hard one to place).
  const auto Q = pts(lp, c);
  for (int k = 0; k < 4; ++k) {
    const auto m = lp.mark();
    std::array<int, 4> in{};
    for (int i = 0; i < 4; ++i) in[i] = (i == k) ? q : lp.add_new();
    std::vector<Quad> qs;
    for (int i = 0; i < 4; ++i) qs.push_back({c[i], c[(i + 1) % 4], in[(i + 1) % 4], in[i]});
    qs.push_back({in[0], in[1], in[2], in[3]});
    const int a1 = in[(k + 1) % 4], a2 = in[(k + 3) % 4], a3 = in[(k + 2) % 4];
    for (const auto& order : {std::vector<int>{a1, a2, a3}, {a3, a1, a2}, {a1, a3, a2}, {a3, a2, a1}})
      if (place_seq(lp, order, 0, Q, qs, [&] { return quads_good(lp, qs); })) {
        for (const Quad& x : qs) lp.quads.push_back(x);
        return true;
      }
    lp.rollback(m);
  }
  return false;
}

bool quad_nested_free(LocalPatch& lp, const Ring& c) {
  const auto K = kernel(lp, c);
  if (K.size() < 3) return false;
  const auto m = lp.mark();
  for (double f : {0.0, 0.3, 0.6}) {
    const P2 k0 = centroid(K);
    for (const P2& v : K) {
      const int q = lp.add_new(lerp(k0, v, f));
      if (quad_with_point(lp, c, q)) return true;
      lp.rollback(m);
      if (f == 0.0) break;
    }
  }
  return false;
}

// ---------------------------------------------------------------- B.2.1
int pentagon(LocalPatch& lp, const Ring& v, int* kind, int hexagon_budget) {
  auto P = [&](int i) -> const P2& { return lp.p[v[i]]; };
  auto V = [&](int i) { return v[i]; };
  const auto m = lp.mark();
  auto set = [&](int k) { if (kind) *kind = k; };
  // Ears on the outgoing edge: no Steiner point; the better-shaped quad
  // when both are valid.
  const bool ear2 = good_triangle(P(0), P(1), P(2)) && good_quad(P(0), P(2), P(3), P(4));
  const bool ear4 = good_triangle(P(4), P(0), P(1)) && good_quad(P(1), P(2), P(3), P(4));
  if (ear2 && (!ear4 || quad_mu(lp, {V(0), V(2), V(3), V(4)}) >= quad_mu(lp, {V(1), V(2), V(3), V(4)}))) {
    lp.quads.push_back({V(0), V(2), V(3), V(4)});
    set(0);
    return V(2);
  }
  if (ear4) {
    lp.quads.push_back({V(1), V(2), V(3), V(4)});
    set(0);
    return V(4);
  }
  // Type 1: the outgoing edge in the centre triangle (v0, v1, v3).
  if (good_triangle(P(0), P(1), P(3)) && good_triangle(P(1), P(2), P(3)) &&
      good_triangle(P(3), P(4), P(0))) {
    const int p1 = lp.add_new();
    const std::vector<Quad> qs = {{V(0), p1, V(3), V(4)}, {V(3), p1, V(1), V(2)}};
    if (place(lp, p1, {P(0), P(1), P(3)}, qs, {{V(0), V(1), p1}}, {}, [] { return true; })) {
      for (const Quad& q : qs) lp.quads.push_back(q);
      set(1);
      return p1;
    }
    lp.rollback(m);
  }
  // Type 2 and its mirror image: the outgoing edge in an ear not at the
  // common vertex. Labels w1..w5 of doc/tri2quad.md 3.4 (w[1..5]).
  for (int mirror = 0; mirror < 2; ++mirror) {
    int w[6];
    if (!mirror) { w[2] = V(0); w[3] = V(1); w[4] = V(2); w[5] = V(3); w[1] = V(4); }
    else { w[5] = V(0); w[1] = V(1); w[2] = V(2); w[3] = V(3); w[4] = V(4); }
    auto W = [&](int i) -> const P2& { return lp.p[w[i]]; };
    if (!(good_triangle(W(4), W(1), W(2)) && good_triangle(W(2), W(3), W(4)) &&
          good_triangle(W(4), W(5), W(1))))
      continue;
    const int p1 = lp.add_new(), p2 = lp.add_new();
    std::vector<Quad> proxy, fin;
    std::vector<P2> b2;
    std::array<int, 3> tri{};
    if (!mirror) {
      proxy = {{w[1], p1, w[4], w[5]}, {w[4], p1, w[2], w[3]}};
      fin = {{w[1], p1, w[4], w[5]}, {w[2], p2, p1, w[1]}, {w[3], w[4], p1, p2}};
      tri = {w[2], w[3], p2};
    } else {
      proxy = {{w[3], w[4], p1, w[2]}, {w[5], w[1], p1, w[4]}};
      fin = {{w[3], w[4], p1, w[2]}, {w[2], p1, p2, w[1]}, {p2, p1, w[4], w[5]}};
      tri = {w[5], w[1], p2};
    }
    bool ok = place(lp, p1, {W(4), W(1), W(2)}, proxy, {}, {}, [&] {
      const std::vector<P2> bound = !mirror ? std::vector<P2>{lp.p[p1], W(2), W(3)}
                                            : std::vector<P2>{lp.p[p1], W(5), W(1)};
      std::vector<Quad> q2;
      for (const Quad& q : fin)
        if (std::find(q.begin(), q.end(), p2) != q.end()) q2.push_back(q);
      return place(lp, p2, bound, q2, {tri}, {}, [&] {
        for (const Quad& q : fin) if (!good_local(lp, q)) return false;
        return true;
      });
    });
    if (ok) {
      for (const Quad& q : fin) lp.quads.push_back(q);
      set(2);
      return p2;
    }
    lp.rollback(m);
  }
  // Only fans from v0 or v1 exist (type 3 in the thesis, which puts a point
  // on the outgoing edge). Instead: leftover (v0, v1, p) with a new apex p,
  // and the hexagon (v1, v2, v3, v4, v0, p) by B.1.1, fewest points first.
  const P2 e0 = P(0), e1 = P(1), em = mid(e0, e1);
  const std::vector<P2> targets = {P(2), P(3), P(4), centroid(pts(lp, v))};
  for (int budget = 0; budget <= hexagon_budget; ++budget)
    for (const P2& X : targets)
      for (double f : {0.3, 0.5, 0.15, 0.7}) {
        const int p = lp.add_new(lerp(em, X, f));
        const Ring hex = {V(1), V(2), V(3), V(4), V(0), p};
        if (good_triangle(e0, e1, lp.p[p]) && simple_ccw(pts(lp, hex)) && hexagon(lp, hex, budget)) {
          set(3);
          return p;
        }
        lp.rollback(m);
      }
  return -1;
}

// ---------------------------------------------------------------- B.3.1
namespace {
// Interior bisector of the polygon vertex cur (neighbours prev, next).
P2 bisector(const P2& prev, const P2& cur, const P2& next) {
  const double ux = next[0] - cur[0], uy = next[1] - cur[1], wx = prev[0] - cur[0], wy = prev[1] - cur[1];
  double th = std::atan2(cross2(ux, uy, wx, wy), ux * wx + uy * wy);
  if (th < 0) th += 2 * std::acos(-1.0);
  const double nu = std::hypot(ux, uy), cs = std::cos(th / 2), sn = std::sin(th / 2);
  return {(ux * cs - uy * sn) / nu, (ux * sn + uy * cs) / nu};
}

// T0 of B.1.1 on the hexagon h: the diagonal (h_t, h_t+3).
void diagonal_split(const Ring& h, int t, std::vector<Quad>& qs) {
  qs.push_back({h[t], h[t + 1], h[t + 2], h[t + 3]});
  qs.push_back({h[t + 3], h[(t + 4) % 6], h[(t + 5) % 6], h[t]});
}

// The octagon o cut by a path o_i - p - o_i+4 through the new point p into
// two hexagons, each split by a diagonal (5 quads); p by the placement
// rule. With `first_bound`, o[0] is a new point too, placed first in that
// region by the turns that do not involve p, with `first_tri` kept proper.
bool two_diagonals(LocalPatch& lp, const Ring& o, int p, const std::vector<P2>* first_bound,
                   const std::array<int, 3>& first_tri) {
  auto O = [&](int i) { return o[i % 8]; };
  const int first = first_bound ? o[0] : -1;
  const auto box = bbox_poly(pts(lp, Ring(o.begin() + 1, o.end())), 0.0);
  for (int i = 0; i < 4; ++i) {
    const Ring h1 = {O(i), O(i + 1), O(i + 2), O(i + 3), O(i + 4), p};
    const Ring h2 = {O(i + 4), O(i + 5), O(i + 6), O(i + 7), O(i), p};
    for (int t1 = 0; t1 < 3; ++t1)
      for (int t2 = 0; t2 < 3; ++t2) {
        std::vector<Quad> qs, with_p;
        diagonal_split(h1, t1, qs);
        diagonal_split(h2, t2, qs);
        bool known_ok = true;
        for (const Quad& q : qs) {
          const bool has_p = std::find(q.begin(), q.end(), p) != q.end();
          if (has_p) with_p.push_back(q);
          else if (std::find(q.begin(), q.end(), first) == q.end()) known_ok = known_ok && good_local(lp, q);
        }
        if (!known_ok) continue;
        auto place_p = [&] { return place(lp, p, box, with_p, {}, {}, [&] { return quads_good(lp, qs); }); };
        const bool ok = first < 0 ? place_p()
                                  : place(lp, first, *first_bound, {}, {first_tri}, turns_of(lp, first, {p}, qs), place_p);
        if (ok) {
          for (const Quad& q : qs) lp.quads.push_back(q);
          return true;
        }
      }
  }
  return false;
}
} // namespace

bool octagon(LocalPatch& lp, const Ring& o, int budget) {
  const auto m = lp.mark();
  auto O = [&](int i) { return o[i % 8]; };
  auto simple = [&](const Ring& r) { return simple_ccw(pts(lp, r)); };
  // A diagonal cuts off a strictly convex quad; B.1.1 on the hexagon left.
  for (int i = 0; i < 8; ++i)
    for (int len : {3, 5}) {
      Ring quad, hex;
      for (int k = 0; k <= len; ++k) (len == 3 ? quad : hex).push_back(O(i + k));
      for (int k = len; k <= 8; ++k) (len == 3 ? hex : quad).push_back(O(i + k));
      const Quad q{quad[0], quad[1], quad[2], quad[3]};
      if (!good_local(lp, q) || !simple(hex)) continue;
      lp.quads.push_back(q);
      if (hexagon(lp, hex, std::min(budget, 3))) return true;
      lp.rollback(m);
    }
  if (budget < 1) return false;
  // A path o_i - p - o_i+4 through one new point cuts two hexagons; first
  // each split by a diagonal, then with p on the way or on a reflex end's
  // bisector and B.1.1 on both.
  const int p = lp.add_new();
  const auto with_p = lp.mark();
  if (two_diagonals(lp, o, p, nullptr, {})) return true;
  for (int i = 0; i < 4; ++i) {
    std::vector<P2> cand;
    for (double f : {0.5, 0.3, 0.7}) cand.push_back(lerp(lp.p[O(i)], lp.p[O(i + 4)], f));
    for (int j : {i, i + 4}) {
      const P2 &a = lp.p[O(j + 7)], &c = lp.p[O(j)], &b = lp.p[O(j + 1)];
      if (orientation(a, c, b) > 0) continue;
      const P2 d = bisector(a, c, b);
      const double L = std::min(std::hypot(a[0] - c[0], a[1] - c[1]), std::hypot(b[0] - c[0], b[1] - c[1]));
      for (double f : {0.4, 0.2, 0.6}) cand.push_back({c[0] + f * L * d[0], c[1] + f * L * d[1]});
    }
    const Ring h1 = {O(i), O(i + 1), O(i + 2), O(i + 3), O(i + 4), p};
    const Ring h2 = {O(i + 4), O(i + 5), O(i + 6), O(i + 7), O(i), p};
    for (const P2& x : cand) {
      lp.p[p] = x;
      if (!simple(h1) || !simple(h2)) continue;
      for (int k1 = 0; k1 < budget; ++k1)
        for (int k2 = 0; k1 + k2 < budget; ++k2) {
          if (hexagon(lp, h1, k1) && hexagon(lp, h2, k2)) return true;
          lp.rollback(with_p);
        }
    }
  }
  lp.rollback(m);
  return false;
}

int heptagon(LocalPatch& lp, const Ring& v, int* kind) {
  auto P = [&](int i) -> P2 { return lp.p[v[i]]; };
  const auto m = lp.mark();
  // A leftover ear on the outgoing edge and B.1.1 for the hexagon left.
  for (int side = 0; side < 2; ++side) {
    const int apex = side == 0 ? v[2] : v[6];
    const Ring rest = side == 0 ? Ring{v[0], v[2], v[3], v[4], v[5], v[6]} : Ring{v[1], v[2], v[3], v[4], v[5], v[6]};
    const bool tri_ok = side == 0 ? good_triangle(P(0), P(1), P(2)) : good_triangle(P(6), P(0), P(1));
    if (!tri_ok || !simple_ccw(pts(lp, rest))) continue;
    if (hexagon(lp, rest)) { if (kind) *kind = 0; return apex; }
    lp.rollback(m);
  }
  // General form (doc/tri2quad.md 3.6): the leftover (v0, v1, p3) leaves the octagon
  // (p3, v1, ..., v6, v0) to close with at most 3 more points (6 quads and
  // 4 points in all). First the thesis's shape, a path through one point
  // p1 and two diagonals (5 quads, 2 points), with p3 placed in the centre
  // triangle by the placement rule; then p3 at fixed places.
  const int p3 = lp.add_new();
  const Ring O = {p3, v[1], v[2], v[3], v[4], v[5], v[6], v[0]};
  const std::vector<P2> own = {P(0), P(1), P(4)};
  if (two_diagonals(lp, O, lp.add_new(), &own, {v[0], v[1], p3})) {
    if (kind) *kind = 1;
    return p3;
  }
  lp.rollback({m.np + 1, m.nq});
  const P2 em = mid(P(0), P(1)), ctr = {(P(0)[0] + P(1)[0] + P(4)[0]) / 3, (P(0)[1] + P(1)[1] + P(4)[1]) / 3};
  for (const P2& X : {ctr, P(4)})
    for (double f3 : {0.3, 0.5, 0.15, 0.7}) {
      lp.p[p3] = lerp(em, X, f3);
      if (good_triangle(P(0), P(1), lp.p[p3]) && octagon(lp, O, 3)) {
        if (kind) *kind = 1;
        return p3;
      }
    }
  lp.rollback(m);
  return -1;
}

bool heptagon_closed(LocalPatch& lp, const Ring& v, int mpt) {
  return octagon(lp, {mpt, v[1], v[2], v[3], v[4], v[5], v[6], v[0]}, 4);
}

// ---------------------------------------------------------------- splits
bool joe_split(LocalPatch& lp, int a, int b, int m, int c) {
  const P2 A = lp.p[a], B = lp.p[b], C = lp.p[c], M = lp.p[m];  // copies: lp.p grows below
  const P2 h = {(A[0] + B[0] + C[0]) / 3, (A[1] + B[1] + C[1]) / 3};
  const P2 w = {M[0] - h[0], M[1] - h[1]};
  const double rx = line_param(h, w, B, C);
  if (!(rx > 0)) return false;
  double rhi = std::numeric_limits<double>::infinity();
  for (double t : {line_param(h, w, A, B), line_param(h, w, C, A)})
    if (t > rx) rhi = std::min(rhi, t);
  const auto mk = lp.mark();
  // The best shaped of a few valid parameter choices (Joe's mu).
  double best = -1, best_sigma = 0, best_f = 0;
  for (int pass = 0; pass < 2; ++pass)
    for (double sigma : {0.5, 0.35, 0.65, 0.2})
      for (double f : {0.5, 0.25, 0.75, 0.1}) {
        if (pass == 1 && (sigma != best_sigma || f != best_f)) continue;
        const double rho = std::isfinite(rhi) ? rx + f * (rhi - rx) : rx * (1 + 2 * f);
        const double lam = sigma / rho;
        const int ia = lp.add_new(lerp(h, A, lam)), ib = lp.add_new(lerp(h, B, lam));
        const int ic = lp.add_new(lerp(h, C, lam)), im = lp.add_new(lerp(h, M, sigma));
        lp.quads.push_back({a, b, ib, ia});
        lp.quads.push_back({b, m, im, ib});
        lp.quads.push_back({m, c, ic, im});
        lp.quads.push_back({c, a, ia, ic});
        lp.quads.push_back({ia, ib, im, ic});
        if (all_good(lp, mk.nq)) {
          if (pass == 1) return true;
          double score = 90;
          for (std::size_t k = mk.nq; k < lp.quads.size(); ++k) {
            const Quad& q = lp.quads[k];
            score = std::min(score, joe_mu(lp.p[q[0]], lp.p[q[1]], lp.p[q[2]], lp.p[q[3]]));
          }
          if (score > best) { best = score; best_sigma = sigma; best_f = f; }
        }
        lp.rollback(mk);
      }
  return false;
}

bool deberg_split(LocalPatch& lp, int a, int b, int c, int mab, int mbc, int mca) {
  const auto mk = lp.mark();
  const int g = lp.add_new();
  const std::vector<Quad> qs = {{a, mab, g, mca}, {b, mbc, g, mab}, {c, mca, g, mbc}};
  if (place(lp, g, {lp.p[a], lp.p[b], lp.p[c]}, qs, {}, {}, [] { return true; })) {
    for (const Quad& q : qs) lp.quads.push_back(q);
    return true;
  }
  lp.rollback(mk);
  return false;
}

} // namespace imgmesh::tri2quad_detail
