#include "quad/smooth.hpp"

#include "util/error.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <functional>
#include <thread>
#include <unordered_map>
#include <unordered_set>

namespace imgmesh {

Json SmoothStats::to_json() const {
  Json j = Json::object();
  j["before"] = before.to_json();
  j["after"] = after.to_json();
  Json ops = Json::object();
  ops["passes"] = passes;
  ops["moves"] = moves;
  ops["slides"] = slides;
  ops["rejected_moves"] = rejected;
  ops["worst_mu_climbs"] = optimized;
  ops["edge_moves"] = edge_moves;
  ops["diagonal_swaps"] = swaps;
  ops["valence_swaps"] = valence_swaps;
  ops["pair_splits"] = splits;
  ops["pair_splits_four"] = splits_four;
  ops["doublets_removed"] = doublets;
  ops["quad_collapses"] = collapses;
  ops["valence_collapses"] = valence_collapses;
  ops["fixed_vertices"] = fixed_vertices;
  j["operations"] = ops;
  return j;
}

namespace {

// sin of the smallest angle of a triangle from its squared edge lengths
// and twice its area. The smallest angle is at most 60 degrees, where sin
// is monotone: comparing sines compares angles without any trigonometry
// (the guard runs millions of times). It is opposite the shortest edge:
// sin = 2A / (product of the other two).
inline double sin_min_angle(double l1, double l2, double l3, double area2) {
  double den;
  if (l1 <= l2 && l1 <= l3) den = l2 * l3;
  else if (l2 <= l3) den = l1 * l3;
  else den = l1 * l2;
  if (!(den > 0)) return 0;
  return std::fabs(area2) / std::sqrt(den);
}

// sin(Joe's mu); mu <= 45 degrees so the sine orders quads like mu does.
// The four triangles share the four sides and two diagonals.
inline double sin_mu(const Point2& a, const Point2& b, const Point2& c, const Point2& d) {
  auto sq = [](const Point2& p, const Point2& q) {
    return (q[0] - p[0]) * (q[0] - p[0]) + (q[1] - p[1]) * (q[1] - p[1]);
  };
  auto cross = [](const Point2& o, const Point2& p, const Point2& q) {
    return (p[0] - o[0]) * (q[1] - o[1]) - (p[1] - o[1]) * (q[0] - o[0]);
  };
  const double ab = sq(a, b), bc = sq(b, c), cd = sq(c, d), da = sq(d, a), ac = sq(a, c), bd = sq(b, d);
  // Diagonal bd: [a,b,d], [c,d,b]; diagonal ac: [a,b,c], [d,a,c].
  return std::min(std::min(sin_min_angle(ab, bd, da, cross(a, b, d)), sin_min_angle(cd, bd, bc, cross(c, d, b))),
                  std::min(sin_min_angle(ab, bc, ac, cross(a, b, c)), sin_min_angle(da, ac, cd, cross(d, a, c))));
}

// Clean-up for the worst mu is tried only around poor quads: sin(30 deg) for
// swaps (a quad of the pair below the usual bar), sin(15 deg) for collapses
// (pair splits: SmoothOptions::split_below). Valence-driven swaps and
// collapses may run anywhere.
constexpr double kSwapBelow = 0.5;
constexpr double kCollapseBelow = 0.25881904510252074;
// Vertices next to a quad with mu below 25 degrees also get a compass search
// on the soft minimum of mu around them.
constexpr double kOptimizeBelow = 0.42261826174069944;  // sin(25 deg)
constexpr int kOptimizeRounds = 6;
constexpr std::size_t kStarCache = 16;  // quads around a vertex whose sines try_move keeps aside
// Only moves of over 3% of an edge put the neighbours back on the smoothing
// work list: the smaller ones barely change their targets, and waking for
// them cost a third more time on 10^6 quads for 0.4 degrees of mean mu.
constexpr double kWakeFar = 1e-3;

// The directed edges a -> b of all elements grouped by a (a counting sort,
// in element order): for each vertex, the elements around it and the next
// vertex in each. The conformity check and the smoother's adjacency both
// read it; no sort and no hashing, so 10^6 quads take a fraction of a second.
struct Stars {
  std::vector<int> start, next, elem;
  // The element holding the directed edge b -> a, or -1.
  int twin(int a, int b) const {
    for (int i = start[b]; i < start[b + 1]; ++i)
      if (next[i] == a) return elem[i];
    return -1;
  }
};

// Checks the input contract (see check_quad_mesh) and returns the stars.
Stars conforming_stars(const PlanarMesh& m, const std::string& path) {
  const long long n = static_cast<long long>(m.points.size());
  if (m.elements.empty()) throw Error("mesh has no elements", path);
  for (const auto& p : m.points)
    if (!std::isfinite(p[0]) || !std::isfinite(p[1])) throw Error("non-finite point coordinate", path);
  Stars s;
  s.start.assign(std::size_t(n) + 1, 0);
  for (std::size_t e = 0; e < m.elements.size(); ++e) {
    const auto& el = m.elements[e];
    auto where = [&] { return "element " + std::to_string(e + m.first_index); };  // built only to throw
    if (el.size() != 3 && el.size() != 4) throw Error(where() + " has " + std::to_string(el.size()) + " nodes (want 3 or 4)", path);
    for (std::size_t i = 0; i < el.size(); ++i) {
      if (el[i] < 0 || el[i] >= n) throw Error(where() + ": node id out of range", path);
      for (std::size_t j = 0; j < i; ++j)
        if (el[i] == el[j]) throw Error(where() + ": repeated node", path);
    }
    const auto& P = m.points;
    double area2 = 0;
    for (std::size_t i = 0; i < el.size(); ++i) {
      const Point2 &p = P[el[i]], &q = P[el[(i + 1) % el.size()]];
      area2 += p[0] * q[1] - p[1] * q[0];
    }
    if (!(area2 > 0)) throw Error(where() + " is clockwise or degenerate (want counter-clockwise)", path);
    for (int v : el) ++s.start[v + 1];
  }
  for (std::size_t v = 0; v < std::size_t(n); ++v) s.start[v + 1] += s.start[v];
  s.next.resize(s.start[n]);
  s.elem.resize(s.start[n]);
  std::vector<int> fill(s.start.begin(), s.start.end() - 1);
  for (std::size_t e = 0; e < m.elements.size(); ++e) {
    const auto& el = m.elements[e];
    for (std::size_t i = 0; i < el.size(); ++i) {
      const int a = el[i];
      s.next[fill[a]] = el[(i + 1) % el.size()];
      s.elem[fill[a]++] = int(e);
    }
  }
  // An edge in at most two elements with opposite orientations: no directed
  // edge twice (a third use would repeat one of the two directions).
  for (int a = 0; a < n; ++a)
    for (int i = s.start[a]; i < s.start[a + 1]; ++i)
      for (int j = i + 1; j < s.start[a + 1]; ++j) {
        if (s.next[i] != s.next[j]) continue;
        const int b = s.next[i];
        const std::string where = "edge " + std::to_string(std::min(a, b) + m.first_index) + "-" +
                                  std::to_string(std::max(a, b) + m.first_index);
        int uses = 0;
        for (int k = s.start[a]; k < s.start[a + 1]; ++k) uses += s.next[k] == b;
        for (int k = s.start[b]; k < s.start[b + 1]; ++k) uses += s.next[k] == a;
        if (uses > 2) throw Error(where + " is shared by more than two elements", path);
        throw Error(where + ": neighbouring elements are oriented inconsistently", path);
      }
  for (const auto& sg : m.segments)
    if (sg[0] < 0 || sg[0] >= n || sg[1] < 0 || sg[1] >= n) throw Error("segment id out of range", path);
  return s;
}

class QuadImprover {
public:
  QuadImprover(PlanarMesh& m, const SmoothOptions& opt, SmoothStats& st)
      : m_(m), opt_(opt), st_(st), P_(m.points),
        split_below_(std::sin(std::clamp(opt.split_below, 0.0, 45.0) * (3.14159265358979323846 / 180))) {}

