// Quad collapse (Canann, Muthukrishnan and Phillips, 1998): a squashed
// quad (a, b, c, d) goes by merging a and c, at the fixed one if either is
// fixed, else at their midpoint; also, where two free valence-3 vertices
// face each other, the valence-driven collapse (on a Patch, undone unless
// the relaxed patch's worst mu holds).
#include "quadsmooth/smooth_mesh.hpp"

#include <algorithm>

namespace imgmesh::quadsmooth_detail {

namespace {

// Collapses for the worst mu are tried only on quads below sin(15 deg);
// valence-driven ones may run anywhere.
constexpr double kCollapseBelow = 0.25881904510252074;

} // namespace

bool collapse_quad(QuadMesh& qm, int q, int diag, SmoothStats& st) {
  std::vector<Point2>& P = qm.points;
  const Quad C = qm.quads[q];
  int a = C[diag], c = C[diag + 2];
  const int b = C[diag + 1], d = C[(diag + 3) & 3];
  if (qm.vertex_dead[a] || qm.vertex_dead[c]) return false;
  if (qm.fixed[a] && qm.fixed[c]) return false;
  // Collapses are for the worst quads (short diagonal, squashed), and
  // for diagonals of two free valence-3 vertices (they merge into a
  // regular one) when b or d has more quads than it wants, which it
  // then loses (Canann et al.'s valence-driven collapse).
  bool valence = false;
  if (!qm.fixed[a] && !qm.fixed[c] && qm.vertex_quads[a].size() == 3 && qm.vertex_quads[c].size() == 3) {
    const Fan fb = qm.fan(b, q), fd = qm.fan(d, q);
    valence = fb.count - fb.ideal + fd.count - fd.ideal > 0;
  }
  if (!valence && qm.quad_sin_mu[q] >= kCollapseBelow) return false;
  bool feat = false;
  for (int t = 0; t < 4; ++t) feat = feat || qm.is_feature(C[t], C[(t + 1) & 3]);
  if (feat) return false;
  if (qm.fixed[c]) std::swap(a, c);  // keep the fixed one (a), merge c into it
  // Link condition: no other quad holds both a and c, and a and c share
  // no edge neighbour besides b and d.
  bool bad = false;
  for (int o : qm.vertex_quads[c])
    if (o != q && std::find(qm.quads[o].begin(), qm.quads[o].end(), a) != qm.quads[o].end()) bad = true;
  if (bad) return false;
  std::vector<int> na;
  for (int o : qm.vertex_quads[a]) {
    if (o == q) continue;
    const Quad& E = qm.quads[o];
    for (int t = 0; t < 4; ++t)
      if (E[t] == a) { na.push_back(E[(t + 1) & 3]); na.push_back(E[(t + 3) & 3]); }
  }
  for (int o : qm.vertex_quads[c]) {
    if (o == q) continue;
    const Quad& E = qm.quads[o];
    for (int t = 0; t < 4; ++t)
      if (E[t] == c)
        for (int x : {E[(t + 1) & 3], E[(t + 3) & 3]})
          if (x != b && x != d && std::find(na.begin(), na.end(), x) != na.end()) bad = true;
  }
  if (bad) return false;
  // b and d lose a quad: interior ones of valence 3 would become
  // doublets and boundary ones must keep one; leave those alone.
  if (qm.vertex_quads[b].size() <= (qm.fixed[b] ? 1u : 3u) || qm.vertex_quads[d].size() <= (qm.fixed[d] ? 1u : 3u))
    return false;
  double worst_old = 2;
  for (int o : qm.vertex_quads[a]) worst_old = std::min(worst_old, qm.quad_sin_mu[o]);
  for (int o : qm.vertex_quads[c]) worst_old = std::min(worst_old, qm.quad_sin_mu[o]);
  const Point2 pa = P[a], pc = P[c];
  const Point2 pm = qm.fixed[a] ? pa : Point2{0.5 * (pa[0] + pc[0]), 0.5 * (pa[1] + pc[1])};
  // Evaluate with c replaced by a at pm.
  P[a] = pm;
  bool ok = true;
  double worst = 2;
  auto eval = [&](int o) {
    if (o == q || !ok) return;
    Quad E = qm.quads[o];
    for (int& x : E) if (x == c) x = a;
    if (!qm.convex(E)) { ok = false; return; }
    worst = std::min(worst, qm.sin_mu_of(E));
  };
  for (int o : qm.vertex_quads[a]) eval(o);
  for (int o : qm.vertex_quads[c]) eval(o);
  if (!ok || (!valence && worst <= worst_old * (1 + 1e-9) + 1e-15)) { P[a] = pa; return false; }
  Patch pt;
  if (valence) {
    P[a] = pa;
    qm.save_patch({a, c, b, d}, pt);
    P[a] = pm;
  }
  // Commit.
  for (int x : C) qm.remove_from(x, q);
  qm.quad_dead[q] = 1;
  for (int o : qm.vertex_quads[c]) {
    for (int& x : qm.quads[o]) if (x == c) x = a;
    qm.vertex_quads[a].push_back(o);
  }
  qm.vertex_quads[c].clear();
  qm.vertex_dead[c] = 1;
  for (int o : qm.vertex_quads[a]) qm.quad_sin_mu[o] = qm.sin_mu_of(qm.quads[o]);
  if (valence) {
    // Taken if, once relaxed, the worst mu around has not dropped.
    const double before = std::min(qm.patch_worst(pt), worst_old);
    relax(qm, pt);
    if (qm.patch_worst(pt) < before) { qm.rollback(pt); return false; }
    ++st.valence_collapses;
  }
  qm.wake(a);
  ++st.collapses;
  return true;
}

void collapse_pass(QuadMesh& qm, SmoothStats& st) {
  for (std::size_t q = 0; q < qm.quads.size(); ++q) {
    if (qm.quad_dead[q]) continue;
    for (int diag = 0; diag < 2; ++diag)
      if (collapse_quad(qm, int(q), diag, st)) break;
  }
}

} // namespace imgmesh::quadsmooth_detail
