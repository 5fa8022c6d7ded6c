// quadsmooth's grading pass (see grading_pass in smooth_mesh.hpp).
#include "quadsmooth/smooth_mesh.hpp"

#include <algorithm>
#include <cmath>
#include <utility>

namespace imgmesh::quadsmooth_detail {

namespace {

// The bar on the worst quad: the pass trades mu for grading down
// to it, never below.
constexpr double kFloor = 0.17364817766693033;  // sin(10 deg)
constexpr int kRounds = 4;

double quad_size(const std::vector<Point2>& P, const Quad& q) {
  double a = 0;
  for (int k = 0; k < 4; ++k) {
    const Point2 &p = P[q[k]], &r = P[q[(k + 1) & 3]];
    a += p[0] * r[1] - r[0] * p[1];
  }
  return std::sqrt(std::fabs(a) / 2);
}

// Whether q is the smaller quad of a pair at its grading ratio r.
bool smaller_of_worst(const QuadMesh& qm, int q, double r) {
  const Quad& Qd = qm.quads[q];
  const double s = quad_size(qm.points, Qd);
  for (int k = 0; k < 4; ++k) {
    const int o = qm.quad_with_edge(Qd[(k + 1) & 3], Qd[k]);
    if (o >= 0 && quad_size(qm.points, qm.quads[o]) >= s * r * (1 - 1e-9)) return true;
  }
  return false;
}

} // namespace

double grading_ratio(const QuadMesh& qm, int q) {
  const Quad& Qd = qm.quads[q];
  const double s = quad_size(qm.points, Qd);
  double worst = 1;
  for (int k = 0; k < 4; ++k) {
    const int o = qm.quad_with_edge(Qd[(k + 1) & 3], Qd[k]);
    if (o < 0) continue;
    const double t = quad_size(qm.points, qm.quads[o]);
    worst = std::max(worst, std::max(s / t, t / s));
  }
  return worst;
}

void grading_pass(QuadMesh& qm, SmoothStats& st, double target) {
  const std::vector<Point2>& P = qm.points;
  // Nor under the input's worst mu, which quadsmooth never lowers.
  const double floor_all = std::max(kFloor, std::sin(st.before.min_mu * (3.14159265358979323846 / 180)));
  for (int round = 0; round < kRounds; ++round) {
    std::size_t done = 0;
    for (int q = 0; q < int(qm.quads.size()); ++q) {
      if (qm.quad_dead[q] || grading_ratio(qm, q) <= target) continue;
      const Quad Qd = qm.quads[q];
      for (int k = 0; k < 4; ++k) {
        const int v = Qd[k];
        if (qm.fixed[v] || qm.vertex_dead[v] || qm.vertex_quads[v].size() < 3) continue;
        const Point2& x = P[Qd[(k + 1) & 3]];
        const double h2 = (x[0] - P[v][0]) * (x[0] - P[v][0]) + (x[1] - P[v][1]) * (x[1] - P[v][1]);
        if (raise_grading(qm, v, h2, target, floor_all)) ++st.grading_moves, ++done;
      }
    }
    // Where moves cannot: the worst pairs first, the smaller quad collapsed
    // or the larger split with a neighbour.
    std::vector<std::pair<double, int>> bad;
    for (int q = 0; q < int(qm.quads.size()); ++q)
      if (!qm.quad_dead[q]) {
        const double r = grading_ratio(qm, q);
        if (r > target) bad.push_back({r, q});
      }
    std::sort(bad.rbegin(), bad.rend());
    for (const auto& [ratio, q] : bad) {
      if (qm.quad_dead[q]) continue;
      const double r0 = grading_ratio(qm, q);
      if (!(r0 > target)) continue;
      // Every quad of the patch under r0 (so the largest ratio only falls)
      // and none under the floor or the patch's worst before.
      const Accept accept = [&](const Patch& pt, const std::vector<double>& before) {
        const double floor = std::min(before.empty() ? floor_all : before[0], floor_all);
        for (int o : pt.quads)
          if (!qm.quad_dead[o] && (qm.quad_sin_mu[o] < floor || grading_ratio(qm, o) >= r0 * (1 - 1e-9)))
            return false;
        return true;
      };
      if (smaller_of_worst(qm, q, r0)) {
        for (int diag = 0; diag < 2; ++diag)
          if (collapse_and_merge(qm, q, diag, accept)) {
            ++st.grading_collapses, ++done;
            break;
          }
      } else {
        for (int i = 0; i < 4 && !qm.quad_dead[q]; ++i) {
          int q2, H[6];
          if (!pair_hexagon(qm, q, i, q2, H)) continue;
          if (split_pair(qm, q, q2, H, accept)) {
            ++st.grading_splits, ++done;
            break;
          }
        }
      }
    }
    if (!done) break;
  }
}

} // namespace imgmesh::quadsmooth_detail
