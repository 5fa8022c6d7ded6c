// Doublet removal (Canann, Muthukrishnan and Phillips, 1998): a free vertex
// in only two quads (A = (v, a, b, c), B = (v, c, d, a)) cannot have both
// strictly convex; the two merge into (a, b, c, d) and v goes. Beyond it,
// the same for a free vertex of valence 3 that splits a sharp fixed corner
// (open_sharp_corner).
#include "quadsmooth/smooth_mesh.hpp"

#include <algorithm>

namespace imgmesh::quadsmooth_detail {

namespace {

// Quad q's corners in order, beginning at its corner v.
Quad from_corner(const QuadMesh& qm, int q, int v) {
  Quad A = qm.quads[q];
  while (A[0] != v) std::rotate(A.begin(), A.begin() + 1, A.end());
  return A;
}

// The doublet at the free valence-2 vertex v: its quads A = (v, a, b, c)
// and B = (v, c, d, a) as the merged (a, b, c, d) (a repeated corner if
// they are not such a pair).
Quad doublet_merged(const QuadMesh& qm, int v) {
  const Quad A = from_corner(qm, qm.vertex_quads[v][0], v), B = from_corner(qm, qm.vertex_quads[v][1], v);
  if (B[1] != A[3] || B[3] != A[1]) return {A[1], A[1], A[1], A[1]};
  return {A[1], A[2], A[3], B[2]};
}

// Replaces v's two quads by M (doublet_merged), v gone.
void merge_doublet(QuadMesh& qm, int v, const Quad& M) {
  const int q1 = qm.vertex_quads[v][0], q2 = qm.vertex_quads[v][1];
  for (int x : qm.quads[q2]) qm.remove_from(x, q2);
  qm.quad_dead[q2] = 1;
  qm.vertex_dead[v] = 1;
  qm.set_quad(q1, M);
}

} // namespace

bool remove_doublet(QuadMesh& qm, int v) {
  if (qm.fixed[v] || qm.vertex_dead[v] || qm.vertex_quads[v].size() != 2) return false;
  const Quad M = doublet_merged(qm, v);
  if (M[1] == M[3] || !qm.convex(M) ||
      qm.sin_mu_of(M) < std::min(qm.quad_sin_mu[qm.vertex_quads[v][0]], qm.quad_sin_mu[qm.vertex_quads[v][1]]))
    return false;
  merge_doublet(qm, v, M);
  for (int x : M) qm.wake(x);
  return true;
}

namespace {

// open_sharp_corner's other way, for when neither pair of quads keeping c
// is strictly convex where the hexagon's corners stand: m keeps its
// valence but is joined to the hexagon's odd corners instead of its even
// ones (the other parity of the hexagon's one-point split, doc/tri2quad.md
// 3.2 T1), so that c = H[2i] lies in one quad (H[2i-1], c, H[2i+1], m).
// m and the two other even corners (if free; they were bent toward m) are
// placed in turn where their quads are strictly convex; taken if, once the
// patch is relaxed, its worst mu rose.
bool respoke(QuadMesh& qm, int m, const int (&H)[6], const int (&Q)[3], int i) {
  auto at = [&](int k) { return H[(k + 6) % 6]; };
  Patch pt;
  qm.save_patch({m, H[0], H[1], H[2], H[3], H[4], H[5]}, pt);
  const std::vector<double> before = qm.patch_sines(pt);
  for (int j = 0; j < 3; ++j) qm.set_quad(Q[j], {at(2 * i - 1 + 2 * j), at(2 * i + 2 * j), at(2 * i + 1 + 2 * j), m});
  bool ok = true;
  // An even corner left in two quads (it was in three) is a doublet: they merge.
  for (int x : {at(2 * i + 2), at(2 * i + 4)})
    if (!qm.fixed[x] && qm.vertex_quads[x].size() == 2) {
      const Quad M = doublet_merged(qm, x);
      if (M[1] == M[3]) ok = false;
      else merge_doublet(qm, x, M);
    }
  // In turn: where one is stuck, the others' moves may open it.
  for (int round = 0; round < 3 && ok; ++round)
    for (int x : {at(2 * i + 2), at(2 * i + 4), m})
      if (!qm.fixed[x] && !qm.vertex_dead[x]) place_in_star(qm, x);
  for (int q : pt.quads)
    if (ok && !qm.quad_dead[q]) ok = qm.convex(qm.quads[q]);
  if (ok) {
    relax(qm, pt);
    ok = lex_better(qm.patch_sines(pt), before);
  }
  if (ok) {
    for (int x : pt.verts) qm.wake(x);
    return true;
  }
  qm.rollback(pt);
  return false;
}

} // namespace

// After a re-meshing of the patch pt (its sines were `before`): the free
// corners of each quad not strictly convex are placed where their quads are
// (in turn, rounds: one placement may open the next; their stars are in the
// patch, which holds every quad around its vertices; a corner beyond them,
// of a ring vertex's quad, stays: rollback would not put it back), the patch relaxed,
// then its free vertices climb on the worst mu around them (the
// relaxation's energy may leave a new corner quad thin). True, the patch's
// vertices woken, if every quad is strictly convex and the patch's sines
// rose (lex); the caller rolls back otherwise.
bool settle(QuadMesh& qm, const Patch& pt, const std::vector<double>& before, const Accept& accept) {
  auto all_convex = [&] {
    for (int q : pt.quads)
      if (!qm.quad_dead[q] && !qm.convex(qm.quads[q])) return false;
    return true;
  };
  const auto in_patch = [&](int x) { return std::find(pt.verts.begin(), pt.verts.end(), x) != pt.verts.end(); };
  for (int round = 0; round < 4 && !all_convex(); ++round)
    for (int q : pt.quads)
      if (!qm.quad_dead[q] && !qm.convex(qm.quads[q]))
        for (int x : qm.quads[q])
          if (!qm.fixed[x] && in_patch(x)) place_in_star(qm, x);
  if (!all_convex()) return false;
  relax(qm, pt);
  for (int round = 0; round < 3; ++round)
    for (int x : pt.verts)
      if (!qm.fixed[x] && !qm.vertex_dead[x] && qm.vertex_quads[x].size() >= 3) {
        const Quad& A = qm.quads[qm.vertex_quads[x][0]];
        const Point2 &p = qm.points[x], &y = qm.points[A[0] == x ? A[1] : A[0]];
        raise_worst(qm, x, (y[0] - p[0]) * (y[0] - p[0]) + (y[1] - p[1]) * (y[1] - p[1]));
      }
  if (accept ? !accept(pt, before) : !lex_better(qm.patch_sines(pt), before)) return false;
  for (int x : pt.verts)
    if (!qm.vertex_dead[x]) qm.wake(x);
  return true;
}

namespace {

// open_sharp_corner's split of the hexagon into N1 (c in it) and N2 where
// they are not strictly convex as the corners stand (a wedge tip whose
// free neighbours sit on its sides): m goes, then each free hexagon corner
// left in two quads is a doublet and merges away (in turn: one merge can
// leave the next), the others are placed where their quads are strictly
// convex. Taken if every quad of the patch is then strictly convex and,
// once the patch is relaxed, its sines rose (lex).
bool split_and_merge(QuadMesh& qm, int m, const int (&H)[6], const int (&Q)[3], const Quad& N1, const Quad& N2) {
  Patch pt;
  qm.save_patch({m, H[0], H[1], H[2], H[3], H[4], H[5]}, pt);
  const std::vector<double> before = qm.patch_sines(pt);
  qm.set_quad(Q[0], N1);
  qm.set_quad(Q[1], N2);
  for (int x : qm.quads[Q[2]]) qm.remove_from(x, Q[2]);
  qm.quad_dead[Q[2]] = 1;
  qm.vertex_dead[m] = 1;
  bool ok = true;
  for (bool merged = true; merged && ok;) {
    merged = false;
    for (int x : H)
      if (!qm.fixed[x] && !qm.vertex_dead[x] && qm.vertex_quads[x].size() == 2) {
        const Quad M = doublet_merged(qm, x);
        if (M[1] == M[3]) { ok = false; break; }
        merge_doublet(qm, x, M);
        merged = true;
      }
  }
  if (ok && settle(qm, pt, before)) return true;
  qm.rollback(pt);
  return false;
}

} // namespace

bool open_sharp_corner(QuadMesh& qm, int m, bool respoke_too) {
  if (qm.fixed[m] || qm.vertex_dead[m] || qm.vertex_quads[m].size() != 3) return false;
  // The hexagon H around m, counter-clockwise: its quads are (m, H[2i],
  // H[2i+1], H[2i+2]), so H's even corners are m's edge neighbours.
  int H[6], Q[3];
  Q[0] = qm.vertex_quads[m][0];
  for (int i = 0; i < 3; ++i) {
    const Quad A = from_corner(qm, Q[i], m);
    H[2 * i] = A[1];
    H[2 * i + 1] = A[2];
    if (i == 2) {
      if (A[3] != H[0]) return false;  // not a closed star
      break;
    }
    Q[i + 1] = qm.quad_with_edge(m, A[3]);
    if (Q[i + 1] < 0 || Q[i + 1] == Q[0] || from_corner(qm, Q[i + 1], m)[1] != A[3]) return false;
  }
  for (int k = 0; k < 6; ++k)
    for (int l = k + 1; l < 6; ++l)
      if (H[k] == H[l]) return false;
  for (int i = 0; i < 3; ++i) {
    const int c = H[2 * i];
    if (!qm.fixed[c]) continue;
    // c's corner in this region is held by two of m's quads and wants one.
    const Fan f = qm.fan(c, Q[i]);
    if (f.closed || f.count != 2 || f.ideal != 1) continue;
    // The splits not strictly convex as the corners stand, tried last.
    std::vector<std::array<Quad, 2>> later;
    for (int side = 0; side < 2; ++side) {
      // The quad keeping c whole, (H[k-1], c, H[k+1], H[k+2]) or
      // (H[k-2], H[k-1], c, H[k+1]), and the other four corners.
      const int s = 2 * i + 5 + 5 * side;  // the new quad's first corner, k - 1 or k - 2 (mod 6)
      const Quad N1{H[s % 6], H[(s + 1) % 6], H[(s + 2) % 6], H[(s + 3) % 6]};
      const Quad N2{H[(s + 3) % 6], H[(s + 4) % 6], H[(s + 5) % 6], H[s % 6]};
      if (qm.is_feature(N1[0], N1[3]) || qm.quad_with_edge(N1[0], N1[3]) >= 0 || qm.quad_with_edge(N1[3], N1[0]) >= 0)
        continue;
      if (!qm.convex(N1) || !qm.convex(N2)) {
        later.push_back({N1, N2});
        continue;
      }
      Patch pt;
      qm.save_patch({m, H[0], H[1], H[2], H[3], H[4], H[5]}, pt);
      const double before = qm.patch_worst(pt);
      qm.set_quad(Q[0], N1);
      qm.set_quad(Q[1], N2);
      for (int x : qm.quads[Q[2]]) qm.remove_from(x, Q[2]);
      qm.quad_dead[Q[2]] = 1;
      qm.vertex_dead[m] = 1;
      relax(qm, pt);
      if (qm.patch_worst(pt) > before * (1 + 1e-9) + 1e-15) {
        for (int x : pt.verts) qm.wake(x);
        return true;
      }
      qm.rollback(pt);
    }
    if (respoke_too && respoke(qm, m, H, Q, i)) return true;
    for (const auto& N : later)
      if (respoke_too && split_and_merge(qm, m, H, Q, N[0], N[1])) return true;
  }
  return false;
}

bool collapse_and_merge(QuadMesh& qm, int q, int diag, const Accept& accept) {
  const Quad C = qm.quads[q];
  int a = C[diag], c = C[diag + 2];
  const int b = C[diag + 1], d = C[(diag + 3) & 3];
  if (qm.quad_dead[q] || qm.vertex_dead[a] || qm.vertex_dead[c]) return false;
  if (qm.fixed[c]) std::swap(a, c);
  // c free: its edges are no feature, and every quad around it is in q's
  // region; a keeps its place if fixed.
  if (qm.fixed[c]) return false;
  // Link condition (as collapse_quad): no other quad holds both a and c,
  // and a and c share no edge neighbour besides b and d.
  for (int o : qm.vertex_quads[c])
    if (o != q && std::find(qm.quads[o].begin(), qm.quads[o].end(), a) != qm.quads[o].end()) return false;
  std::vector<int> na;
  for (int o : qm.vertex_quads[a]) {
    if (o == q) continue;
    const Quad E = from_corner(qm, o, a);
    na.push_back(E[1]);
    na.push_back(E[3]);
  }
  for (int o : qm.vertex_quads[c]) {
    if (o == q) continue;
    const Quad E = from_corner(qm, o, c);
    for (int x : {E[1], E[3]})
      if (x != b && x != d && std::find(na.begin(), na.end(), x) != na.end()) return false;
  }
  // A fixed b or d must keep a quad.
  if ((qm.fixed[b] && qm.vertex_quads[b].size() < 2) || (qm.fixed[d] && qm.vertex_quads[d].size() < 2)) return false;
  Patch pt;
  qm.save_patch({a, b, c, d}, pt);
  const std::vector<double> before = qm.patch_sines(pt);
  if (!qm.fixed[a]) qm.points[a] = {0.5 * (qm.points[a][0] + qm.points[c][0]), 0.5 * (qm.points[a][1] + qm.points[c][1])};
  for (int x : C) qm.remove_from(x, q);
  qm.quad_dead[q] = 1;
  for (int o : qm.vertex_quads[c]) {
    for (int& x : qm.quads[o])
      if (x == c) x = a;
    qm.vertex_quads[a].push_back(o);
  }
  qm.vertex_quads[c].clear();
  qm.vertex_dead[c] = 1;
  for (int o : qm.vertex_quads[a]) qm.quad_sin_mu[o] = qm.sin_mu_of(qm.quads[o]);
  // b and d lost a quad: free ones left in two merge away.
  bool ok = true;
  for (int x : {b, d})
    if (!qm.fixed[x] && qm.vertex_quads[x].size() == 2) {
      const Quad M = doublet_merged(qm, x);
      if (M[1] == M[3]) { ok = false; break; }
      merge_doublet(qm, x, M);
    }
  for (int x : {a, b, d})
    if (ok && !qm.vertex_dead[x] && qm.vertex_quads[x].size() < (qm.fixed[x] ? 1u : 3u)) ok = false;
  if (ok && settle(qm, pt, before, accept)) return true;
  qm.rollback(pt);
  return false;
}

void final_collapse_pass(QuadMesh& qm, SmoothStats& st) {
  constexpr double kBelow = 0.20791169081775931;  // sin(12 deg), as the max-min climb's
  for (std::size_t q = 0; q < qm.quads.size(); ++q)
    for (int diag = 0; diag < 2; ++diag)
      if (!qm.quad_dead[q] && qm.quad_sin_mu[q] < kBelow && collapse_and_merge(qm, int(q), diag)) {
        ++st.collapses;
        break;
      }
}

void doublet_pass(QuadMesh& qm, SmoothStats& st) {
  const int n = int(qm.points.size());
  for (int v = 0; v < n; ++v)
    if (remove_doublet(qm, v))
      ++st.doublets;
    else if (open_sharp_corner(qm, v, false))
      ++st.sharp_corners;
}

void sharp_corner_pass(QuadMesh& qm, SmoothStats& st) {
  for (int v = 0; v < int(qm.points.size()); ++v)
    if (open_sharp_corner(qm, v, true)) ++st.sharp_corners;
}

} // namespace imgmesh::quadsmooth_detail
