// --pair-above: pairs first, then the thesis's conversion around them.
#include "quad/tri2quad_conversion.hpp"

#include "quad/quality.hpp"
#include "util/error.hpp"

#include <algorithm>
#include <unordered_set>

namespace imgmesh::t2q {

// Pairs first (--pair-above): adjacent triangles that make a quad of Joe's
// mu >= the threshold are merged greedily, best first; the thesis's
// conversion then runs on the other triangles, with the merged quads as
// holes. A merged quad on whose edge it puts a Steiner point goes back to
// the triangles and the conversion runs again. If that does not settle, or
// the result exceeds the thesis's size bounds (of the whole mesh), the plain
// conversion's result is returned.
Tri2QuadResult pairs_first(const Tri2QuadInput& in, const Tri2QuadOptions& opt) {
  const std::size_t nt = in.triangles.size();
  const std::size_t np = in.points.size();
  // The plain conversion, when pairs first cannot keep a guarantee.
  auto plain = [&] {
    Tri2QuadResult r = convert(in, opt);
    r.cases.push_back({"pairs_first", 0});
    r.cases.push_back({"pairs_returned", 0});
    r.cases.push_back({"pairs_first_abandoned", 1});
    return r;
  };
  // The plain conversion's set-up: its input checks (the same errors; the
  // remaining triangles alone might not show them), counter-clockwise
  // triangles T, neighbours nb, constraint and boundary bits con, segment
  // markers segs, and h.
  Tri2QuadResult whole;
  Conversion cv(in, opt, whole);
  cv.build_mesh();
  cv.build_component_tree();
  const auto& T = cv.triangles;
  const auto& nbr = cv.neighbours;
  const std::size_t h = whole.components;
  // Constraint bits of interior edges only (con also marks the boundary).
  std::vector<std::uint8_t> conb(nt, 0);
  for (std::size_t t = 0; t < nt; ++t)
    for (int j = 0; j < 3; ++j)
      if ((cv.constrained[t] >> j & 1) && nbr[t][j] >= 0) conb[t] |= std::uint8_t(1u << j);
  const bool has_attr = in.region.size() == nt;
  // Candidate pairs, best first (ties by triangle ids: deterministic).
  struct Pair { double mu; int t, u; std::array<int, 4> q; };
  std::vector<Pair> cand;
  for (std::size_t t = 0; t < nt; ++t)
    for (int j = 0; j < 3; ++j) {
      const int a = T[t][j], b = T[t][(j + 1) % 3], c = T[t][(j + 2) % 3];
      const int u = nbr[t][j];
      if (u < int(t) || (conb[t] >> j & 1)) continue;  // once per edge; also skips the boundary (-1)
      if (has_attr && in.region[t] != in.region[std::size_t(u)]) continue;
      int x = -1;
      for (int m = 0; m < 3; ++m)
        if (T[u][m] != a && T[u][m] != b) x = T[u][m];
      const std::array<int, 4> q{a, x, b, c};
      const Point2 &pa = in.points[a], &px = in.points[x], &pb = in.points[b], &pc = in.points[c];
      if (!is_strictly_convex(pa, px, pb, pc)) continue;
      const double mu = joe_mu(pa, px, pb, pc);
      if (mu >= opt.pair_above) cand.push_back({mu, int(t), u, q});
    }
  std::stable_sort(cand.begin(), cand.end(), [](const Pair& x, const Pair& y) { return x.mu > y.mu; });
  std::vector<int> mate(nt, -1);  // index into merged, or -1
  std::vector<Pair> merged;
  for (const Pair& p : cand)
    if (mate[p.t] < 0 && mate[p.u] < 0) {
      mate[p.t] = mate[p.u] = int(merged.size());
      merged.push_back(p);
    }
  // A merged quad is still merged while its triangles name it as their mate.
  auto alive = [&](std::size_t m) { return mate[std::size_t(merged[m].t)] == int(m); };
  std::size_t returned = 0;
  auto unmerge = [&](int m) {
    ++returned;
    mate[std::size_t(merged[std::size_t(m)].t)] = mate[std::size_t(merged[std::size_t(m)].u)] = -1;
  };
  auto across = [&](int t, int j) { return nbr[std::size_t(t)][j]; };
  // A group of the other triangles (connected through any edge, as the
  // conversion's T^c joins its components) with an odd count and no input
  // boundary edge would put its leftover's point on a merged quad's edge
  // (a group's boundary has as many edges as it has triangles, mod 2): the
  // merged quads on a shortest path from it to an input boundary edge or to
  // another group go back to the triangles.
  {
    std::vector<int> group(nt), prev(nt, -2), members, start, queue, touched;
    for (int pass = 0;; ++pass) {
      if (pass == 64) return plain();
      std::fill(group.begin(), group.end(), -1);
      members.clear();
      start.clear();
      std::vector<char> needs;
      for (std::size_t s0 = 0; s0 < nt; ++s0) {
        if (mate[s0] >= 0 || group[s0] >= 0) continue;
        const int c = int(start.size());
        start.push_back(int(members.size()));
        group[s0] = c;
        members.push_back(int(s0));
        bool anchored = false;
        for (std::size_t i = std::size_t(start.back()); i < members.size(); ++i) {
          const int t = members[i];
          for (int j = 0; j < 3; ++j) {
            const int u = across(t, j);
            if (u < 0) anchored = true;
            else if (mate[std::size_t(u)] < 0 && group[std::size_t(u)] < 0) { group[std::size_t(u)] = c; members.push_back(u); }
          }
        }
        needs.push_back(!anchored && (members.size() - std::size_t(start.back())) % 2 == 1);
      }
      start.push_back(int(members.size()));
      bool changed = false;
      for (std::size_t c = 0; c < needs.size(); ++c) {
        if (!needs[c]) continue;
        queue.assign(members.begin() + start[c], members.begin() + start[c + 1]);
        for (int t : queue) prev[std::size_t(t)] = -1;
        touched = queue;
        int target = -1;
        for (std::size_t i = 0; i < queue.size() && target < 0; ++i) {
          const int t = queue[i];
          for (int j = 0; j < 3 && target < 0; ++j) {
            const int u = across(t, j);
            if (u < 0 || prev[std::size_t(u)] != -2) continue;
            prev[std::size_t(u)] = t;
            touched.push_back(u);
            if (mate[std::size_t(u)] < 0) { target = u; break; }  // another group
            for (int k = 0; k < 3; ++k)
              if (across(u, k) < 0) target = u;  // an input boundary edge
            queue.push_back(u);
          }
        }
        if (target < 0) return plain();
        for (int t = target; prev[std::size_t(t)] != -1; t = prev[std::size_t(t)])
          if (mate[std::size_t(t)] >= 0) unmerge(mate[std::size_t(t)]);
        for (int t : touched) prev[std::size_t(t)] = -2;
        changed = true;
      }
      if (!changed) break;
    }
  }

  // Hole edges: edges of a remaining triangle with a merged one across.
  std::unordered_set<std::uint64_t> holes;
  Tri2QuadResult rest;
  for (int round = 0;; ++round) {
    if (round == 8) return plain();
    // The other triangles, with their constraint and boundary edges (each
    // once, with its marker).
    Tri2QuadInput r;
    r.points = in.points;
    r.index_base = in.index_base;
    r.path = in.path;
    for (std::size_t t = 0; t < nt; ++t) {
      if (mate[t] >= 0) continue;
      r.triangles.push_back(T[t]);
      if (has_attr) r.region.push_back(in.region[t]);
      for (int j = 0; j < 3; ++j) {
        const int u = nbr[t][j];
        if (!(cv.constrained[t] >> j & 1) || (u > int(t) && mate[std::size_t(u)] < 0)) continue;
        const int a = T[t][j], b = T[t][(j + 1) % 3];
        r.constraints.push_back({a, b});
        r.constraint_markers.push_back(cv.segments.at(edge_key(a, b)));
      }
    }
    if (r.triangles.empty()) {
      rest = Tri2QuadResult{};
      rest.points = in.points;
      for (int i = 0; i < kNumCases; ++i) rest.cases.push_back({kCaseNames[i], 0});
      rest.cases.push_back({"size_bound_retry", 0});
    }
    holes.clear();
    for (std::size_t t = 0; t < nt; ++t)
      if (mate[t] < 0)
        for (int j = 0; j < 3; ++j)
          if (nbr[t][j] >= 0 && mate[std::size_t(nbr[t][j])] >= 0) holes.insert(edge_key(T[t][j], T[t][(j + 1) % 3]));
    if (!r.triangles.empty()) {
      try {
        rest = convert(r, opt, &holes);
      } catch (const Error&) {
        return plain();
      }
    }
    // A hole edge must come out whole: a Steiner point on it would leave
    // the merged quad a pentagon. Such quads go back to the triangles.
    std::unordered_set<std::uint64_t> kept;
    for (const auto& sg : rest.segments) kept.insert(edge_key(sg[0], sg[1]));
    bool conflict = false;
    for (std::size_t t = 0; t < nt; ++t)
      if (mate[t] < 0)
        for (int j = 0; j < 3; ++j) {
          const int u = nbr[t][j];
          if (u >= 0 && mate[std::size_t(u)] >= 0 && !kept.count(edge_key(T[t][j], T[t][(j + 1) % 3]))) {
            unmerge(mate[std::size_t(u)]);
            conflict = true;
          }
        }
    if (!conflict) break;
  }
  // Assemble: the conversion's quads and points, then the merged quads.
  Tri2QuadResult out = std::move(rest);
  out.allow_outside = opt.allow_outside;
  out.input_points = np;
  out.triangles = nt;
  out.components = h;
  std::size_t pairs = 0;
  for (std::size_t m = 0; m < merged.size(); ++m) {
    if (!alive(m)) continue;
    ++pairs;
    out.quads.push_back(merged[m].q);
    if (has_attr) out.region.push_back(in.region[std::size_t(merged[m].t)]);
  }
  // Segments: the conversion's, without the hole edges (unless they are
  // constraints), and the merged quads' edges on a constraint or on the
  // input boundary (cv.segments, with their markers).
  std::vector<std::pair<std::uint64_t, int>> segs;
  for (std::size_t k = 0; k < out.segments.size(); ++k) {
    const std::uint64_t kk = edge_key(out.segments[k][0], out.segments[k][1]);
    if (holes.count(kk) && !cv.segments.count(kk)) continue;
    segs.push_back({kk, out.segment_markers[k]});
  }
  for (std::size_t m = 0; m < merged.size(); ++m) {
    if (!alive(m)) continue;
    for (const int t : {merged[m].t, merged[m].u})
      for (int j = 0; j < 3; ++j) {
        const int u = nbr[std::size_t(t)][j];
        if (u == merged[m].t || u == merged[m].u) continue;  // the merged diagonal
        const std::uint64_t kk = edge_key(T[std::size_t(t)][j], T[std::size_t(t)][(j + 1) % 3]);
        const auto c = cv.segments.find(kk);  // constraints and boundary
        if (c != cv.segments.end()) segs.push_back({kk, c->second});
      }
  }
  std::sort(segs.begin(), segs.end());
  segs.erase(std::unique(segs.begin(), segs.end(), [](const auto& x, const auto& y) { return x.first == y.first; }), segs.end());
  out.segments.clear();
  out.segment_markers.clear();
  for (const auto& [k, m] : segs) {
    out.segments.push_back({int(k >> 32), int(k & 0xffffffffu)});
    out.segment_markers.push_back(m);
  }
  out.cases.push_back({"pairs_first", pairs});
  out.cases.push_back({"pairs_returned", returned});
  out.cases.push_back({"pairs_first_abandoned", 0});
  if (out.quads.size() > out.quad_bound() || out.steiner > out.steiner_bound(opt.allow_outside)) return plain();
  return out;
}

} // namespace imgmesh::t2q
