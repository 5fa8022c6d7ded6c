// --pair-above, beyond the thesis: pairs first, then the thesis's conversion
// around them.
//
//   candidate_pairs()      adjacent triangles whose quad has Joe's mu >= the
//                          threshold, best first, after those that keep a
//                          sharp input corner in one quad
//   merge_greedily()       each triangle in at most one merged quad
//   anchor_odd_groups()    merged quads that would take a Steiner point go
//                          back to the triangles (parity of the groups left)
//   convert_rest()         the conversion on the other triangles, with the
//                          merged quads as holes, until no hole edge is split
//   assemble()             its quads and points, then the merged quads
//
// Whenever a step cannot keep a guarantee, the plain conversion's result is
// returned instead.
#include "tri2quad/conversion.hpp"

#include "quad/quality.hpp"
#include "util/error.hpp"

#include <algorithm>
#include <cmath>
#include <unordered_set>

namespace imgmesh::tri2quad_detail {

namespace {

struct Pair {
  double mu;
  int t, u;                // the two triangles
  std::array<int, 4> q;    // the quad, counter-clockwise
  bool corner;             // keeps a sharp input corner whole
};

// A triangle alone in an input corner under this angle (both its edges
// there constraints or boundary) that the conversion split would leave two
// quads at the corner, each with mu at most a quarter of its angle; paired
// across the third edge, the corner's quad can reach half of it, the bar.
constexpr double kCosSharpCorner = 0.5;  // 60 degrees
// Unless the pair is nearly flat (mu under 1 degree): a Steiner point on a
// straight segment makes an angle within rounding of 180 degrees, which
// the exact predicates may call convex but no smoothing can open.
constexpr double kCornerPairMinMu = 1;

// The plain conversion, when pairs first cannot keep a guarantee.
Tri2QuadResult plain_conversion(const Tri2QuadInput& in, const Tri2QuadOptions& opt) {
  Tri2QuadResult r = convert(in, opt);
  r.cases.push_back({"pairs_first", 0});
  r.cases.push_back({"pairs_returned", 0});
  r.cases.push_back({"pairs_first_abandoned", 1});
  return r;
}

class PairsFirst {
public:
  // The plain conversion's set-up: its input checks (the same errors; the
  // remaining triangles alone might not show them), counter-clockwise
  // triangles, neighbours, constraint and boundary bits, segment markers,
  // and h.
  PairsFirst(const Tri2QuadInput& in, const Tri2QuadOptions& opt)
      : input(in), options(opt), mesh(in, opt, whole), triangle_count(in.triangles.size()),
        has_regions(in.region.size() == in.triangles.size()) {
    mesh.build_mesh();
    mesh.build_component_tree();
  }

  std::vector<Pair> candidate_pairs() const;
  void merge_greedily(const std::vector<Pair>& candidates);
  bool anchor_odd_groups();
  bool convert_rest(Tri2QuadResult& rest, std::unordered_set<std::uint64_t>& holes);
  Tri2QuadResult assemble(Tri2QuadResult rest, const std::unordered_set<std::uint64_t>& holes) const;

private:
  const Tri2QuadInput& input;
  const Tri2QuadOptions& options;
  Tri2QuadResult whole;
  Conversion mesh;
  const std::size_t triangle_count;
  const bool has_regions;
  std::vector<Pair> merged;
  std::vector<int> mate;  // index into merged, or -1
  std::size_t returned = 0;

