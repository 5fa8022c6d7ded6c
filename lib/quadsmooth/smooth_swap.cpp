// Diagonal swaps (Canann, Muthukrishnan and Phillips, 1998): the edge two
// quads share is replaced by one of the other two diagonals of their
// hexagon, for the pair's worst mu or for more regular valences; a poor
// pair no swap helps is split instead (smooth_split.cpp).
#include "quadsmooth/smooth_mesh.hpp"

#include <algorithm>

namespace imgmesh::quadsmooth_detail {

namespace {

// Swaps for the worst mu are tried only where a quad of the pair is below
// sin(30 deg), the usual bar; valence-driven swaps may run anywhere.
constexpr double kSwapBelow = 0.5;

// A plain quad (neither poor nor with a fixed or irregular corner) has
// nothing to gain: most of a fine mesh is skipped before the neighbour is
// even looked up.
bool is_plain(const QuadMesh& qm, int q) {
  if (qm.quad_sin_mu[q] < std::max(kSwapBelow, qm.split_below)) return false;
  for (int x : qm.quads[q])
    if (qm.fixed[x] || qm.vertex_quads[x].size() != 4) return false;
  return true;
}

} // namespace

bool swap_diagonal(QuadMesh& qm, int q1, int i, SmoothStats& st) {
  // The other quad q2 and the hexagon u, c, d, w, a, b. A pair is tried
  // from its first non-plain quad (a pass reaching q1 has tried q2 already
  // if it was).
  int q2, H[6];
  if (!pair_hexagon(qm, q1, i, q2, H) || (q2 < q1 && !is_plain(qm, q2))) return false;
  const int u = H[0], c = H[1], d = H[2], w = H[3], a = H[4], b = H[5];
  // Valence excess of u and w (they lose a quad) and of the ends of
  // either new diagonal (they gain one).
  const Fan fu = qm.fan(u, q1), fw = qm.fan(w, q1);
  const bool keep_valence = fu.count - 1 >= (fu.closed ? 3 : 1) && fw.count - 1 >= (fw.closed ? 3 : 1);
  const int e_uw = 1 - 2 * (fu.count - fu.ideal) + 1 - 2 * (fw.count - fw.ideal);
  const double cur = std::min(qm.quad_sin_mu[q1], qm.quad_sin_mu[q2]);
  const bool poor = cur < kSwapBelow;
  double best = cur * (1 + 1e-9) + 1e-15;
  int best_k = -1, valence_k = -1, best_de = 0;
  for (int k = 1; k <= 2; ++k) {
    const int p = H[k], r = H[(k + 3) % 6];
    const Fan fp = qm.fan(p, q2), fr = qm.fan(r, q1);  // c, d are in B; a, b in A
    const int de = e_uw + 1 + 2 * (fp.count - fp.ideal) + 1 + 2 * (fr.count - fr.ideal);
    const bool fewer_irregular = keep_valence && de < best_de;
    if (!poor && !fewer_irregular) continue;  // most pairs of a fine mesh stop here
    const Quad N1{H[k], H[k + 1], H[k + 2], H[(k + 3) % 6]};
    const Quad N2{H[(k + 3) % 6], H[(k + 4) % 6], H[(k + 5) % 6], H[k]};
    if (!qm.convex(N1) || !qm.convex(N2) || qm.is_feature(p, r) || qm.quad_with_edge(p, r) >= 0 ||
        qm.quad_with_edge(r, p) >= 0)
      continue;  // the new diagonal must not already be an edge
    if (fewer_irregular) { best_de = de; valence_k = k; }
    const double sm = std::min(qm.sin_mu_of(N1), qm.sin_mu_of(N2));
    if (poor && sm > best) { best = sm; best_k = k; }
  }
  auto apply = [&](int k) {
    qm.set_quad(q1, {H[k], H[k + 1], H[k + 2], H[(k + 3) % 6]});
    qm.set_quad(q2, {H[(k + 3) % 6], H[(k + 4) % 6], H[(k + 5) % 6], H[k]});
  };
  if (best_k >= 0) {
    apply(best_k);  // the pair's worst mu improves: nothing else changes
  } else if (const int parts = cur < qm.split_below && !qm.tried[q1] ? split_pair(qm, q1, q2, H) : 0) {
    ++st.splits;
    st.splits_four += parts == 4;
    return true;
  } else if (valence_k >= 0) {
    // Fewer irregular vertices: taken if, after relaxing the patch, its
    // worst mu has not dropped.
    Patch pt;
    qm.save_patch({u, w, a, b, c, d}, pt);
    const double before = qm.patch_worst(pt);
    apply(valence_k);
    relax(qm, pt);
    if (qm.patch_worst(pt) < before) { qm.rollback(pt); return false; }
    for (int x : pt.verts) qm.wake(x);
    ++st.valence_swaps;
  } else {
    return false;
  }
  for (int x : H) qm.wake(x);
  ++st.swaps;
  return true;
}

void swap_pass(QuadMesh& qm, SmoothStats& st) {
  for (std::size_t q1 = 0; q1 < qm.quads.size(); ++q1) {
    if (qm.quad_dead[q1] || is_plain(qm, int(q1))) continue;
    bool changed = false;
    for (int i = 0; i < 4 && !changed; ++i) changed = swap_diagonal(qm, int(q1), i, st);
    if (!changed && qm.quad_sin_mu[q1] < qm.split_below) qm.tried[q1] = 1;
  }
}

} // namespace imgmesh::quadsmooth_detail