  void run(const Stars& stars);

private:
  using Quad = std::array<int, 4>;
  PlanarMesh& m_;
  const SmoothOptions& opt_;
  SmoothStats& st_;
  std::vector<Point2>& P_;
  const double split_below_;             // sin of SmoothOptions::split_below
  std::vector<Quad> Q_;                  // quads (copies of 4-node elements)
  std::vector<int> q_elem_;              // element index of each quad
  std::vector<char> q_dead_;
  std::vector<double> q_smu_;            // cached sin(mu)
  std::vector<std::vector<int>> vq_;     // vertex -> incident quads
  std::vector<char> fixed_;              // never moves (and never merges away)
  std::vector<char> v_dead_;
  std::unordered_set<std::uint64_t> feature_;  // boundary, segment and region-boundary edges
  // Sliding vertices: the fixed ends A, B of their straight chain and the two
  // feature neighbours bounding the slide.
  struct Slide { int v, A, B, u, w; };
  std::vector<Slide> slides_;
  std::vector<char> active_;             // smoothing work list (see smooth_pass)
  // Poor quads whose pair splits all failed: a later try rarely succeeds
  // and costs a relaxation each, so they are tried again only once changed.
  std::vector<char> tried_;

  void setup(const Stars& stars);
  // Feature edges join two fixed vertices: test that first, hash rarely.
  bool is_feature(int a, int b) const { return fixed_[a] && fixed_[b] && feature_.count(edge_key(a, b)) != 0; }
  double quad_smu(const Quad& q) const { return sin_mu(P_[q[0]], P_[q[1]], P_[q[2]], P_[q[3]]); }
  bool convex(const Quad& q) const { return is_strictly_convex(P_[q[0]], P_[q[1]], P_[q[2]], P_[q[3]]); }
  // Try moving v to p (with back-off toward the current position); the guard.
  bool try_move(int v, Point2 p, bool slide_line, const Slide* s);
  bool angle_based_target(int v, Point2& out) const;
  // The energy sum 1/sin(mu) of the quads around v (a soft minimum); false
  // if a quad is not strictly convex or below floor, or the energy reaches cap.
  bool star_energy(int v, double floor, double cap, double& energy) const;
  // Compass search on the energy around v, the worst mu never dropping.
  bool optimize_star(int v, double h2);
  // Compass search moving the two free ends u, v of an edge together, on the
  // energy of the quads around either, same guard (see edge_pass).
  bool optimize_edge(int u, int v, double h);
  void edge_pass();
  // One guarded angle-based move then the compass search; kMoved, kRejected,
  // kOptimized bits, and kFar: moved by over sqrt(kWakeFar) of an edge.
  enum { kMoved = 1, kRejected = 2, kOptimized = 4, kFar = 8 };
  int smooth_vertex(int v);
  // Colour classes of the smoothing vertices (see colour()); recomputed
  // when the topology changed.
  std::vector<std::vector<int>> colours_;
  bool colours_stale_ = true;
  // The compass search waits for the first angle-based pass: most poor
  // quads of a distorted mesh are fixed by it, at a fraction of the cost.
  bool climb_ = false;
  void colour();
  void smooth_pass();
  void slide_pass();

