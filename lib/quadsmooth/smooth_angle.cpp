// Angle-based smoothing (Zhou and Shimada, 2000) with a guard, the compass
// search on the worst mu around a vertex or an edge, and the colouring that
// lets one pass run on several threads with a result that does not depend
// on their number (thesis 3.2.3).
#include "quadsmooth/smooth_mesh.hpp"

#include <algorithm>
#include <cmath>
#include <functional>
#include <thread>

namespace imgmesh::quadsmooth_detail {

namespace {

// Vertices next to a quad with mu below 25 degrees also get a compass search
// on the soft minimum of mu around them.
constexpr double kOptimizeBelow = 0.42261826174069944;  // sin(25 deg)
constexpr int kOptimizeRounds = 6;
constexpr int kWorstRounds = 24;
constexpr double kWorstBelow = 0.20791169081775934;  // sin(12 deg)
constexpr std::size_t kStarCache = 16;  // quads around a vertex whose sines try_move keeps aside
// Only moves of over 3% of an edge put the neighbours back on the smoothing
// work list: the smaller ones barely change their targets, and waking for
// them cost a third more time on 10^6 quads for 0.4 degrees of mean mu.
constexpr double kWakeFar = 1e-3;

} // namespace

bool angle_based_target(const QuadMesh& qm, int v, Point2& out) {
  const std::vector<Point2>& P = qm.points;
  // Star of v: for each quad (v, x, y, z), the edge neighbour x sees the
  // opposite corner y on one side, z sees y on the other. Zhou-Shimada
  // rotate v about each edge neighbour onto the bisector of the star's angle
  // there, then average.
  struct Nb { int x; int y1 = -1, y2 = -1; };
  Nb nb[16];
  int k = 0;
  auto slot = [&](int x) -> Nb* {
    for (int i = 0; i < k; ++i)
      if (nb[i].x == x) return &nb[i];
    if (k == 16) return nullptr;
    nb[k].x = x; nb[k].y1 = nb[k].y2 = -1;
    return &nb[k++];
  };
  for (int q : qm.vertex_quads[v]) {
    const Quad& Qd = qm.quads[q];
    int i = 0;
    while (Qd[i] != v) ++i;
    const int x = Qd[(i + 1) & 3], y = Qd[(i + 2) & 3], z = Qd[(i + 3) & 3];
    Nb* sx = slot(x);
    Nb* sz = slot(z);
    if (!sx || !sz) return false;
    sx->y1 = y;
    sz->y2 = y;
  }
  double sx = 0, sy = 0;
  int cnt = 0;
  const Point2& pv = P[v];
  for (int i = 0; i < k; ++i) {
    if (nb[i].y1 < 0 || nb[i].y2 < 0) return false;  // open star: not interior
    const Point2& px = P[nb[i].x];
    const double vx = pv[0] - px[0], vy = pv[1] - px[1];
    const double len = std::sqrt(vx * vx + vy * vy);
    double ax = P[nb[i].y1][0] - px[0], ay = P[nb[i].y1][1] - px[1];
    double bx = P[nb[i].y2][0] - px[0], by = P[nb[i].y2][1] - px[1];
    const double la = std::sqrt(ax * ax + ay * ay), lb = std::sqrt(bx * bx + by * by);
    if (!(la > 0 && lb > 0 && len > 0)) return false;
    ax /= la; ay /= la; bx /= lb; by /= lb;
    // Bisector of the angle between a and b that contains v.
    double cx = ax + bx, cy = ay + by;
    const double cl = std::sqrt(cx * cx + cy * cy);
    if (cl < 1e-12) {  // a and b opposite: the bisector is perpendicular
      cx = -ay; cy = ax;
      if (cx * vx + cy * vy < 0) { cx = -cx; cy = -cy; }
    } else {
      cx /= cl; cy /= cl;
      const double cab = ax * by - ay * bx;
      const double c1 = ax * vy - ay * vx, c2 = vx * by - vy * bx;
      const bool in_small = cab >= 0 ? (c1 >= 0 && c2 >= 0) : (c1 <= 0 && c2 <= 0);
      if (!in_small) { cx = -cx; cy = -cy; }
    }
    sx += px[0] + len * cx;
    sy += px[1] + len * cy;
    ++cnt;
  }
  if (cnt == 0) return false;
  out = {sx / cnt, sy / cnt};
  return std::isfinite(out[0]) && std::isfinite(out[1]);
}

bool try_move(QuadMesh& qm, int v, Point2 p, bool slide_line, const Slide* s) {
  std::vector<Point2>& P = qm.points;
  const Point2 old = P[v];
  double worst_old = 2;
  for (int q : qm.vertex_quads[v]) worst_old = std::min(worst_old, qm.quad_sin_mu[q]);
  double t = 1;
  for (int attempt = 0; attempt < 2; ++attempt, t *= 0.5) {
    Point2 c{old[0] + t * (p[0] - old[0]), old[1] + t * (p[1] - old[1])};
    if (slide_line) {
      // Recompute on the line through the fixed chain ends A and B.
      const Point2 &A = P[s->A], &B = P[s->B];
      const double dx = B[0] - A[0], dy = B[1] - A[1];
      const double tt = ((c[0] - A[0]) * dx + (c[1] - A[1]) * dy) / (dx * dx + dy * dy);
      c = {A[0] + tt * dx, A[1] + tt * dy};
      if (dx == 0) c[0] = A[0];  // axis-parallel segments stay exact
      if (dy == 0) c[1] = A[1];
    }
    if (c == old) return false;
    P[v] = c;
    // New sines kept aside, written only if every quad passes.
    double smu[kStarCache];
    const std::size_t k = qm.vertex_quads[v].size();
    bool ok = true;
    // The mu guard first: it refuses most rejected moves, and costs less
    // than the sixteen orientation tests of the star.
    for (std::size_t i = 0; i < k && ok; ++i) {
      const Quad& Qd = qm.quads[qm.vertex_quads[v][i]];
      const double sq = qm.sin_mu_of(Qd);
      if (sq < worst_old || !qm.convex(Qd)) ok = false;
      if (i < kStarCache) smu[i] = sq;
    }
    if (ok) {
      for (std::size_t i = 0; i < k; ++i) {
        const int q = qm.vertex_quads[v][i];
        qm.quad_sin_mu[q] = i < kStarCache ? smu[i] : qm.sin_mu_of(qm.quads[q]);
      }
      return true;
    }
    P[v] = old;
  }
  return false;
}

namespace {

// The compass search's eight directions, polled in this order.
constexpr double kCompass[8][2] = {{1, 0}, {0.7071067811865476, 0.7071067811865476}, {0, 1},
                                   {-0.7071067811865476, 0.7071067811865476}, {-1, 0},
                                   {-0.7071067811865476, -0.7071067811865476}, {0, -1},
                                   {0.7071067811865476, -0.7071067811865476}};

// The energy sum 1/sin(mu) of the quads qs (a soft minimum); false if a
// quad is not strictly convex or below floor, or the energy reaches cap.
bool guarded_energy(const QuadMesh& qm, const std::vector<int>& qs, double floor, double cap, double& energy) {
  energy = 0;
  for (int q : qs) {
    const double s = qm.sin_mu_of(qm.quads[q]);
    if (s < floor) return false;
    energy += 1 / s;
    if (energy >= cap) return false;
  }
  // Convexity last: most candidate points fail on the energy already.
  for (int q : qs)
    if (!qm.convex(qm.quads[q])) return false;
  return true;
}

// The compass search of the climbs below, on a point s from s0 (a vertex's
// place, or the displacement of an edge's two ends): the eight directions
// at step h polled from the last one that gained (opportunistic);
// place(c) puts the moving vertices at candidate c, gains() judges them
// there (keeping its new best if so); a round without a gain halves h.
// Returns the last s that gained, the vertices placed at it.
template <class Place, class Gains>
Point2 compass_search(Point2 s, double h, int rounds, Place place, Gains gains) {
  int first = 0;
  for (int round = 0; round < rounds; ++round) {
    bool improved = false;
    for (int k = 0; k < 8 && !improved; ++k) {
      const int d = (first + k) & 7;
      const Point2 c{s[0] + h * kCompass[d][0], s[1] + h * kCompass[d][1]};
      place(c);
      if (gains()) { s = c; first = d; improved = true; }
    }
    place(s);
    if (!improved) h *= 0.5;
  }
  return s;
}

} // namespace

bool optimize_star(QuadMesh& qm, int v, double h2) {
  std::vector<Point2>& P = qm.points;
  double worst0 = 2, energy0 = 0;
  for (int q : qm.vertex_quads[v]) {
    worst0 = std::min(worst0, qm.quad_sin_mu[q]);
    energy0 += 1 / qm.quad_sin_mu[q];
  }
  if (worst0 >= kOptimizeBelow || !(worst0 > 0)) return false;
  const Point2 start = P[v];
  double best = energy0;
  compass_search(start, 0.25 * std::sqrt(h2), kOptimizeRounds, [&](const Point2& c) { P[v] = c; }, [&] {
    double e;
    if (!guarded_energy(qm, qm.vertex_quads[v], worst0, best * (1 - 1e-12), e)) return false;
    best = e;
    return true;
  });
  if (!(best < energy0 * (1 - 1e-9))) { P[v] = start; return false; }
  for (int q : qm.vertex_quads[v]) qm.quad_sin_mu[q] = qm.sin_mu_of(qm.quads[q]);
  return true;
}

bool raise_mean(QuadMesh& qm, int v, double h2, double grading) {
  std::vector<Point2>& P = qm.points;
  const std::vector<int>& qs = qm.vertex_quads[v];
  const auto ratio = [&] {
    double r = 1;
    for (int q : qs) r = std::max(r, grading_ratio(qm, q));
    return r;
  };
  const double ratio_cap = grading > 0 ? std::max(grading, ratio()) : 0;  // 0: no cap
  double worst0 = 2, sum0 = 0;
  for (int q : qs) {
    worst0 = std::min(worst0, qm.quad_sin_mu[q]);
    sum0 += qm.quad_sin_mu[q];
  }
  if (!(worst0 > 0)) return false;
  const Point2 start = P[v];
  double best = sum0;
  compass_search(start, 0.125 * std::sqrt(h2), kOptimizeRounds, [&](const Point2& c) { P[v] = c; }, [&] {
    // sin(mu) is concave on [0, 45] degrees: its sum also evens the quads out.
    double sum = 0;
    for (int q : qs) {
      const double sq = qm.sin_mu_of(qm.quads[q]);
      if (sq < worst0) return false;
      sum += sq;
    }
    if (!(sum > best * (1 + 1e-12))) return false;
    for (int q : qs)
      if (!qm.convex(qm.quads[q])) return false;
    if (ratio_cap > 0 && ratio() > ratio_cap) return false;
    best = sum;
    return true;
  });
  if (!(best > sum0 * (1 + 1e-9))) { P[v] = start; return false; }
  for (int q : qs) qm.quad_sin_mu[q] = qm.sin_mu_of(qm.quads[q]);
  return true;
}

// climb(v, h2) on each free vertex of three or more quads, one of them with
// sin mu under `below`, vertex by vertex in id order (Gauss-Seidel, one
// thread: the result cannot depend on --threads); h2 is the squared length
// of v's first edge, the climb's scale. The climbs that moved v.
template <class Climb>
std::size_t climb_stars_below(QuadMesh& qm, double below, Climb climb) {
  const std::vector<Point2>& P = qm.points;
  std::size_t moved = 0;
  for (int v = 0; v < int(P.size()); ++v) {
    if (qm.fixed[v] || qm.vertex_dead[v] || qm.vertex_quads[v].size() < 3) continue;
    double worst = 2;
    for (int q : qm.vertex_quads[v]) worst = std::min(worst, qm.quad_sin_mu[q]);
    if (worst >= below) continue;
    const Quad& first = qm.quads[qm.vertex_quads[v][0]];
    const Point2& x = P[first[0] == v ? first[1] : first[0]];
    const double h2 = (x[0] - P[v][0]) * (x[0] - P[v][0]) + (x[1] - P[v][1]) * (x[1] - P[v][1]);
    if (climb(v, h2)) ++moved;
  }
  return moved;
}

void mean_pass(QuadMesh& qm, SmoothStats& st, double grading) {
  // Stars whose quads are all near squares (mu >= 40) are left alone, which
  // keeps the pass cheap on good meshes.
  constexpr double kGood = 0.6427876096865393;  // sin(40 deg)
  st.mean_climbs += climb_stars_below(qm, kGood, [&](int v, double h2) { return raise_mean(qm, v, h2, grading); });
}

bool raise_worst(QuadMesh& qm, int v, double h2) {
  std::vector<Point2>& P = qm.points;
  const std::vector<int>& qs = qm.vertex_quads[v];
  // The two smallest sines around v, the first compared first: a max-min
  // on mu itself, where optimize_star's energy may trade the worst quad
  // for the others.
  auto worst_two = [&](double& a, double& b, bool cached) {
    a = b = 2;
    for (int q : qs) {
      const double s = cached ? qm.quad_sin_mu[q] : qm.sin_mu_of(qm.quads[q]);
      if (s < a) { b = a; a = s; } else if (s < b) b = s;
    }
  };
  double a0, b0;
  worst_two(a0, b0, true);
  if (!(a0 > 0)) return false;
  const Point2 start = P[v];
  double ba = a0, bb = b0;
  compass_search(start, 0.125 * std::sqrt(h2), kWorstRounds, [&](const Point2& c) { P[v] = c; }, [&] {
    double a, b;
    worst_two(a, b, false);
    if (!(a > ba * (1 + 1e-12) || (a >= ba && b > bb * (1 + 1e-12)))) return false;
    for (int q : qs)
      if (!qm.convex(qm.quads[q])) return false;
    ba = a;
    bb = b;
    return true;
  });
  if (P[v] == start) return false;
  for (int q : qs) qm.quad_sin_mu[q] = qm.sin_mu_of(qm.quads[q]);
  return true;
}

bool raise_worst_pair(QuadMesh& qm, int u, int v, double h) {
  std::vector<Point2>& P = qm.points;
  std::vector<int> qs = qm.vertex_quads[u];
  for (int q : qm.vertex_quads[v])
    if (std::find(qs.begin(), qs.end(), q) == qs.end()) qs.push_back(q);
  auto worst_two = [&](double& a, double& b) {
    a = b = 2;
    for (int q : qs) {
      const double s = qm.sin_mu_of(qm.quads[q]);
      if (s < a) { b = a; a = s; } else if (s < b) b = s;
    }
  };
  const Point2 su = P[u], sv = P[v];
  double ba, bb;
  worst_two(ba, bb);
  if (!(ba > 0)) return false;
  // u and v together, apart, or one alone: a kite's two free corners
  // move as one where one at a time each lowers the other's quad.
  constexpr double kMode[4][2] = {{1, 1}, {1, -1}, {1, 0}, {0, 1}};
  Point2 du{0, 0}, dv{0, 0};
  bool moved = false;
  for (int round = 0; round < kWorstRounds; ++round) {
    bool improved = false;
    for (int k = 0; k < 32 && !improved; ++k) {
      const double* d = kCompass[k & 7];
      const double mu_ = kMode[k >> 3][0], mv = kMode[k >> 3][1];
      const Point2 cu{du[0] + h * mu_ * d[0], du[1] + h * mu_ * d[1]}, cv{dv[0] + h * mv * d[0], dv[1] + h * mv * d[1]};
      P[u] = {su[0] + cu[0], su[1] + cu[1]};
      P[v] = {sv[0] + cv[0], sv[1] + cv[1]};
      double a, b;
      worst_two(a, b);
      if (!(a > ba * (1 + 1e-12) || (a >= ba && b > bb * (1 + 1e-12)))) continue;
      bool convex = true;
      for (int q : qs) convex = convex && qm.convex(qm.quads[q]);
      if (!convex) continue;
      ba = a; bb = b; du = cu; dv = cv; improved = moved = true;
    }
    P[u] = {su[0] + du[0], su[1] + du[1]};
    P[v] = {sv[0] + dv[0], sv[1] + dv[1]};
    if (!improved) h *= 0.5;
  }
  for (int q : qs) qm.quad_sin_mu[q] = qm.sin_mu_of(qm.quads[q]);
  return moved;
}

void worst_pass(QuadMesh& qm, SmoothStats& st) {
  const std::vector<Point2>& P = qm.points;
  st.worst_climbs += climb_stars_below(qm, kWorstBelow, [&](int v, double h2) { return raise_worst(qm, v, h2); });
  for (int q = 0; q < int(qm.quads.size()); ++q) {
    if (qm.quad_dead[q] || qm.quad_sin_mu[q] >= kWorstBelow) continue;
    for (int k = 0; k < 4; ++k) {
      const int u = qm.quads[q][k], v = qm.quads[q][(k + 1) & 3];
      if (qm.fixed[u] || qm.fixed[v]) continue;
      const double h = 0.125 * std::hypot(P[u][0] - P[v][0], P[u][1] - P[v][1]);
      if (raise_worst_pair(qm, u, v, h)) ++st.worst_climbs;
    }
  }
}

bool optimize_edge(QuadMesh& qm, int u, int v, double h) {
  std::vector<Point2>& P = qm.points;
  std::vector<int> qs = qm.vertex_quads[u];
  for (int q : qm.vertex_quads[v])
    if (std::find(qs.begin(), qs.end(), q) == qs.end()) qs.push_back(q);
  double worst0 = 2, energy0 = 0;
  for (int q : qs) {
    worst0 = std::min(worst0, qm.quad_sin_mu[q]);
    energy0 += 1 / qm.quad_sin_mu[q];
  }
  if (worst0 >= kOptimizeBelow || !(worst0 > 0)) return false;
  const Point2 su = P[u], sv = P[v];
  double best = energy0;
  compass_search(Point2{0, 0}, h, 2 * kOptimizeRounds,
                 [&](const Point2& d) {  // the displacement of both ends
                   P[u] = {su[0] + d[0], su[1] + d[1]};
                   P[v] = {sv[0] + d[0], sv[1] + d[1]};
                 },
                 [&] {
                   double e;
                   if (!guarded_energy(qm, qs, worst0, best * (1 - 1e-12), e)) return false;
                   best = e;
                   return true;
                 });
  if (!(best < energy0 * (1 - 1e-9))) {
    P[u] = su;
    P[v] = sv;
    return false;
  }
  for (int q : qs) qm.quad_sin_mu[q] = qm.sin_mu_of(qm.quads[q]);
  return true;
}

void edge_pass(QuadMesh& qm, SmoothStats& st) {
  const std::vector<Point2>& P = qm.points;
  // A poor quad whose two free corners lie almost on its opposite, fixed
  // side (a sliver along a segment) cannot be opened one corner at a time:
  // moving either away from the segment makes the other reflex. Moved
  // together, they can. Only such flat pairs: edge moves anywhere else
  // gained little and, on the brain with --slide-boundary, steered the
  // clean-up into a worse end (min mu 2.6 instead of 9).
  for (int q = 0; q < int(qm.quads.size()); ++q) {
    if (qm.quad_dead[q] || qm.quad_sin_mu[q] >= kOptimizeBelow) continue;
    const Quad& Qd = qm.quads[q];
    double side2 = 0;
    for (int k = 0; k < 4; ++k) {
      const Point2 &a = P[Qd[k]], &b = P[Qd[(k + 1) & 3]];
      side2 = std::max(side2, (a[0] - b[0]) * (a[0] - b[0]) + (a[1] - b[1]) * (a[1] - b[1]));
    }
    // Flat: the corner's cosine below -0.7 (over 134 degrees).
    auto flat = [&](int k) {
      const Point2 &o = P[Qd[k]], &a = P[Qd[(k + 1) & 3]], &b = P[Qd[(k + 3) & 3]];
      const double ux = a[0] - o[0], uy = a[1] - o[1], vx = b[0] - o[0], vy = b[1] - o[1];
      return ux * vx + uy * vy < -0.7 * std::sqrt((ux * ux + uy * uy) * (vx * vx + vy * vy));
    };
    for (int k = 0; k < 4 && qm.quad_sin_mu[q] < kOptimizeBelow; ++k) {
      const int u = Qd[k], v = Qd[(k + 1) & 3];
      if (qm.fixed[u] || qm.fixed[v] || !flat(k) || !flat((k + 1) & 3) ||
          !optimize_edge(qm, u, v, 0.25 * std::sqrt(side2)))
        continue;
      ++st.edge_moves;
      qm.wake(u);
      qm.wake(v);
    }
  }
}

int smooth_vertex(QuadMesh& qm, int v) {
  const std::vector<Point2>& P = qm.points;
  Point2 target;
  if (!angle_based_target(qm, v, target)) return 0;
  const Point2& p = P[v];
  const Quad& first = qm.quads[qm.vertex_quads[v][0]];
  const Point2& x = P[first[0] == v ? first[1] : first[0]];
  const double d2 = (target[0] - p[0]) * (target[0] - p[0]) + (target[1] - p[1]) * (target[1] - p[1]);
  const double h2 = (x[0] - p[0]) * (x[0] - p[0]) + (x[1] - p[1]) * (x[1] - p[1]);
  int r = 0;
  // Closer than 1e-2 of an edge: converged.
  if (d2 >= 1e-4 * h2) r = try_move(qm, v, target, false, nullptr) ? kMoved : kRejected;
  if ((r & kMoved) && d2 >= kWakeFar * h2) r |= kFar;
  // Where the angle-based position cannot help a poor quad, climb on the
  // soft minimum of mu itself (compass search, guarded the same way).
  if (qm.climb && optimize_star(qm, v, h2)) r |= kOptimized;
  return r;
}

void colour(const QuadMesh& qm, Colouring& colouring) {
  const std::vector<Point2>& P = qm.points;
  // Greedy colouring of the vertices that smooth: two that share a quad
  // get different colours, so the vertices of one colour move
  // independently (each writes only its own position and its own star's
  // sines) and a colour's result does not depend on the thread count.
  const int n = int(P.size());
  std::vector<int> col(n, -1), seen;
  colouring.classes.clear();
  for (int v = 0; v < n; ++v) {
    if (qm.fixed[v] || qm.vertex_dead[v] || qm.vertex_quads[v].size() < 3) continue;
    for (int q : qm.vertex_quads[v])
      for (int w : qm.quads[q])
        if (col[w] >= 0) {
          if (int(seen.size()) <= col[w]) seen.resize(col[w] + 1, -1);
          seen[col[w]] = v;
        }
    int c = 0;
    while (c < int(seen.size()) && seen[c] == v) ++c;
    col[v] = c;
    if (int(colouring.classes.size()) <= c) colouring.classes.resize(c + 1);
    colouring.classes[c].push_back(v);
  }
}

void smooth_pass(QuadMesh& qm, Colouring& colouring, int thread_count, SmoothStats& st) {
  // Active set: a vertex is revisited only after something around it moved
  // (a rejected or negligible move would be rejected or negligible again).
  // Colour by colour, split over the threads; each thread keeps its own
  // counts and the vertices it woke up, applied after the colour.
  if (colouring.stale) { colour(qm, colouring); colouring.stale = false; }
  const int threads = std::max(1, thread_count);
  struct Local { std::size_t moves = 0, rejected = 0, optimized = 0; std::vector<int> woken; };
  std::vector<Local> local(threads);
  for (const std::vector<int>& vs : colouring.classes) {
    auto work = [&](std::size_t begin, std::size_t end, Local& l) {
      for (std::size_t i = begin; i < end; ++i) {
        const int v = vs[i];
        if (!qm.active[v]) continue;
        qm.active[v] = 0;
        const int r = smooth_vertex(qm, v);
        l.moves += (r & kMoved) != 0;
        l.rejected += (r & kRejected) != 0;
        l.optimized += (r & kOptimized) != 0;
        if (r & (kFar | kOptimized))
          for (int q : qm.vertex_quads[v])
            for (int w : qm.quads[q]) l.woken.push_back(w);
      }
    };
    // Small colours are not worth a thread.
    const int t_used = vs.size() < 4096 ? 1 : threads;
    const std::size_t chunk = (vs.size() + t_used - 1) / t_used;
    std::vector<std::thread> pool;
    for (int t = 1; t < t_used; ++t)
      pool.emplace_back(work, std::min(vs.size(), t * chunk), std::min(vs.size(), (t + 1) * chunk), std::ref(local[t]));
    work(0, std::min(vs.size(), chunk), local[0]);
    for (auto& th : pool) th.join();
    for (Local& l : local) {
      for (int w : l.woken) qm.active[w] = 1;
      l.woken.clear();
    }
  }
  for (const Local& l : local) {
    st.moves += l.moves;
    st.rejected += l.rejected;
    st.optimized += l.optimized;
  }
}

void slide_pass(QuadMesh& qm, SmoothStats& st) {
  const std::vector<Point2>& P = qm.points;
  for (const Slide& s : qm.slides) {
    // Even spacing along the segment: the midpoint of the two neighbours,
    // strictly between them, projected back onto the line through A and B.
    const Point2 &u = P[s.u], &w = P[s.w];
    const Point2 mid{0.5 * (u[0] + w[0]), 0.5 * (u[1] + w[1])};
    if (try_move(qm, s.v, mid, true, &s)) {
      ++st.slides;
      qm.wake(s.v);
    }
  }
}

void relax(QuadMesh& qm, const Patch& pt) {
  // The core and new points (after the saved ones) twice, the ring once:
  // every star stays inside the patch.
  auto smooth = [&](std::size_t i) {
    const int v = pt.verts[i];
    if (!qm.fixed[v] && !qm.vertex_dead[v] && qm.vertex_quads[v].size() >= 3) smooth_vertex(qm, v);
  };
  for (int round = 0; round < 2; ++round) {
    for (std::size_t i = 0; i < pt.ncore; ++i) smooth(i);
    for (std::size_t i = pt.p.size(); i < pt.verts.size(); ++i) smooth(i);
  }
  for (std::size_t i = pt.ncore; i < pt.p.size(); ++i) smooth(i);
}

bool raise_grading(QuadMesh& qm, int v, double h2, double target, double floor) {
  std::vector<Point2>& P = qm.points;
  const std::vector<int>& qs = qm.vertex_quads[v];
  auto worst = [&] {
    double w = 1;
    for (int q : qs) w = std::max(w, grading_ratio(qm, q));
    return w;
  };
  const double r0 = worst();
  if (!(r0 > target)) return false;
  // Each quad around keeps its mu, or the floor if that is lower.
  std::vector<double> keep;
  for (int q : qs) keep.push_back(std::min(qm.quad_sin_mu[q], floor));
  const Point2 start = P[v];
  double best = r0;
  compass_search(start, 0.125 * std::sqrt(h2), kWorstRounds, [&](const Point2& c) { P[v] = c; }, [&] {
    // Within the target: no further step (each costs mu).
    if (best <= target) return false;
    for (std::size_t i = 0; i < qs.size(); ++i)
      if (qm.sin_mu_of(qm.quads[qs[i]]) < keep[i]) return false;
    const double r = worst();
    if (!(r < best * (1 - 1e-9))) return false;
    for (int q : qs)
      if (!qm.convex(qm.quads[q])) return false;
    best = r;
    return true;
  });
  if (P[v] == start) return false;
  for (int q : qs) qm.quad_sin_mu[q] = qm.sin_mu_of(qm.quads[q]);
  return true;
}

} // namespace imgmesh::quadsmooth_detail
