// Pair splits: two poor quads sharing an edge become three quads around a
// new point, or four around two (the clean-up of thesis 3.2.3; tried by
// smooth_swap.cpp where no diagonal swap helps). Each try is a Patch, put
// back exactly when it fails.
#include "quadsmooth/smooth_mesh.hpp"

#include <algorithm>

namespace imgmesh::quadsmooth_detail {

int split_pair(QuadMesh& qm, int q1, int q2, const int (&H)[6], const Accept& accept) {
  const std::vector<Point2>& P = qm.points;
  // Hexagon H (the pair's union) split around new points. With one point e
  // joined to alternate corners H[s], H[s+2], H[s+4]: three quads, each of
  // those corners gets a quad more, which is what a flat corner of a poor
  // quad needs. Where two opposite corners H[k], H[k+3] are both flat, two
  // points e1, e2 (e1 joined to H[k], H[k+2], e2 to H[k+3], H[k+5]): four
  // quads. Taken, the first that works, if once the patch is relaxed the new
  // quads are better than the pair's worst and the patch's sorted mu rises.
  Patch pt;
  auto at = [&](int i) { return H[i % 6]; };
  auto mean = [&](std::initializer_list<int> ids) {
    Point2 c{0, 0};
    for (int i : ids) { c[0] += P[at(i)][0] / double(ids.size()); c[1] += P[at(i)][1] / double(ids.size()); }
    return c;
  };
  const double worst_pair = std::min(qm.quad_sin_mu[q1], qm.quad_sin_mu[q2]);
  for (int variant = 0; variant < 5; ++variant) {
    qm.save_patch({H[0], H[1], H[2], H[3], H[4], H[5]}, pt);
    const std::vector<double> before = qm.patch_sines(pt);
    const bool three = variant < 2;
    const int k = three ? variant : variant - 2;
    const int e1 = qm.add_vertex(three ? mean({0, 1, 2, 3, 4, 5}) : mean({0, 1, 2, 3, 4, 5, k, k + 2}));
    const int e2 = three ? -1 : qm.add_vertex(mean({0, 1, 2, 3, 4, 5, k + 3, k + 5}));
    pt.verts.push_back(e1);  // relaxed with the patch, dropped by rollback
    if (!three) pt.verts.push_back(e2);
    const int q3 = qm.add_quad(q1), q4 = three ? -1 : qm.add_quad(q1);
    pt.quads.push_back(q3);
    if (!three) pt.quads.push_back(q4);
    if (three) {
      qm.set_quad(q1, {at(k), at(k + 1), at(k + 2), e1});
      qm.set_quad(q2, {at(k + 2), at(k + 3), at(k + 4), e1});
      qm.set_quad(q3, {at(k + 4), at(k + 5), at(k), e1});
    } else {
      qm.set_quad(q1, {at(k), at(k + 1), at(k + 2), e1});
      qm.set_quad(q2, {at(k + 2), at(k + 3), e2, e1});
      qm.set_quad(q3, {at(k + 3), at(k + 4), at(k + 5), e2});
      qm.set_quad(q4, {at(k + 5), at(k), e1, e2});
    }
    bool ok = qm.convex(qm.quads[q1]) && qm.convex(qm.quads[q2]) && qm.convex(qm.quads[q3]) &&
              (three || qm.convex(qm.quads[q4]));
    if (ok) {
      // Relaxed by the angle-based moves alone: the compass search here was
      // 70-80% of quadsmooth's time at --split-below 25 (brain slice, default
      // chain: 16 s against 4), and without it the splits taken are the ones
      // that stay good, for fewer quads and a higher mean mu.
      const bool climb = qm.climb;
      qm.climb = false;
      relax(qm, pt);
      qm.climb = climb;
      double worst_new = std::min(std::min(qm.quad_sin_mu[q1], qm.quad_sin_mu[q2]), qm.quad_sin_mu[q3]);
      if (!three) worst_new = std::min(worst_new, qm.quad_sin_mu[q4]);
      ok = accept ? accept(pt, before)
                  : worst_new > worst_pair * (1 + 1e-9) + 1e-15 && lex_better(qm.patch_sines(pt), before);
    }
    if (ok) {
      for (int x : pt.verts) qm.wake(x);
      return three ? 3 : 4;
    }
    qm.rollback(pt);
  }
  return 0;
}

bool pair_hexagon(const QuadMesh& qm, int q1, int i, int& q2, int (&H)[6]) {
  const Quad A = qm.quads[q1];
  const int u = A[i], w = A[(i + 1) & 3];
  q2 = qm.is_feature(u, w) ? -1 : qm.quad_with_edge(w, u);
  if (q2 < 0) return false;
  const Quad B = qm.quads[q2];
  int j = 0;
  while (B[j] != w) ++j;
  const int h[6] = {u, B[(j + 2) & 3], B[(j + 3) & 3], w, A[(i + 2) & 3], A[(i + 3) & 3]};
  for (int x = 0; x < 6; ++x) {
    H[x] = h[x];
    for (int y = 0; y < x; ++y)
      if (h[x] == h[y]) return false;
  }
  return true;
}

void final_split_pass(QuadMesh& qm, SmoothStats& st) {
  // sin(10 deg), the bar: with a settled split (placed, relaxed,
  // climbed) on quads under 12 degrees random blob 2's mean mu fell under
  // 30 (29.90).
  constexpr double kBelow = 0.17364817766693033;
  const std::size_t n = qm.quads.size();  // the quads a split adds are not tried again
  for (std::size_t q1 = 0; q1 < n; ++q1)
    for (int i = 0; i < 4 && !qm.quad_dead[q1] && qm.quad_sin_mu[q1] < kBelow; ++i) {
      int q2, H[6];
      if (!pair_hexagon(qm, int(q1), i, q2, H)) continue;
      if (const int parts = split_pair(qm, int(q1), q2, H)) {
        ++st.splits;
        if (parts == 4) ++st.splits_four;
      }
    }
}

} // namespace imgmesh::quadsmooth_detail