  // A patch: the stars of some core vertices and of their neighbours, saved
  // so that a topological operation plus relaxation can be undone.
  struct Patch {
    std::vector<int> quads, verts;  // verts: the core first, then the ring
    std::size_t ncore = 0;
    std::vector<Quad> q;
    std::vector<char> qdead, vdead;
    std::vector<std::vector<int>> vq;
    std::vector<Point2> p;
  };
  std::vector<int> vstamp_, qstamp_;
  int stamp_id_ = 0;
  void save_patch(std::initializer_list<int> core, Patch& pt);
  void restore(const Patch& pt);
  double patch_worst(const Patch& pt) const;
  void relax(const Patch& pt);
  void set_quad(int q, const Quad& nq);
  int quad_with_edge(int a, int b) const;  // the quad holding the directed edge a -> b, or -1
  // Valence (Canann et al.): the quads around v in the fan holding q, bounded
  // by feature edges, and the number the fan's angle wants, one a 90 degrees
  // (4 around a closed star).
  struct Fan { int count, ideal; bool closed; };
  Fan fan(int v, int q) const {
    return fixed_[v] ? fixed_fan(v, q) : Fan{int(vq_[v].size()), 4, true};  // a free vertex's star is closed
  }
  Fan fixed_fan(int v, int q) const;
  // The sines of the patch's live quads, ascending: operations compare
  // these lexicographically, so one bad quad elsewhere in the patch does not
  // hide an improvement of the next worst.
  std::vector<double> patch_sines(const Patch& pt) const;
  static bool lex_better(const std::vector<double>& now, const std::vector<double>& before);
  // A new free vertex at p (point attributes and marker zero), and a new quad
  // element of q's region (its corners set by set_quad); the drop_* undo the
  // latest one.
  int add_vertex(const Point2& p);
  void drop_vertex();
  int add_quad(int like);
  void drop_quad();
  // 3 or 4: the number of quads the pair became; 0: left as it was.
  int split_pair(int q1, int q2, const int (&H)[6]);
  void swap_pass();
  void collapse_pass();
  void doublet_pass();
  // Puts the vertices of the quads around v back on the smoothing work list
  // (after a topological operation near v).
  void wake(int v) {
    for (int q : vq_[v])
      for (int w : Q_[q]) active_[w] = 1;
  }
  void remove_from(int v, int q) {
    auto& l = vq_[v];
    l.erase(std::remove(l.begin(), l.end(), q), l.end());
  }
  void compact();
};

void QuadImprover::setup(const Stars& stars) {
  const int n = int(P_.size());
  vq_.assign(n, {});
  fixed_.assign(n, 0);
  v_dead_.assign(n, 0);
  std::vector<int> quad_of_elem(m_.elements.size(), -1);
  for (std::size_t e = 0; e < m_.elements.size(); ++e) {
    const auto& el = m_.elements[e];
    if (el.size() != 4) continue;
    quad_of_elem[e] = int(Q_.size());
    Q_.push_back({el[0], el[1], el[2], el[3]});
    q_elem_.push_back(int(e));
  }
  // Feature edges: used once (boundary), between elements of different
  // region attribute, or listed as segments.
  auto region = [&](int e) {
    return m_.element_attributes.empty() || m_.element_attributes[e].empty() ? 0.0 : m_.element_attributes[e][0];
  };
  for (int v = 0; v < n; ++v) {
    vq_[v].reserve(stars.start[v + 1] - stars.start[v]);
    for (int i = stars.start[v]; i < stars.start[v + 1]; ++i) {
      const int e = stars.elem[i];
      if (quad_of_elem[e] >= 0) vq_[v].push_back(quad_of_elem[e]);
      else fixed_[v] = 1;  // triangles stay as they are
      const int t = stars.twin(v, stars.next[i]);
      if (t < 0 || region(t) != region(e)) feature_.insert(edge_key(v, stars.next[i]));
    }
  }
  q_dead_.assign(Q_.size(), 0);
  tried_.assign(Q_.size(), 0);
  q_smu_.resize(Q_.size());
  for (std::size_t q = 0; q < Q_.size(); ++q) q_smu_[q] = quad_smu(Q_[q]);
  for (const auto& s : m_.segments) feature_.insert(edge_key(s[0], s[1]));
  // Segment markers of feature edges, to tell one input segment from the next.
  std::unordered_map<std::uint64_t, int> seg_marker;
  for (std::size_t i = 0; i < m_.segments.size(); ++i)
    seg_marker[edge_key(m_.segments[i][0], m_.segments[i][1])] =
        m_.segment_markers.empty() ? 0 : m_.segment_markers[i];

  std::vector<std::vector<int>> fnb(n);  // feature neighbours
  for (std::uint64_t k : feature_) {
    const int a = int(k >> 32), b = int(k & 0xffffffffu);
    fnb[a].push_back(b);
    fnb[b].push_back(a);
  }
  std::vector<char> can_slide(n, 0);
  for (int v = 0; v < n; ++v) {
    if (!fnb[v].empty()) fixed_[v] = 1;
    // A marked vertex off every feature edge is an input point: keep it.
    // Marked vertices on feature edges (Triangle marks the boundary) follow
    // the feature rules below, so they may slide.
    if (!m_.point_markers.empty() && m_.point_markers[v] != 0) fixed_[v] = 1;
    if (fnb[v].size() == 2 && opt_.slide_boundary && !vq_[v].empty()) {
      const int u = fnb[v][0], w = fnb[v][1];
      // Only inside one straight input segment: collinear (exactly), v between
      // u and w, same segment marker on both sides, and only quads around.
      const auto mu = seg_marker.find(edge_key(u, v)), mw = seg_marker.find(edge_key(v, w));
      const bool same_marker = (mu == seg_marker.end() ? 0 : mu->second) == (mw == seg_marker.end() ? 0 : mw->second);
      const double dot = (P_[u][0] - P_[v][0]) * (P_[w][0] - P_[v][0]) + (P_[u][1] - P_[v][1]) * (P_[w][1] - P_[v][1]);
      can_slide[v] = orientation(P_[u], P_[v], P_[w]) == 0 && dot < 0 && same_marker;
    }
  }
  // Vertices on triangles stay fixed even if they could slide.
  for (const auto& el : m_.elements)
    if (el.size() != 4)
      for (int v : el) can_slide[v] = 0;
  // Chains of sliding vertices end at fixed vertices A and B; slides are
  // computed from A and B, which never move, so no rounding accumulates.
  std::vector<char> seen(n, 0);
  for (int v = 0; v < n; ++v) {
    if (!can_slide[v] || seen[v]) continue;
    std::vector<int> chain{v};
    seen[v] = 1;
    int ends[2];
    for (int side = 0; side < 2; ++side) {
      int prev = v, cur = fnb[v][side];
      while (can_slide[cur] && !seen[cur]) {
        seen[cur] = 1;
        chain.push_back(cur);
        const int nxt = fnb[cur][0] == prev ? fnb[cur][1] : fnb[cur][0];
        prev = cur;
        cur = nxt;
      }
      ends[side] = cur;
    }
    if (ends[0] == ends[1] || can_slide[ends[0]] || can_slide[ends[1]]) continue;  // closed straight loop: impossible, be safe
    for (int c : chain) {
      // Every vertex of the chain must be collinear with the ends, exactly.
      if (orientation(P_[ends[0]], P_[c], P_[ends[1]]) != 0) { chain.clear(); break; }
    }
    for (int c : chain) slides_.push_back({c, ends[0], ends[1], fnb[c][0], fnb[c][1]});
  }
  std::size_t nf = 0;
  for (int v = 0; v < n; ++v) nf += fixed_[v] && !vq_[v].empty();
  st_.fixed_vertices = nf;
}

bool QuadImprover::angle_based_target(int v, Point2& out) const {
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
  for (int q : vq_[v]) {
    const Quad& Qd = Q_[q];
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
  const Point2& pv = P_[v];
  for (int i = 0; i < k; ++i) {
    if (nb[i].y1 < 0 || nb[i].y2 < 0) return false;  // open star: not interior
    const Point2& px = P_[nb[i].x];
    const double vx = pv[0] - px[0], vy = pv[1] - px[1];
    const double len = std::sqrt(vx * vx + vy * vy);
    double ax = P_[nb[i].y1][0] - px[0], ay = P_[nb[i].y1][1] - px[1];
    double bx = P_[nb[i].y2][0] - px[0], by = P_[nb[i].y2][1] - px[1];
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

bool QuadImprover::try_move(int v, Point2 p, bool slide_line, const Slide* s) {
  const Point2 old = P_[v];
  double worst_old = 2;
  for (int q : vq_[v]) worst_old = std::min(worst_old, q_smu_[q]);
  double t = 1;
  for (int attempt = 0; attempt < 2; ++attempt, t *= 0.5) {
    Point2 c{old[0] + t * (p[0] - old[0]), old[1] + t * (p[1] - old[1])};
    if (slide_line) {
      // Recompute on the line through the fixed chain ends A and B.
      const Point2 &A = P_[s->A], &B = P_[s->B];
      const double dx = B[0] - A[0], dy = B[1] - A[1];
      const double tt = ((c[0] - A[0]) * dx + (c[1] - A[1]) * dy) / (dx * dx + dy * dy);
      c = {A[0] + tt * dx, A[1] + tt * dy};
      if (dx == 0) c[0] = A[0];  // axis-parallel segments stay exact
      if (dy == 0) c[1] = A[1];
    }
    if (c == old) return false;
    P_[v] = c;
    // New sines kept aside, written only if every quad passes.
    double smu[kStarCache];
    const std::size_t k = vq_[v].size();
    bool ok = true;
    // The mu guard first: it refuses most rejected moves, and costs less
    // than the sixteen orientation tests of the star.
    for (std::size_t i = 0; i < k && ok; ++i) {
      const Quad& Qd = Q_[vq_[v][i]];
      const double sq = quad_smu(Qd);
      if (sq < worst_old || !convex(Qd)) ok = false;
      if (i < kStarCache) smu[i] = sq;
    }
    if (ok) {
      for (std::size_t i = 0; i < k; ++i) q_smu_[vq_[v][i]] = i < kStarCache ? smu[i] : quad_smu(Q_[vq_[v][i]]);
      return true;
    }
    P_[v] = old;
  }
  return false;
}

bool QuadImprover::star_energy(int v, double floor, double cap, double& energy) const {
  energy = 0;
  for (int q : vq_[v]) {
    const double s = quad_smu(Q_[q]);
    if (s < floor) return false;
    energy += 1 / s;
    if (energy >= cap) return false;
  }
  // Convexity last: most candidate points fail on the energy already.
  for (int q : vq_[v])
    if (!convex(Q_[q])) return false;
  return true;
}

bool QuadImprover::optimize_star(int v, double h2) {
  double worst0 = 2, energy0 = 0;
  for (int q : vq_[v]) {
    worst0 = std::min(worst0, q_smu_[q]);
    energy0 += 1 / q_smu_[q];
  }
  if (worst0 >= kOptimizeBelow || !(worst0 > 0)) return false;
  const Point2 start = P_[v];
  Point2 p = start;
  double best = energy0, h = 0.25 * std::sqrt(h2);
  static const double dirs[8][2] = {{1, 0}, {0.7071067811865476, 0.7071067811865476}, {0, 1},
                                    {-0.7071067811865476, 0.7071067811865476}, {-1, 0},
                                    {-0.7071067811865476, -0.7071067811865476}, {0, -1},
                                    {0.7071067811865476, -0.7071067811865476}};
  // Opportunistic polling: the first direction that lowers the energy is
  // taken, and polled first again from the new point.
  int first = 0;
  for (int round = 0; round < kOptimizeRounds; ++round) {
    bool improved = false;
    for (int k = 0; k < 8 && !improved; ++k) {
      const int d = (first + k) & 7;
      P_[v] = {p[0] + h * dirs[d][0], p[1] + h * dirs[d][1]};
      double e;
      if (star_energy(v, worst0, best * (1 - 1e-12), e)) { best = e; p = P_[v]; first = d; improved = true; }
    }
    P_[v] = p;
    if (!improved) h *= 0.5;
  }
  if (!(best < energy0 * (1 - 1e-9))) { P_[v] = start; return false; }
  P_[v] = p;
  for (int q : vq_[v]) q_smu_[q] = quad_smu(Q_[q]);
  return true;
}

bool QuadImprover::optimize_edge(int u, int v, double h) {
  std::vector<int> qs = vq_[u];
  for (int q : vq_[v])
    if (std::find(qs.begin(), qs.end(), q) == qs.end()) qs.push_back(q);
  double worst0 = 2, energy0 = 0;
  for (int q : qs) {
    worst0 = std::min(worst0, q_smu_[q]);
    energy0 += 1 / q_smu_[q];
  }
  if (worst0 >= kOptimizeBelow || !(worst0 > 0)) return false;
  auto energy = [&](double cap, double& e) {
    e = 0;
    for (int q : qs) {
      const double sq = quad_smu(Q_[q]);
      if (sq < worst0) return false;
      e += 1 / sq;
      if (e >= cap) return false;
    }
    for (int q : qs)
      if (!convex(Q_[q])) return false;
    return true;
  };
  static const double dirs[8][2] = {{1, 0}, {0.7071067811865476, 0.7071067811865476}, {0, 1},
                                    {-0.7071067811865476, 0.7071067811865476}, {-1, 0},
                                    {-0.7071067811865476, -0.7071067811865476}, {0, -1},
                                    {0.7071067811865476, -0.7071067811865476}};
  const Point2 su = P_[u], sv = P_[v];
  Point2 d{0, 0};  // the displacement so far
  double best = energy0;
  int first = 0;
  for (int round = 0; round < 2 * kOptimizeRounds; ++round) {
    bool improved = false;
    for (int k = 0; k < 8 && !improved; ++k) {
      const int dk = (first + k) & 7;
      const Point2 c{d[0] + h * dirs[dk][0], d[1] + h * dirs[dk][1]};
      P_[u] = {su[0] + c[0], su[1] + c[1]};
      P_[v] = {sv[0] + c[0], sv[1] + c[1]};
      double e;
      if (energy(best * (1 - 1e-12), e)) { best = e; d = c; first = dk; improved = true; }
    }
    P_[u] = {su[0] + d[0], su[1] + d[1]};
    P_[v] = {sv[0] + d[0], sv[1] + d[1]};
    if (!improved) h *= 0.5;
  }
  if (!(best < energy0 * (1 - 1e-9))) {
    P_[u] = su;
    P_[v] = sv;
    return false;
  }
  for (int q : qs) q_smu_[q] = quad_smu(Q_[q]);
  return true;
}

void QuadImprover::edge_pass() {
  // A poor quad whose two free corners lie almost on its opposite, fixed
  // side (a sliver along a segment) cannot be opened one corner at a time:
  // moving either away from the segment makes the other reflex. Moved
  // together, they can. Only such flat pairs: edge moves anywhere else
  // gained little and, on the brain with --slide-boundary, steered the
  // clean-up into a worse end (min mu 2.6 instead of 9).
  for (int q = 0; q < int(Q_.size()); ++q) {
    if (q_dead_[q] || q_smu_[q] >= kOptimizeBelow) continue;
    const Quad& Qd = Q_[q];
    double side2 = 0;
    for (int k = 0; k < 4; ++k) {
      const Point2 &a = P_[Qd[k]], &b = P_[Qd[(k + 1) & 3]];
      side2 = std::max(side2, (a[0] - b[0]) * (a[0] - b[0]) + (a[1] - b[1]) * (a[1] - b[1]));
    }
    // Flat: the corner's cosine below -0.7 (over 134 degrees).
    auto flat = [&](int k) {
      const Point2 &o = P_[Qd[k]], &a = P_[Qd[(k + 1) & 3]], &b = P_[Qd[(k + 3) & 3]];
      const double ux = a[0] - o[0], uy = a[1] - o[1], vx = b[0] - o[0], vy = b[1] - o[1];
      return ux * vx + uy * vy < -0.7 * std::sqrt((ux * ux + uy * uy) * (vx * vx + vy * vy));
    };
    for (int k = 0; k < 4 && q_smu_[q] < kOptimizeBelow; ++k) {
      const int u = Qd[k], v = Qd[(k + 1) & 3];
      if (fixed_[u] || fixed_[v] || !flat(k) || !flat((k + 1) & 3) ||
          !optimize_edge(u, v, 0.25 * std::sqrt(side2)))
        continue;
      ++st_.edge_moves;
      wake(u);
      wake(v);
    }
  }
}

int QuadImprover::smooth_vertex(int v) {
  Point2 target;
  if (!angle_based_target(v, target)) return 0;
  const Point2& p = P_[v];
  const Point2& x = P_[Q_[vq_[v][0]][0] == v ? Q_[vq_[v][0]][1] : Q_[vq_[v][0]][0]];
  const double d2 = (target[0] - p[0]) * (target[0] - p[0]) + (target[1] - p[1]) * (target[1] - p[1]);
  const double h2 = (x[0] - p[0]) * (x[0] - p[0]) + (x[1] - p[1]) * (x[1] - p[1]);
  int r = 0;
  if (d2 >= 1e-4 * h2) r = try_move(v, target, false, nullptr) ? kMoved : kRejected;  // else converged to 1e-2 of an edge
  if ((r & kMoved) && d2 >= kWakeFar * h2) r |= kFar;
  // Where the angle-based position cannot help a poor quad, climb on the
  // soft minimum of mu itself (compass search, guarded the same way).
  if (climb_ && optimize_star(v, h2)) r |= kOptimized;
  return r;
}

void QuadImprover::colour() {
  // Greedy colouring of the vertices that smooth: two that share a quad
  // get different colours, so the vertices of one colour move
  // independently (each writes only its own position and its own star's
  // sines) and a colour's result does not depend on the thread count.
  const int n = int(P_.size());
  std::vector<int> col(n, -1), seen;
  colours_.clear();
  for (int v = 0; v < n; ++v) {
    if (fixed_[v] || v_dead_[v] || vq_[v].size() < 3) continue;
    for (int q : vq_[v])
      for (int w : Q_[q])
        if (col[w] >= 0) {
          if (int(seen.size()) <= col[w]) seen.resize(col[w] + 1, -1);
          seen[col[w]] = v;
        }
    int c = 0;
    while (c < int(seen.size()) && seen[c] == v) ++c;
    col[v] = c;
    if (int(colours_.size()) <= c) colours_.resize(c + 1);
    colours_[c].push_back(v);
  }
}

void QuadImprover::smooth_pass() {
  // Active set: a vertex is revisited only after something around it moved
  // (a rejected or negligible move would be rejected or negligible again).
  // Colour by colour, split over the threads; each thread keeps its own
  // counts and the vertices it woke up, applied after the colour.
  if (active_.size() != P_.size()) active_.assign(P_.size(), 1);
  if (colours_stale_) { colour(); colours_stale_ = false; }
  const int threads = std::max(1, opt_.threads);
  struct Local { std::size_t moves = 0, rejected = 0, optimized = 0; std::vector<int> woken; };
  std::vector<Local> local(threads);
  for (const std::vector<int>& vs : colours_) {
    auto work = [&](std::size_t begin, std::size_t end, Local& l) {
      for (std::size_t i = begin; i < end; ++i) {
        const int v = vs[i];
        if (!active_[v]) continue;
        active_[v] = 0;
        const int r = smooth_vertex(v);
        l.moves += (r & kMoved) != 0;
        l.rejected += (r & kRejected) != 0;
        l.optimized += (r & kOptimized) != 0;
        if (r & (kFar | kOptimized))
          for (int q : vq_[v])
            for (int w : Q_[q]) l.woken.push_back(w);
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
      for (int w : l.woken) active_[w] = 1;
      l.woken.clear();
    }
  }
  for (const Local& l : local) {
    st_.moves += l.moves;
    st_.rejected += l.rejected;
    st_.optimized += l.optimized;
  }
}

void QuadImprover::slide_pass() {
  for (const Slide& s : slides_) {
    // Even spacing along the segment: the midpoint of the two neighbours,
    // strictly between them, projected back onto the line through A and B.
    const Point2 &u = P_[s.u], &w = P_[s.w];
    const Point2 mid{0.5 * (u[0] + w[0]), 0.5 * (u[1] + w[1])};
    if (try_move(s.v, mid, true, &s)) {
      ++st_.slides;
      if (!active_.empty())
        for (int q : vq_[s.v])
          for (int w : Q_[q]) active_[w] = 1;
    }
  }
}

int QuadImprover::quad_with_edge(int a, int b) const {
  for (int q : vq_[a]) {
    const Quad& E = Q_[q];
    for (int k = 0; k < 4; ++k)
      if (E[k] == a && E[(k + 1) & 3] == b) return q;
  }
  return -1;
}

QuadImprover::Fan QuadImprover::fixed_fan(int v, int q0) const {
  auto corner = [&](int q) {
    int i = 0;
    while (Q_[q][i] != v) ++i;
    return i;
  };
  Fan f{0, 0, false};
  double angle = 0;
  auto add = [&](int q) {
    const int i = corner(q);
    const Point2 &o = P_[v], &x = P_[Q_[q][(i + 1) & 3]], &z = P_[Q_[q][(i + 3) & 3]];
    const double ux = x[0] - o[0], uy = x[1] - o[1], wx = z[0] - o[0], wy = z[1] - o[1];
    angle += std::atan2(std::fabs(ux * wy - uy * wx), ux * wx + uy * wy);
    ++f.count;
  };
  // Counter-clockwise across the edge v-z of (v, x, y, z), then clockwise
  // across v-x, each way until a feature edge or the mesh boundary.
  add(q0);
  for (int q = q0;;) {
    const int z = Q_[q][(corner(q) + 3) & 3];
    const int nx = is_feature(v, z) ? -1 : quad_with_edge(v, z);
    if (nx < 0) break;
    if (nx == q0) { f.closed = true; break; }
    add(nx);
    q = nx;
  }
  if (!f.closed)
    for (int q = q0;;) {
      const int x = Q_[q][(corner(q) + 1) & 3];
      const int nx = is_feature(v, x) ? -1 : quad_with_edge(x, v);
      if (nx < 0) break;
      add(nx);
      q = nx;
    }
  f.ideal = f.closed ? 4 : std::max(1, int(std::lround(angle * (2 / 3.14159265358979323846))));
  return f;
}

void QuadImprover::save_patch(std::initializer_list<int> core, Patch& pt) {
  if (++stamp_id_ == 1) {
    vstamp_.assign(P_.size(), 0);
    qstamp_.assign(Q_.size(), 0);
  }
  pt.quads.clear();
  pt.verts.clear();
  auto addv = [&](int v) {
    if (vstamp_[v] != stamp_id_) { vstamp_[v] = stamp_id_; pt.verts.push_back(v); }
  };
  for (int c : core) addv(c);
  pt.ncore = pt.verts.size();
  for (std::size_t i = 0; i < pt.ncore; ++i)
    for (int q : vq_[pt.verts[i]])
      for (int x : Q_[q]) addv(x);
  for (int v : pt.verts)
    for (int q : vq_[v])
      if (qstamp_[q] != stamp_id_) { qstamp_[q] = stamp_id_; pt.quads.push_back(q); }
  pt.q.clear(); pt.qdead.clear(); pt.vq.clear(); pt.p.clear(); pt.vdead.clear();
  for (int q : pt.quads) { pt.q.push_back(Q_[q]); pt.qdead.push_back(q_dead_[q]); }
  for (int v : pt.verts) { pt.vq.push_back(vq_[v]); pt.p.push_back(P_[v]); pt.vdead.push_back(v_dead_[v]); }
}

void QuadImprover::restore(const Patch& pt) {
  for (std::size_t i = 0; i < pt.verts.size(); ++i) {
    const int v = pt.verts[i];
    vq_[v] = pt.vq[i];
    P_[v] = pt.p[i];
    v_dead_[v] = pt.vdead[i];
  }
  for (std::size_t i = 0; i < pt.quads.size(); ++i) {
    const int q = pt.quads[i];
    Q_[q] = pt.q[i];
    q_dead_[q] = pt.qdead[i];
    q_smu_[q] = quad_smu(Q_[q]);
  }
}

double QuadImprover::patch_worst(const Patch& pt) const {
  double w = 2;
  for (int q : pt.quads)
    if (!q_dead_[q]) w = std::min(w, q_smu_[q]);
  return w;
}

void QuadImprover::relax(const Patch& pt) {
  // The core and new points (after the saved ones) twice, the ring once:
  // every star stays inside the patch.
  auto smooth = [&](std::size_t i) {
    const int v = pt.verts[i];
    if (!fixed_[v] && !v_dead_[v] && vq_[v].size() >= 3) smooth_vertex(v);
  };
  for (int round = 0; round < 2; ++round) {
    for (std::size_t i = 0; i < pt.ncore; ++i) smooth(i);
    for (std::size_t i = pt.p.size(); i < pt.verts.size(); ++i) smooth(i);
  }
  for (std::size_t i = pt.ncore; i < pt.p.size(); ++i) smooth(i);
}

void QuadImprover::set_quad(int q, const Quad& nq) {
  tried_[q] = 0;
  for (int x : Q_[q]) remove_from(x, q);
  Q_[q] = nq;
  for (int x : nq) vq_[x].push_back(q);
  q_smu_[q] = quad_smu(nq);
}

std::vector<double> QuadImprover::patch_sines(const Patch& pt) const {
  std::vector<double> s;
  for (int q : pt.quads)
    if (!q_dead_[q]) s.push_back(q_smu_[q]);
  std::sort(s.begin(), s.end());
  return s;
}

bool QuadImprover::lex_better(const std::vector<double>& now, const std::vector<double>& before) {
  const std::size_t n = std::min(now.size(), before.size());
  for (std::size_t i = 0; i < n; ++i) {
    if (now[i] > before[i] * (1 + 1e-9) + 1e-15) return true;
    if (now[i] < before[i] * (1 - 1e-9)) return false;
  }
  return false;
}

int QuadImprover::add_vertex(const Point2& p) {
  const int v = int(P_.size());
  P_.push_back(p);
  if (!m_.point_attributes.empty()) m_.point_attributes.emplace_back(m_.point_attributes[0].size(), 0.0);
  if (!m_.point_markers.empty()) m_.point_markers.push_back(0);
  vq_.emplace_back();
  fixed_.push_back(0);
  v_dead_.push_back(0);
  active_.push_back(1);
  vstamp_.push_back(stamp_id_);
  return v;
}

void QuadImprover::drop_vertex() {
  P_.pop_back();
  if (!m_.point_attributes.empty()) m_.point_attributes.pop_back();
  if (!m_.point_markers.empty()) m_.point_markers.pop_back();
  vq_.pop_back(); fixed_.pop_back(); v_dead_.pop_back(); active_.pop_back(); vstamp_.pop_back();
}

int QuadImprover::add_quad(int like) {
  const int q = int(Q_.size());
  // Copies: push_back may reallocate.
  const std::vector<int> el = m_.elements[q_elem_[like]];
  m_.elements.push_back(el);
  if (!m_.element_attributes.empty()) {
    const std::vector<double> attr = m_.element_attributes[q_elem_[like]];
    m_.element_attributes.push_back(attr);
  }
  Q_.push_back(Q_[like]);
  q_elem_.push_back(int(m_.elements.size()) - 1);
  q_dead_.push_back(0);
  q_smu_.push_back(0);
  qstamp_.push_back(stamp_id_);
  tried_.push_back(0);
  for (int x : Q_[q]) vq_[x].push_back(q);
  return q;
}

void QuadImprover::drop_quad() {
  m_.elements.pop_back();
  if (!m_.element_attributes.empty()) m_.element_attributes.pop_back();
  Q_.pop_back(); q_elem_.pop_back(); q_dead_.pop_back(); q_smu_.pop_back(); qstamp_.pop_back();
  tried_.pop_back();
}

int QuadImprover::split_pair(int q1, int q2, const int (&H)[6]) {
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
    for (int i : ids) { c[0] += P_[at(i)][0] / double(ids.size()); c[1] += P_[at(i)][1] / double(ids.size()); }
    return c;
  };
  const double worst_pair = std::min(q_smu_[q1], q_smu_[q2]);
  for (int variant = 0; variant < 5; ++variant) {
    save_patch({H[0], H[1], H[2], H[3], H[4], H[5]}, pt);
    const std::vector<double> before = patch_sines(pt);
    const bool three = variant < 2;
    const int k = three ? variant : variant - 2;
    const int e1 = add_vertex(three ? mean({0, 1, 2, 3, 4, 5}) : mean({0, 1, 2, 3, 4, 5, k, k + 2}));
    const int e2 = three ? -1 : add_vertex(mean({0, 1, 2, 3, 4, 5, k + 3, k + 5}));
    pt.verts.push_back(e1);  // relaxed with the patch
    if (!three) pt.verts.push_back(e2);
    const int q3 = add_quad(q1), q4 = three ? -1 : add_quad(q1);
    pt.quads.push_back(q3);
    if (!three) pt.quads.push_back(q4);
    if (three) {
      set_quad(q1, {at(k), at(k + 1), at(k + 2), e1});
      set_quad(q2, {at(k + 2), at(k + 3), at(k + 4), e1});
      set_quad(q3, {at(k + 4), at(k + 5), at(k), e1});
    } else {
      set_quad(q1, {at(k), at(k + 1), at(k + 2), e1});
      set_quad(q2, {at(k + 2), at(k + 3), e2, e1});
      set_quad(q3, {at(k + 3), at(k + 4), at(k + 5), e2});
      set_quad(q4, {at(k + 5), at(k), e1, e2});
    }
    bool ok = convex(Q_[q1]) && convex(Q_[q2]) && convex(Q_[q3]) && (three || convex(Q_[q4]));
    if (ok) {
      relax(pt);
      double worst_new = std::min(std::min(q_smu_[q1], q_smu_[q2]), q_smu_[q3]);
      if (!three) worst_new = std::min(worst_new, q_smu_[q4]);
      ok = worst_new > worst_pair * (1 + 1e-9) + 1e-15 && lex_better(patch_sines(pt), before);
    }
    if (ok) {
      for (int x : pt.verts) wake(x);
      return three ? 3 : 4;
    }
    // Undo: the patch first (it drops every reference to the new items), then the new items.
    for (int i = three ? 1 : 2; i > 0; --i) { pt.verts.pop_back(); pt.quads.pop_back(); }
    restore(pt);
    for (int i = three ? 1 : 2; i > 0; --i) { drop_vertex(); drop_quad(); }
  }
  return 0;
}

void QuadImprover::swap_pass() {
  Patch pt;
  // A pair of plain quads (neither poor nor with a fixed or irregular
  // corner) has nothing to gain: most of a fine mesh is skipped before the
  // neighbour is even looked up. A pair is tried from its first non-plain quad.
  const double try_below = std::max(kSwapBelow, split_below_);
  auto plain = [&](int q) {
    if (q_smu_[q] < try_below) return false;
    for (int x : Q_[q])
      if (fixed_[x] || vq_[x].size() != 4) return false;
    return true;
  };
  for (std::size_t q1 = 0; q1 < Q_.size(); ++q1) {
    if (q_dead_[q1] || plain(int(q1))) continue;
    bool changed = false;
    for (int i = 0; i < 4 && !changed; ++i) {
      const Quad A = Q_[q1];
      const int u = A[i], w = A[(i + 1) & 3];
      if (is_feature(u, w)) continue;
      // The other quad, holding w -> u.
      const int q2 = quad_with_edge(w, u);
      if (q2 < 0 || (q2 < int(q1) && !plain(q2))) continue;
      const Quad B = Q_[q2];
      int j = 0;
      while (B[j] != w) ++j;
      // Hexagon u, c, d, w, a, b (counter-clockwise).
      const int a = A[(i + 2) & 3], b = A[(i + 3) & 3];
      const int c = B[(j + 2) & 3], d = B[(j + 3) & 3];
      const int H[6] = {u, c, d, w, a, b};
      bool distinct = true;
      for (int x = 0; x < 6; ++x)
        for (int y = x + 1; y < 6; ++y) distinct = distinct && H[x] != H[y];
      if (!distinct) continue;
      // Valence excess of u and w (they lose a quad) and of the ends of
      // either new diagonal (they gain one).
      const Fan fu = fan(u, int(q1)), fw = fan(w, int(q1));
      const bool keep_valence = fu.count - 1 >= (fu.closed ? 3 : 1) && fw.count - 1 >= (fw.closed ? 3 : 1);
      const int e_uw = 1 - 2 * (fu.count - fu.ideal) + 1 - 2 * (fw.count - fw.ideal);
      const double cur = std::min(q_smu_[q1], q_smu_[q2]);
      const bool poor = cur < kSwapBelow;
      double best = cur * (1 + 1e-9) + 1e-15;
      int best_k = -1, valence_k = -1, best_de = 0;
      for (int k = 1; k <= 2; ++k) {
        const int p = H[k], r = H[(k + 3) % 6];
        const Fan fp = fan(p, q2), fr = fan(r, int(q1));  // c, d are in B; a, b in A
        const int de = e_uw + 1 + 2 * (fp.count - fp.ideal) + 1 + 2 * (fr.count - fr.ideal);
        const bool fewer_irregular = keep_valence && de < best_de;
        if (!poor && !fewer_irregular) continue;  // most pairs of a fine mesh stop here
        const Quad N1{H[k], H[k + 1], H[k + 2], H[(k + 3) % 6]};
        const Quad N2{H[(k + 3) % 6], H[(k + 4) % 6], H[(k + 5) % 6], H[k]};
        if (!convex(N1) || !convex(N2) || is_feature(p, r) || quad_with_edge(p, r) >= 0 ||
            quad_with_edge(r, p) >= 0)
          continue;  // the new diagonal must not already be an edge
        if (fewer_irregular) { best_de = de; valence_k = k; }
        const double sm = std::min(quad_smu(N1), quad_smu(N2));
        if (poor && sm > best) { best = sm; best_k = k; }
      }
      auto apply = [&](int k) {
        set_quad(int(q1), {H[k], H[k + 1], H[k + 2], H[(k + 3) % 6]});
        set_quad(q2, {H[(k + 3) % 6], H[(k + 4) % 6], H[(k + 5) % 6], H[k]});
      };
      if (best_k >= 0) {
        apply(best_k);  // the pair's worst mu improves: nothing else changes
      } else if (const int parts = cur < split_below_ && !tried_[q1] ? split_pair(int(q1), q2, H) : 0) {
        ++st_.splits;
        st_.splits_four += parts == 4;
        changed = true;
        continue;
      } else if (valence_k >= 0) {
        // Fewer irregular vertices: taken if, after relaxing the patch, its
        // worst mu has not dropped.
        save_patch({u, w, a, b, c, d}, pt);
        const double before = patch_worst(pt);
        apply(valence_k);
        relax(pt);
        if (patch_worst(pt) < before) { restore(pt); continue; }
        for (int x : pt.verts) wake(x);
        ++st_.valence_swaps;
      } else {
        continue;
      }
      for (int x : H) wake(x);
      ++st_.swaps;
      changed = true;  // q1 changed: move on
    }
    if (!changed && q_smu_[q1] < split_below_) tried_[q1] = 1;
  }
}

void QuadImprover::doublet_pass() {
  const int n = int(P_.size());
  for (int v = 0; v < n; ++v) {
    if (fixed_[v] || v_dead_[v] || vq_[v].size() != 2) continue;
    const int q1 = vq_[v][0], q2 = vq_[v][1];
    Quad A = Q_[q1];
    while (A[0] != v) std::rotate(A.begin(), A.begin() + 1, A.end());
    Quad B = Q_[q2];
    while (B[0] != v) std::rotate(B.begin(), B.begin() + 1, B.end());
    // A = (v, a, b, c), B = (v, c, d, a).
    if (B[1] != A[3] || B[3] != A[1]) continue;
    const Quad M{A[1], A[2], A[3], B[2]};
    if (M[1] == M[3] || !convex(M) || quad_smu(M) < std::min(q_smu_[q1], q_smu_[q2])) continue;
    for (int x : B) remove_from(x, q2);
    remove_from(v, q1);
    q_dead_[q2] = 1;
    v_dead_[v] = 1;
    Q_[q1] = M;
    if (std::find(vq_[B[2]].begin(), vq_[B[2]].end(), q1) == vq_[B[2]].end()) vq_[B[2]].push_back(q1);
    q_smu_[q1] = quad_smu(M);
    for (int x : M) wake(x);
    ++st_.doublets;
  }
}

void QuadImprover::collapse_pass() {
  Patch pt;
  for (std::size_t q = 0; q < Q_.size(); ++q) {
    if (q_dead_[q]) continue;
    for (int diag = 0; diag < 2; ++diag) {
      const Quad C = Q_[q];
      int a = C[diag], c = C[diag + 2];
      const int b = C[diag + 1], d = C[(diag + 3) & 3];
      if (v_dead_[a] || v_dead_[c]) continue;
      if (fixed_[a] && fixed_[c]) continue;
      // Collapses are for the worst quads (short diagonal, squashed), and
      // for diagonals of two free valence-3 vertices (they merge into a
      // regular one) when b or d has more quads than it wants, which it
      // then loses (Canann et al.'s valence-driven collapse).
      bool valence = false;
      if (!fixed_[a] && !fixed_[c] && vq_[a].size() == 3 && vq_[c].size() == 3) {
        const Fan fb = fan(b, int(q)), fd = fan(d, int(q));
        valence = fb.count - fb.ideal + fd.count - fd.ideal > 0;
      }
      if (!valence && q_smu_[q] >= kCollapseBelow) continue;
      bool feat = false;
      for (int t = 0; t < 4; ++t) feat = feat || is_feature(C[t], C[(t + 1) & 3]);
      if (feat) continue;
      if (fixed_[c]) std::swap(a, c);  // keep the fixed one (a), merge c into it
      // Link condition: no other quad holds both a and c, and a and c share
      // no edge neighbour besides b and d.
      bool bad = false;
      for (int o : vq_[c])
        if (o != int(q) && std::find(Q_[o].begin(), Q_[o].end(), a) != Q_[o].end()) bad = true;
      if (bad) continue;
      std::vector<int> na;
      for (int o : vq_[a]) {
        if (o == int(q)) continue;
        const Quad& E = Q_[o];
        for (int t = 0; t < 4; ++t)
          if (E[t] == a) { na.push_back(E[(t + 1) & 3]); na.push_back(E[(t + 3) & 3]); }
      }
      for (int o : vq_[c]) {
        if (o == int(q)) continue;
        const Quad& E = Q_[o];
        for (int t = 0; t < 4; ++t)
          if (E[t] == c)
            for (int x : {E[(t + 1) & 3], E[(t + 3) & 3]})
              if (x != b && x != d && std::find(na.begin(), na.end(), x) != na.end()) bad = true;
      }
      if (bad) continue;
      // b and d lose a quad: interior ones of valence 3 would become
      // doublets and boundary ones must keep one; leave those alone.
      if (vq_[b].size() <= (fixed_[b] ? 1u : 3u) || vq_[d].size() <= (fixed_[d] ? 1u : 3u)) continue;
      double worst_old = 2;
      for (int o : vq_[a]) worst_old = std::min(worst_old, q_smu_[o]);
      for (int o : vq_[c]) worst_old = std::min(worst_old, q_smu_[o]);
      const Point2 pa = P_[a], pc = P_[c];
      const Point2 pm = fixed_[a] ? pa : Point2{0.5 * (pa[0] + pc[0]), 0.5 * (pa[1] + pc[1])};
      // Evaluate with c replaced by a at pm.
      P_[a] = pm;
      bool ok = true;
      double worst = 2;
      auto eval = [&](int o) {
        if (o == int(q) || !ok) return;
        Quad E = Q_[o];
        for (int& x : E) if (x == c) x = a;
        if (!is_strictly_convex(P_[E[0]], P_[E[1]], P_[E[2]], P_[E[3]])) { ok = false; return; }
        worst = std::min(worst, quad_smu(E));
      };
      for (int o : vq_[a]) eval(o);
      for (int o : vq_[c]) eval(o);
      if (!ok || (!valence && worst <= worst_old * (1 + 1e-9) + 1e-15)) { P_[a] = pa; continue; }
      if (valence) {
        P_[a] = pa;
        save_patch({a, c, b, d}, pt);
        P_[a] = pm;
      }
      // Commit.
      for (int x : C) remove_from(x, int(q));
      q_dead_[q] = 1;
      for (int o : vq_[c]) {
        for (int& x : Q_[o]) if (x == c) x = a;
        vq_[a].push_back(o);
      }
      vq_[c].clear();
      v_dead_[c] = 1;
      for (int o : vq_[a]) q_smu_[o] = quad_smu(Q_[o]);
      if (valence) {
        // Taken if, once relaxed, the worst mu around has not dropped.
        const double before = std::min(patch_worst(pt), worst_old);
        relax(pt);
        if (patch_worst(pt) < before) { restore(pt); continue; }
        ++st_.valence_collapses;
      }
      wake(a);
      ++st_.collapses;
      break;
    }
  }
}

void QuadImprover::compact() {
  // In place, by moves: no element or attribute list is copied (10^6 of
  // them would be as many allocations).
  std::vector<int> newid(P_.size(), -1);
  int k = 0;
  for (std::size_t v = 0; v < P_.size(); ++v)
    if (!v_dead_[v]) newid[v] = k++;
  // Elements: quads from Q_, others as they were.
  std::vector<int> quad_of_elem(m_.elements.size(), -1);
  for (std::size_t q = 0; q < Q_.size(); ++q) quad_of_elem[q_elem_[q]] = int(q);
  const bool attrs = !m_.element_attributes.empty();
  std::size_t kept = 0;
  for (std::size_t e = 0; e < m_.elements.size(); ++e) {
    const int q = quad_of_elem[e];
    if (q >= 0 && q_dead_[q]) continue;
    std::vector<int>& el = m_.elements[e];
    if (q >= 0) el.assign(Q_[q].begin(), Q_[q].end());
    for (int& x : el) x = newid[x];
    if (kept != e) {
      m_.elements[kept] = std::move(el);
      if (attrs) m_.element_attributes[kept] = std::move(m_.element_attributes[e]);
    }
    ++kept;
  }
  m_.elements.resize(kept);
  if (attrs) m_.element_attributes.resize(kept);
  if (k == int(P_.size())) return;
  const bool pattrs = !m_.point_attributes.empty(), pmarks = !m_.point_markers.empty();
  for (std::size_t v = 0; v < P_.size(); ++v) {
    if (v_dead_[v] || newid[v] == int(v)) continue;
    P_[newid[v]] = P_[v];
    if (pattrs) m_.point_attributes[newid[v]] = std::move(m_.point_attributes[v]);
    if (pmarks) m_.point_markers[newid[v]] = m_.point_markers[v];
  }
  P_.resize(k);
  if (pattrs) m_.point_attributes.resize(k);
  if (pmarks) m_.point_markers.resize(k);
  for (auto& sg : m_.segments) sg = {newid[sg[0]], newid[sg[1]]};  // segment ends never die
}

void QuadImprover::run(const Stars& stars) {
  setup(stars);
  const int passes = std::max(0, opt_.iterations);
  for (int it = 0; it < passes; ++it) {
    // Clean-up every third pass, once smoothing has done what it can, then
    // smoothing resumes on the new topology.
    if (opt_.cleanup && it > 0 && it % 3 == 0) {
      const std::size_t ops = st_.swaps + st_.splits + st_.collapses + st_.doublets;
      swap_pass();
      collapse_pass();
      doublet_pass();
      edge_pass();
      // New colours only where the topology changed (the operations woke
      // the vertices around them).
      colours_stale_ = st_.swaps + st_.splits + st_.collapses + st_.doublets != ops;
    }
    smooth_pass();
    climb_ = true;
    if (opt_.slide_boundary) slide_pass();
    st_.passes = it + 1;
    if (opt_.progress) opt_.progress(it + 1, passes);
  }
  if (opt_.cleanup && passes > 0) {
    swap_pass();
    doublet_pass();
  }
  compact();
}

} // namespace

void check_quad_mesh(const PlanarMesh& m, const std::string& path) { conforming_stars(m, path); }

SmoothStats smooth_quad_mesh(PlanarMesh& mesh, const SmoothOptions& opt) {
  const Stars stars = conforming_stars(mesh, {});
  SmoothStats st;
  st.before = quality_report(mesh);
  QuadImprover(mesh, opt, st).run(stars);
  st.after = quality_report(mesh);
  return st;
}

} // namespace imgmesh