  int across(int t, int j) const { return mesh.neighbours[std::size_t(t)][j]; }
  // A merged quad is still merged while its triangles name it as their mate.
  bool is_merged(std::size_t m) const { return mate[std::size_t(merged[m].t)] == int(m); }
  void return_to_triangles(int m) {
    ++returned;
    mate[std::size_t(merged[std::size_t(m)].t)] = mate[std::size_t(merged[std::size_t(m)].u)] = -1;
  }
  Tri2QuadInput remaining_input() const;
  std::unordered_set<std::uint64_t> hole_edges() const;
  bool return_quads_on_split_holes(const Tri2QuadResult& rest);
};

// Candidate pairs, best first (ties by triangle ids: deterministic).
std::vector<Pair> PairsFirst::candidate_pairs() const {
  const auto& T = mesh.triangles;
  const auto& nbr = mesh.neighbours;
  const std::size_t nt = triangle_count;
  // Constraint bits of interior edges only (constrained also marks the boundary).
  std::vector<std::uint8_t> conb(nt, 0);
  for (std::size_t t = 0; t < nt; ++t)
    for (int j = 0; j < 3; ++j)
      if ((mesh.constrained[t] >> j & 1) && nbr[t][j] >= 0) conb[t] |= std::uint8_t(1u << j);
  // Triangle t alone at an input corner under 60 degrees opposite its edge j.
  const auto sharp_opposite = [&](std::size_t t, int j) {
    const int k = (j + 1) % 3, l = (j + 2) % 3;
    if (!(mesh.constrained[t] >> k & 1) || !(mesh.constrained[t] >> l & 1)) return false;
    const Point2 &c = input.points[T[t][l]], &a = input.points[T[t][j]], &b = input.points[T[t][k]];
    const double ux = a[0] - c[0], uy = a[1] - c[1], vx = b[0] - c[0], vy = b[1] - c[1];
    return ux * vx + uy * vy > kCosSharpCorner * std::hypot(ux, uy) * std::hypot(vx, vy);
  };
  std::vector<Pair> cand;
  for (std::size_t t = 0; t < nt; ++t)
    for (int j = 0; j < 3; ++j) {
      const int a = T[t][j], b = T[t][(j + 1) % 3], c = T[t][(j + 2) % 3];
      const int u = nbr[t][j];
      if (u < int(t) || (conb[t] >> j & 1)) continue;  // once per edge; also skips the boundary (-1)
      if (has_regions && input.region[t] != input.region[std::size_t(u)]) continue;
      int x = -1;
      for (int m = 0; m < 3; ++m)
        if (T[u][m] != a && T[u][m] != b) x = T[u][m];
      const std::array<int, 4> q{a, x, b, c};
      const Point2 &pa = input.points[a], &px = input.points[x], &pb = input.points[b], &pc = input.points[c];
      if (!is_strictly_convex(pa, px, pb, pc)) continue;
      const double mu = joe_mu(pa, px, pb, pc);
      int ju = 0;  // u's slot of the shared edge
      while (nbr[u][ju] != int(t)) ++ju;
      const bool corner =
          mu >= kCornerPairMinMu && (sharp_opposite(t, j) || sharp_opposite(std::size_t(u), ju));
      if (corner || mu >= options.pair_above) cand.push_back({mu, int(t), u, q, corner});
    }
  std::stable_sort(cand.begin(), cand.end(),
                   [](const Pair& x, const Pair& y) { return x.corner != y.corner ? x.corner : x.mu > y.mu; });
  return cand;
}

void PairsFirst::merge_greedily(const std::vector<Pair>& candidates) {
  mate.assign(triangle_count, -1);
  for (const Pair& p : candidates)
    if (mate[p.t] < 0 && mate[p.u] < 0) {
      mate[p.t] = mate[p.u] = int(merged.size());
      merged.push_back(p);
    }
}

// A group of the other triangles (connected through any edge, as the
// conversion's T^c joins its components) with an odd count and no input
// boundary edge would put its leftover's point on a merged quad's edge
// (a group's boundary has as many edges as it has triangles, mod 2): the
// merged quads on a shortest path from it to an input boundary edge or to
// another group go back to the triangles. False when that does not settle.
bool PairsFirst::anchor_odd_groups() {
  const std::size_t nt = triangle_count;
  std::vector<int> group(nt), prev(nt, -2), members, start, queue, touched;
  for (int pass = 0;; ++pass) {
    if (pass == 64) return false;
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
      if (target < 0) return false;
      for (int t = target; prev[std::size_t(t)] != -1; t = prev[std::size_t(t)])
        if (mate[std::size_t(t)] >= 0) return_to_triangles(mate[std::size_t(t)]);
      for (int t : touched) prev[std::size_t(t)] = -2;
      changed = true;
    }
    if (!changed) return true;
  }
}

// The other triangles, with their constraint and boundary edges (each
// once, with its marker).
Tri2QuadInput PairsFirst::remaining_input() const {
  const auto& T = mesh.triangles;
  const auto& nbr = mesh.neighbours;
  Tri2QuadInput r;
  r.points = input.points;
  r.index_base = input.index_base;
  r.path = input.path;
  for (std::size_t t = 0; t < triangle_count; ++t) {
    if (mate[t] >= 0) continue;
    r.triangles.push_back(T[t]);
    if (has_regions) r.region.push_back(input.region[t]);
    for (int j = 0; j < 3; ++j) {
      const int u = nbr[t][j];
      if (!(mesh.constrained[t] >> j & 1) || (u > int(t) && mate[std::size_t(u)] < 0)) continue;
      const int a = T[t][j], b = T[t][(j + 1) % 3];
      r.constraints.push_back({a, b});
      r.constraint_markers.push_back(mesh.segments.at(edge_key(a, b)));
    }
  }
  return r;
}

// Hole edges: edges of a remaining triangle with a merged one across.
std::unordered_set<std::uint64_t> PairsFirst::hole_edges() const {
  const auto& T = mesh.triangles;
  const auto& nbr = mesh.neighbours;
  std::unordered_set<std::uint64_t> holes;
  for (std::size_t t = 0; t < triangle_count; ++t)
    if (mate[t] < 0)
      for (int j = 0; j < 3; ++j)
        if (nbr[t][j] >= 0 && mate[std::size_t(nbr[t][j])] >= 0) holes.insert(edge_key(T[t][j], T[t][(j + 1) % 3]));
  return holes;
}

// A hole edge must come out whole: a Steiner point on it would leave the
// merged quad a pentagon. Such quads go back to the triangles; true if any.
bool PairsFirst::return_quads_on_split_holes(const Tri2QuadResult& rest) {
  const auto& T = mesh.triangles;
  const auto& nbr = mesh.neighbours;
  std::unordered_set<std::uint64_t> kept;
  for (const auto& sg : rest.segments) kept.insert(edge_key(sg[0], sg[1]));
  bool conflict = false;
  for (std::size_t t = 0; t < triangle_count; ++t)
    if (mate[t] < 0)
      for (int j = 0; j < 3; ++j) {
        const int u = nbr[t][j];
        if (u >= 0 && mate[std::size_t(u)] >= 0 && !kept.count(edge_key(T[t][j], T[t][(j + 1) % 3]))) {
          return_to_triangles(mate[std::size_t(u)]);
          conflict = true;
        }
      }
  return conflict;
}

// The conversion of the remaining triangles, redone until it splits no
// hole edge; false when it does not settle or fails.
bool PairsFirst::convert_rest(Tri2QuadResult& rest, std::unordered_set<std::uint64_t>& holes) {
  for (int round = 0;; ++round) {
    if (round == 8) return false;
    const Tri2QuadInput r = remaining_input();
    if (r.triangles.empty()) {
      rest = Tri2QuadResult{};
      rest.points = input.points;
      for (int i = 0; i < kNumCases; ++i) rest.cases.push_back({kCaseNames[i], 0});
      rest.cases.push_back({"size_bound_retry", 0});
    }
    holes = hole_edges();
    if (!r.triangles.empty()) {
      try {
        rest = convert(r, options, &holes);
      } catch (const Error&) {
        return false;
      }
    }
    if (!return_quads_on_split_holes(rest)) return true;
  }
}

// The conversion's quads and points, then the merged quads.
Tri2QuadResult PairsFirst::assemble(Tri2QuadResult rest, const std::unordered_set<std::uint64_t>& holes) const {
  const auto& T = mesh.triangles;
  const auto& nbr = mesh.neighbours;
  Tri2QuadResult out = std::move(rest);
  out.allow_outside = options.allow_outside;
  out.input_points = input.points.size();
  out.triangles = triangle_count;
  out.components = whole.components;
  std::size_t pairs = 0;
  for (std::size_t m = 0; m < merged.size(); ++m) {
    if (!is_merged(m)) continue;
    ++pairs;
    out.quads.push_back(merged[m].q);
    if (has_regions) out.region.push_back(input.region[std::size_t(merged[m].t)]);
  }
  // Segments: the conversion's, without the hole edges (unless they are
  // constraints), and the merged quads' edges on a constraint or on the
  // input boundary (mesh.segments, with their markers).
  std::vector<std::pair<std::uint64_t, int>> segs;
  for (std::size_t k = 0; k < out.segments.size(); ++k) {
    const std::uint64_t kk = edge_key(out.segments[k][0], out.segments[k][1]);
    if (holes.count(kk) && !mesh.segments.count(kk)) continue;
    segs.push_back({kk, out.segment_markers[k]});
  }
  for (std::size_t m = 0; m < merged.size(); ++m) {
    if (!is_merged(m)) continue;
    for (const int t : {merged[m].t, merged[m].u})
      for (int j = 0; j < 3; ++j) {
        const int u = nbr[std::size_t(t)][j];
        if (u == merged[m].t || u == merged[m].u) continue;  // the merged diagonal
        const std::uint64_t kk = edge_key(T[std::size_t(t)][j], T[std::size_t(t)][(j + 1) % 3]);
        const auto c = mesh.segments.find(kk);  // constraints and boundary
        if (c != mesh.segments.end()) segs.push_back({kk, c->second});
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
  return out;
}

} // namespace

// If the conversion around the merged quads does not settle, or the result
// exceeds the thesis's size bounds (of the whole mesh), the plain
// conversion's result is returned.
Tri2QuadResult pairs_first(const Tri2QuadInput& in, const Tri2QuadOptions& opt) {
  PairsFirst pf(in, opt);
  pf.merge_greedily(pf.candidate_pairs());
  if (!pf.anchor_odd_groups()) return plain_conversion(in, opt);
  Tri2QuadResult rest;
  std::unordered_set<std::uint64_t> holes;
  if (!pf.convert_rest(rest, holes)) return plain_conversion(in, opt);
  Tri2QuadResult out = pf.assemble(std::move(rest), holes);
  if (out.quads.size() > out.quad_bound() || out.steiner > out.steiner_bound(opt.allow_outside))
    return plain_conversion(in, opt);
  return out;
}

} // namespace imgmesh::tri2quad_detail
