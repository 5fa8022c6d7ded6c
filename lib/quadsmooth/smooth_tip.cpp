// Beyond the thesis: a sharp corner of the curve held by two or three quads
// where its angle wants one (a 34-degree wedge tip in two quads: each of mu
// at most 8.5 degrees), re-meshed around. The pair's hexagon cannot do it
// where the wedge is thin (open_sharp_corner: the one quad keeping the tip
// wants a corner beyond the line between the tip's two side neighbours,
// and what is left of the wedge then has a reflex corner there): it needs
// a vertex more, not fewer. So the quads of the corner's fan and of the
// region's fans around their vertices (1 to 3 rings) are taken as patches
// (topological disks whose inner vertices are free), and a patch is
// re-quadded from its boundary polygon P = (c = p0, p1, ..., p(n-1)),
// counter-clockwise, around new inner points:
//
//   one point m, a fan: (p(2s-1), p(2s), p(2s+1), m) for s = 0 .. n/2 - 1,
//     or the same one vertex on; m of valence n / 2 (n >= 6);
//   a quad of four consecutive corners cut off by a diagonal, the rest a
//     fan around one point (n >= 8): the tip of a wedge too thin for a
//     free corner, in one quad of its own corners;
//   a chain of k = 2 .. 4 points, a strip: P cut at 2(k-1) of its edges
//     into arcs of even length, two opposite arcs (of at least two edges)
//     the fans of the chain's ends, the others of its middle points (left
//     side, then right side, possibly empty), each cut edge (pe, pe+1) a
//     bridge quad (pe, pe+1, y, x) between the points x and y of the arcs
//     before and after it: with c in the middle of an end's fan quad, the
//     strip of quads that follows a wedge's two sides to its tip
//     (doc/benchmarks-log.md, issue 16);
//   a ring of four points around their quad (m1, m2, m3, m4): P cut at four
//     edges, the bridges joining consecutive points;
//   no new point where P is a quad.
//
// Every layout is placed, relaxed and climbed (settle), whether c ends in
// one quad or not; the best whose quads are all strictly convex and whose
// patch's sorted sines rose (lex) is taken, judged on the quads around the
// largest patch. Fixed vertices never move nor go; only the patch's free
// inner vertices are removed.
//
// Then each quad under 10 degrees with a free corner: the stars of its
// free corners (one ring, then the stars of those quads' free corners) are
// patches too, cut along their diagonals into quads of their boundary's
// vertices (n <= 10), the same way judged: a strip between two curves too
// narrow for a point inside, whose free vertices made quads of three fixed
// corners where two quads across it from side to side hold 20-27 degrees
// (brain-kmeans z 30, 0.4 pixel wide at (93.7, 8): two quads of 9.33 and
// two of 9.4 -> 24.0 and 26.6).
#include "quadsmooth/smooth_mesh.hpp"

#include <algorithm>
#include <functional>

