// Doublet removal (Canann, Muthukrishnan and Phillips, 1998): a free vertex
// in only two quads (A = (v, a, b, c), B = (v, c, d, a)) cannot have both
// strictly convex; the two merge into (a, b, c, d) and v goes.
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

void doublet_pass(QuadMesh& qm, SmoothStats& st) {
  const int n = int(qm.points.size());
  for (int v = 0; v < n; ++v)
    if (remove_doublet(qm, v)) ++st.doublets;
}

} // namespace imgmesh::qs
