// Doublet removal (Canann, Muthukrishnan and Phillips, 1998): a free vertex
// in only two quads (A = (v, a, b, c), B = (v, c, d, a)) cannot have both
// strictly convex; the two merge into (a, b, c, d) and v goes. Beyond it,
// the same for a free vertex of valence 3 that splits a sharp fixed corner
// (open_sharp_corner).
#include "quad/smooth_mesh.hpp"

#include <algorithm>

namespace imgmesh::qs {

bool remove_doublet(QuadMesh& qm, int v) {
  if (qm.fixed[v] || qm.vertex_dead[v] || qm.vertex_quads[v].size() != 2) return false;
  const int q1 = qm.vertex_quads[v][0], q2 = qm.vertex_quads[v][1];
  Quad A = qm.quads[q1];
  while (A[0] != v) std::rotate(A.begin(), A.begin() + 1, A.end());
  Quad B = qm.quads[q2];
  while (B[0] != v) std::rotate(B.begin(), B.begin() + 1, B.end());
  // A = (v, a, b, c), B = (v, c, d, a).
  if (B[1] != A[3] || B[3] != A[1]) return false;
  const Quad M{A[1], A[2], A[3], B[2]};
  if (M[1] == M[3] || !qm.convex(M) || qm.sin_mu_of(M) < std::min(qm.quad_sin_mu[q1], qm.quad_sin_mu[q2]))
    return false;
  for (int x : B) qm.remove_from(x, q2);
  qm.remove_from(v, q1);
  qm.quad_dead[q2] = 1;
  qm.vertex_dead[v] = 1;
  qm.quads[q1] = M;
  std::vector<int>& star_d = qm.vertex_quads[B[2]];
  if (std::find(star_d.begin(), star_d.end(), q1) == star_d.end()) star_d.push_back(q1);
  qm.quad_sin_mu[q1] = qm.sin_mu_of(M);
  for (int x : M) qm.wake(x);
  return true;
}

bool open_sharp_corner(QuadMesh& qm, int m) {
  if (qm.fixed[m] || qm.vertex_dead[m] || qm.vertex_quads[m].size() != 3) return false;
  // The hexagon H around m, counter-clockwise: its quads are (m, H[2i],
  // H[2i+1], H[2i+2]), so H's even corners are m's edge neighbours.
  int H[6], Q[3];
  const auto rotated = [&](int q) {
    Quad A = qm.quads[q];
    while (A[0] != m) std::rotate(A.begin(), A.begin() + 1, A.end());
    return A;
  };
  Q[0] = qm.vertex_quads[m][0];
  for (int i = 0; i < 3; ++i) {
    const Quad A = rotated(Q[i]);
    H[2 * i] = A[1];
    H[2 * i + 1] = A[2];
    if (i == 2) {
      if (A[3] != H[0]) return false;  // not a closed star
      break;
    }
    Q[i + 1] = qm.quad_with_edge(m, A[3]);
    if (Q[i + 1] < 0 || Q[i + 1] == Q[0] || rotated(Q[i + 1])[1] != A[3]) return false;
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
    for (int side = 0; side < 2; ++side) {
      // The quad keeping c whole, (H[k-1], c, H[k+1], H[k+2]) or
      // (H[k-2], H[k-1], c, H[k+1]), and the other four corners.
      const int s = 2 * i + 5 + 5 * side;  // the new quad's first corner, k - 1 or k - 2 (mod 6)
      const Quad N1{H[s % 6], H[(s + 1) % 6], H[(s + 2) % 6], H[(s + 3) % 6]};
      const Quad N2{H[(s + 3) % 6], H[(s + 4) % 6], H[(s + 5) % 6], H[s % 6]};
      if (!qm.convex(N1) || !qm.convex(N2) || qm.is_feature(N1[0], N1[3]) || qm.quad_with_edge(N1[0], N1[3]) >= 0 ||
          qm.quad_with_edge(N1[3], N1[0]) >= 0)
        continue;
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
  }
  return false;
}

void doublet_pass(QuadMesh& qm, SmoothStats& st) {
  const int n = int(qm.points.size());
  for (int v = 0; v < n; ++v)
    if (remove_doublet(qm, v))
      ++st.doublets;
    else if (open_sharp_corner(qm, v))
      ++st.sharp_corners;
}

} // namespace imgmesh::qs