namespace imgmesh::quadsmooth_detail {

namespace {

// A layout's quads: ids >= 0 are mesh vertices, -1 - k the k-th new point.
using Layout = std::vector<Quad>;
// The most new points a layout has (a chain of them, or a ring of four).
constexpr int kMaxChain = 4;

bool contains(const std::vector<int>& v, int x) { return std::find(v.begin(), v.end(), x) != v.end(); }

// The quads around v reachable from quad q0 (holding v) by turning about v
// across edges that are not features: the region's fan of v (its whole
// star if v is free). Appended to out if not there.
void add_fan(const QuadMesh& qm, int v, int q0, std::vector<int>& out) {
  auto corner = [&](int q) {
    int i = 0;
    while (qm.quads[q][i] != v) ++i;
    return i;
  };
  if (!contains(out, q0)) out.push_back(q0);
  for (int q = q0, guard = 0; guard < 64; ++guard) {  // counter-clockwise across v-z
    const int z = qm.quads[q][(corner(q) + 3) & 3];
    const int nx = qm.is_feature(v, z) ? -1 : qm.quad_with_edge(v, z);
    if (nx < 0 || nx == q0) break;
    if (!contains(out, nx)) out.push_back(nx);
    q = nx;
  }
  for (int q = q0, guard = 0; guard < 64; ++guard) {  // clockwise across v-x
    const int x = qm.quads[q][(corner(q) + 1) & 3];
    const int nx = qm.is_feature(v, x) ? -1 : qm.quad_with_edge(x, v);
    if (nx < 0 || nx == q0) break;
    if (!contains(out, nx)) out.push_back(nx);
    q = nx;
  }
}

// The ways to cut the polygon R (counter-clockwise, an even number of
// corners) into quads along its diagonals: the quad on the edge (R0, R1)
// is (R0, R1, Ri, Rj), and R[1..i], R[i..j] and R[j..] + R0 (each an even
// polygon, or a side of the quad alone) are cut the same way.
std::vector<Layout> diagonal_cuts(const std::vector<int>& R) {
  const int m = int(R.size());
  if (m == 2) return {Layout{}};
  std::vector<Layout> out;
  for (int i = 2; i < m; i += 2)
    for (int j = i + 1; j < m; j += 2) {
      std::vector<int> C(R.begin() + j, R.end());
      C.push_back(R[0]);
      for (const Layout& a : diagonal_cuts({R.begin() + 1, R.begin() + i + 1}))
        for (const Layout& b : diagonal_cuts({R.begin() + i, R.begin() + j + 1}))
          for (const Layout& c : diagonal_cuts(C)) {
            Layout L{{R[0], R[1], R[i], R[j]}};
            L.insert(L.end(), a.begin(), a.end());
            L.insert(L.end(), b.begin(), b.end());
            L.insert(L.end(), c.begin(), c.end());
            out.push_back(std::move(L));
          }
    }
  return out;
}

// The layouts of the patch bounded by P, see the top.
std::vector<std::pair<Layout, int>> layouts(const std::vector<int>& P) {
  const int n = int(P.size());
  auto at = [&](int i) { return P[((i % n) + n) % n]; };
  std::vector<std::pair<Layout, int>> out;
  if (n == 4) out.push_back({{Quad{P[0], P[1], P[2], P[3]}}, 0});
  if (n >= 6)
    for (int parity = 0; parity < 2; ++parity) {
      Layout L;
      for (int s = 0; s < n / 2; ++s) L.push_back({at(2 * s - 1 + parity), at(2 * s + parity), at(2 * s + 1 + parity), -1});
      out.push_back({L, 1});
    }
  // (p(i), .., p(i+3)) cut off, the rest (p(i+3), .., p(i)) a fan.
  if (n >= 8)
    for (int i = 0; i < n; ++i)
      for (int parity = 0; parity < 2; ++parity) {
        Layout L{{at(i), at(i + 1), at(i + 2), at(i + 3)}};
        std::vector<int> R{at(i + 3)};
        for (int k = 4; k <= n; ++k) R.push_back(at(i + k));  // p(i+3), .., p(i+n) = p(i)
        const int m = int(R.size());
        for (int s = 0; s < m / 2; ++s)
          L.push_back({R[((2 * s - 1 + parity) % m + m) % m], R[(2 * s + parity) % m], R[(2 * s + 1 + parity) % m], -1});
        out.push_back({L, 1});
      }
  // A chain of k = K + 1 points: 2K bridge edges e[0] < ... < e[2K-1] of
  // P, the arcs between them of even length; the arc before e[s] is m1's
  // and the one K further is mk's (each at least two edges), the others
  // the middle points' (left side, then right side); the bridge at e[r]
  // joins its arc's point to the next arc's.
  for (int K = 1; K <= kMaxChain - 1; ++K) {
    std::vector<int> e(2 * K);
    auto emit = [&] {
      std::vector<int> len(2 * K), start(2 * K);  // arc r: from P[start] over len edges, up to e[r]
      for (int r = 0; r < 2 * K; ++r) {
        const int prev = e[(r + 2 * K - 1) % (2 * K)];
        start[r] = (prev + 1) % n;
        len[r] = ((e[r] - start[r]) % n + n) % n;
        if (len[r] % 2) return;
      }
      for (int s0 = 0; s0 < K; ++s0) {
        auto point = [&](int r) {  // -1 - (index of the arc's point in the chain)
          const int d = ((r - s0) % (2 * K) + 2 * K) % (2 * K);
          return -1 - (d <= K ? d : 2 * K - d);
        };
        if (len[s0] < 2 || len[s0 + K] < 2) continue;
        Layout L;
        for (int r = 0; r < 2 * K; ++r) {
          for (int t = 0; t < len[r]; t += 2) L.push_back({at(start[r] + t), at(start[r] + t + 1), at(start[r] + t + 2), point(r)});
          L.push_back({at(e[r]), at(e[r] + 1), point((r + 1) % (2 * K)), point(r)});
        }
        out.push_back({L, K + 1});
      }
    };
    // Every increasing choice of 2K edges.
    std::function<void(int, int)> pick = [&](int r, int from) {
      if (r == 2 * K) { emit(); return; }
      for (int x = from; x < n; ++x) { e[r] = x; pick(r + 1, x + 1); }
    };
    pick(0, 0);
  }
  // A ring of four points, their quad (m1, m2, m3, m4) inside: four bridge
  // edges e[0] < ... < e[3], the arcs between them of even length (an
  // empty one leaves its point in three quads), the arc before e[r] the
  // (r+1)-th point's.
  {
    int e[4];
    for (e[0] = 0; e[0] < n; ++e[0])
      for (e[1] = e[0] + 1; e[1] < n; ++e[1])
        for (e[2] = e[1] + 1; e[2] < n; ++e[2])
          for (e[3] = e[2] + 1; e[3] < n; ++e[3]) {
            int len[4], start[4];
            bool even = true;
            for (int r = 0; r < 4; ++r) {
              start[r] = (e[(r + 3) % 4] + 1) % n;
              len[r] = ((e[r] - start[r]) % n + n) % n;
              even = even && len[r] % 2 == 0;
            }
            if (!even) continue;
            Layout L{{-1, -2, -3, -4}};
            for (int r = 0; r < 4; ++r) {
              for (int t = 0; t < len[r]; t += 2) L.push_back({at(start[r] + t), at(start[r] + t + 1), at(start[r] + t + 2), -1 - r});
              L.push_back({at(e[r]), at(e[r] + 1), -1 - (r + 1) % 4, -1 - r});
            }
            out.push_back({L, 4});
          }
  }
  return out;
}

} // namespace

namespace {

// A patch around the tip c: its quads, its boundary P from c
// (counter-clockwise), its inner vertices (all free, their stars inside),
// and the count of its quads at each P[i].
struct TipPatch {
  std::vector<int> quads, P, inner, in_patch;
};

// c's fan holding q (two or three quads), then the region's fans of the
// patch's vertices, rings times; false if that is no disk with c on its
// boundary and free inner vertices, or too large.
bool patch_boundary(const QuadMesh& qm, int c, TipPatch& tp);

bool tip_patch(const QuadMesh& qm, int c, int q, int rings, TipPatch& tp) {
  std::vector<int>& patch = tp.quads;
  patch.clear();
  add_fan(qm, c, q, patch);
  if (patch.size() < 2 || patch.size() > 3) return false;
  for (int r = 0; r < rings; ++r) {
    const std::vector<int> now = patch;
    for (int p : now)
      for (int v : qm.quads[p]) add_fan(qm, v, p, patch);
  }
  return patch_boundary(qm, c, tp);
}

// tp.quads's boundary P from c (or from any of its vertices, c < 0) and
// its inner vertices; false if it is no disk with free inner vertices.
bool patch_boundary(const QuadMesh& qm, int c, TipPatch& tp) {
  const std::vector<int>& patch = tp.quads;
  constexpr std::size_t kMaxQuads = 32, kMaxBoundary = 14;
  if (patch.size() > kMaxQuads) return false;
  // Its boundary, counter-clockwise: the directed edges of its quads whose
  // twin is not in it; one simple loop through c, else it is no disk.
  std::vector<int> verts, from, to;
  for (int p : patch)
    for (int k = 0; k < 4; ++k) {
      const int a = qm.quads[p][k], b = qm.quads[p][(k + 1) & 3];
      if (!contains(verts, a)) verts.push_back(a);
      const int t = qm.quad_with_edge(b, a);
      if (t >= 0 && contains(patch, t)) continue;
      if (contains(from, a)) return false;  // the boundary touches itself at a
      from.push_back(a);
      to.push_back(b);
    }
  if (from.empty() || from.size() > kMaxBoundary) return false;
  if (c < 0) c = from[0];
  if (!contains(from, c)) return false;
  std::vector<int>& P = tp.P;
  P.assign(1, c);
  for (int x = c;;) {
    x = to[std::find(from.begin(), from.end(), x) - from.begin()];
    if (x == c) break;
    if (!contains(from, x) || P.size() > from.size()) return false;
    P.push_back(x);
  }
  if (P.size() != from.size() || P.size() % 2) return false;
  // The inner vertices go: each free, its whole star in the patch.
  tp.inner.clear();
  for (int v : verts) {
    if (contains(P, v)) continue;
    if (qm.fixed[v]) return false;
    for (int o : qm.vertex_quads[v])
      if (!contains(patch, o)) return false;
    tp.inner.push_back(v);
  }
  tp.in_patch.assign(P.size(), 0);
  for (std::size_t i = 0; i < P.size(); ++i)
    for (int o : qm.vertex_quads[P[i]]) tp.in_patch[i] += contains(patch, o);
  return true;
}

// Puts layout L (with `points` new points, at the centroids of their
// quads' other corners) in place of the patch tp, saved in pt first (its
// sorted sines in before); then settles. True if settle takes it; the
// caller rolls back either way or keeps it.
bool apply_layout(QuadMesh& qm, const TipPatch& tp, const Layout& L, int points, Patch& pt,
                  std::vector<double>& before) {
  std::vector<int> core = tp.P;
  core.insert(core.end(), tp.inner.begin(), tp.inner.end());
  qm.save_patch(core, pt);
  before = qm.patch_sines(pt);
  for (int p : tp.quads) {
    for (int x : qm.quads[p]) qm.remove_from(x, p);
    qm.quad_dead[p] = 1;
  }
  for (int v : tp.inner) {
    qm.vertex_dead[v] = 1;
    qm.vertex_quads[v].clear();
  }
  int m[kMaxChain] = {-1, -1, -1, -1};
  for (int k = 0; k < points; ++k) {
    Point2 s{0, 0};
    int cnt = 0;
    for (const Quad& Q : L)
      if (std::count(Q.begin(), Q.end(), -1 - k))
        for (int x : Q)
          if (x >= 0) { s[0] += qm.points[x][0]; s[1] += qm.points[x][1]; ++cnt; }
    m[k] = qm.add_vertex({s[0] / cnt, s[1] / cnt});
    pt.verts.push_back(m[k]);
  }
  for (std::size_t t = 0; t < L.size(); ++t) {
    int id;
    if (t < tp.quads.size()) id = tp.quads[t];
    else {
      id = qm.add_quad(tp.quads[0]);
      pt.quads.push_back(id);
    }
    Quad Q = L[t];
    for (int& x : Q)
      if (x < 0) x = m[-1 - x];
    qm.quad_dead[id] = 0;
    qm.set_quad(id, Q);
  }
  return settle(qm, pt, before);
}

} // namespace

bool requad_best(QuadMesh& qm, const std::vector<TipPatch>& patches,
                 const std::function<std::vector<std::pair<Layout, int>>(const std::vector<int>&)>& layouts);

bool open_wedge_tip(QuadMesh& qm, int c, int q, int max_rings) {
  if (!qm.fixed[c] || qm.vertex_dead[c] || qm.quad_dead[q]) return false;
  const Fan f = qm.fan(c, q);
  if (f.closed || f.count < 2 || f.count > 3 || f.ideal != 1) return false;
  // The patches of 1 .. max_rings rings (the valid, distinct ones).
  std::vector<TipPatch> patches;
  for (int r = 1; r <= max_rings; ++r) {
    TipPatch tp;
    if (tip_patch(qm, c, q, r, tp) && (patches.empty() || patches.back().quads.size() != tp.quads.size()))
      patches.push_back(std::move(tp));
  }
  return requad_best(qm, patches, layouts);
}

bool requad_best(QuadMesh& qm, const std::vector<TipPatch>& patches,
                 const std::function<std::vector<std::pair<Layout, int>>(const std::vector<int>&)>& layouts) {
  if (patches.empty()) return false;
  // The layouts of the patches are judged on one set: the quads around the
  // largest patch's vertices and their neighbours (every quad a smaller
  // patch's settling can change), and the quads a layout adds.
  std::vector<int> judge;
  {
    Patch all;
    std::vector<int> core = patches.back().P;
    core.insert(core.end(), patches.back().inner.begin(), patches.back().inner.end());
    qm.save_patch(core, all);
    judge = all.quads;
  }
  const std::size_t nquads = qm.quads.size();
  auto judged = [&] {
    std::vector<double> s;
    for (int o : judge)
      if (!qm.quad_dead[o]) s.push_back(qm.quad_sin_mu[o]);
    for (std::size_t o = nquads; o < qm.quads.size(); ++o) s.push_back(qm.quad_sin_mu[o]);
    std::sort(s.begin(), s.end());
    return s;
  };
  int best_patch = -1, best_layout = -1, best_points = 0;
  std::vector<double> best_sines;
  Patch pt;
  std::vector<double> before;
  std::vector<std::vector<std::pair<Layout, int>>> all(patches.size());
  for (std::size_t k = 0; k < patches.size(); ++k) {
    const TipPatch& tp = patches[k];
    all[k] = layouts(tp.P);
    for (std::size_t l = 0; l < all[k].size(); ++l) {
      const Layout& L = all[k][l].first;
      // Free boundary vertices left in fewer than three quads cannot be
      // strictly convex around (a doublet): such layouts are not tried.
      bool valences = true;
      for (std::size_t i = 0; i < tp.P.size() && valences; ++i) {
        int now = 0;
        for (const Quad& Q : L) now += std::count(Q.begin(), Q.end(), tp.P[i]) != 0;
        const int total = int(qm.vertex_quads[tp.P[i]].size()) - tp.in_patch[i] + now;
        if (now == 0 || (!qm.fixed[tp.P[i]] && total < 3)) valences = false;
      }
      if (!valences) continue;
      if (apply_layout(qm, tp, L, all[k][l].second, pt, before)) {
        std::vector<double> s = judged();
        if (best_patch < 0 || lex_better(s, best_sines)) {
          best_patch = int(k);
          best_layout = int(l);
          best_points = all[k][l].second;
          best_sines = std::move(s);
        }
      }
      qm.rollback(pt);
    }
  }
  if (best_patch < 0) return false;
  if (apply_layout(qm, patches[best_patch], all[best_patch][best_layout].first, best_points, pt, before)) return true;
  qm.rollback(pt);
  return false;
}

void tip_pass(QuadMesh& qm, SmoothStats& st) {
  constexpr double kBelow = 0.20791169081775931;  // sin(12 deg), as the final collapse's
  const int n = int(qm.points.size());  // the points a re-meshing adds are free
  for (int c = 0; c < n; ++c) {
    if (!qm.fixed[c] || qm.vertex_dead[c]) continue;
    const std::vector<int> around = qm.vertex_quads[c];
    for (int q : around)
      if (!qm.quad_dead[q] && qm.quad_sin_mu[q] < kBelow &&
          open_wedge_tip(qm, c, q, 3)) {
        ++st.wedge_tips;
        break;
      }
  }
  // Quads under 10 degrees with free corners: the stars of those (one and
  // two rings) cut along the patch's diagonals, no new point (counted with
  // the wedge tips).
  constexpr double kBar = 0.17364817766693033;  // sin(10 deg)
  for (int q = 0; q < int(qm.quads.size()); ++q) {
    if (qm.quad_dead[q] || qm.quad_sin_mu[q] >= kBar) continue;
    std::vector<TipPatch> patches;
    TipPatch tp;
    tp.quads = {q};
    for (int r = 0; r < 2; ++r) {
      const std::vector<int> now = tp.quads;
      for (int p : now)
        for (int v : qm.quads[p])
          if (!qm.fixed[v])
            for (int o : qm.vertex_quads[v])
              if (!contains(tp.quads, o)) tp.quads.push_back(o);
      if (tp.quads.size() > 1 && patch_boundary(qm, -1, tp)) patches.push_back(tp);
    }
    if (requad_best(qm, patches, [](const std::vector<int>& P) {
          std::vector<std::pair<Layout, int>> out;
          if (P.size() <= 10)
            for (Layout& L : diagonal_cuts(P)) out.push_back({std::move(L), 0});
          return out;
        }))
      ++st.wedge_tips;
  }
}

} // namespace imgmesh::quadsmooth_detail
