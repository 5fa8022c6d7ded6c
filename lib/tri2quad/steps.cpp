// Steps 1-5 of thesis 3.2.1 at one node of a component's spanning tree: the
// node's triangle with what its children left forms a small polygon, which
// the lemmas of appendix B (polygons.cpp) quadrangulate, leaving
// at most a triangle (or a point, a dent) on the node's outgoing edge; at
// the root, step 5 closes what is left.
#include "tri2quad/conversion.hpp"

#include "quad/quality.hpp"
#include "util/error.hpp"

#include <algorithm>

namespace imgmesh::tri2quad_detail {

// Node u with outgoing edge (a, b): its triangle and its children's
// leftovers form a polygon, closed by steps 1-4 (step 5 at the root), on a
// second attempt after dents, or by the safe split.
void Conversion::process_node(int u, bool is_root) {
  const int s0 = parent_slot[u];
  const int a = triangles[u][s0], b = triangles[u][(s0 + 1) % 3], c = triangles[u][(s0 + 2) % 3];
  for (int attempt = 0;; ++attempt) {
    Child child[2];
    node_polygon(u, s0, child);
    if (!is_root && small_node(u, c)) return;
    const bool pinched = is_pinched();
    LocalPatch& lp = scratch_patch;
    lp.p.clear();
    lp.gid.clear();
    lp.quads.clear();
    for (int v : scratch_boundary) lp.add_known(points[v], v);
    for (int v : scratch_inner) lp.add_known(points[v], v);
    const double at = attribute[u];
    Leftover r;
    int split_m = -1;  // local id of a point put on the root edge
    const Closing closing = pinched ? Closing::kOpen : close_polygon(u, is_root, child, lp, r, split_m);
    if (closing == Closing::kPassedUp) return;
    if (closing == Closing::kOpen && attempt == 0 && make_dents(u, s0)) continue;
    if (closing == Closing::kOpen) {
      lp.p.clear();
      lp.gid.clear();
      lp.quads.clear();
      r = safe_split(lp, scratch_triangles, is_root, &split_m);
    }
    r = commit_region(lp, r, at, &split_m);  // split_m: a point put on the root edge
    if (is_root) finish_root(u, a, b, r, at, split_m);
    else leftover[u] = r;
    return;
  }
}

// The polygon of node u (outgoing edge in slot s0): the boundary from its
// outgoing edge (a, b, ..., c, ...) with the vertices inside it, and its
// triangles (its own first, split at a child's dent, then the children's).
void Conversion::node_polygon(int u, int s0, Child* child) {
  const int a = triangles[u][s0], b = triangles[u][(s0 + 1) % 3], c = triangles[u][(s0 + 2) % 3];
  std::vector<int>& boundary = scratch_boundary;
  std::vector<int>& inner = scratch_inner;
  std::vector<std::array<int, 3>>& tris = scratch_triangles;
  std::vector<std::array<int, 3>>& kids = scratch_child_triangles;
  boundary.assign({a, b});
  inner.clear();
  tris.assign({{a, b, c}});
  kids.clear();
  for (int k = 1; k <= 2; ++k) {
    const int j = (s0 + k) % 3;
    const int w = neighbours[u][j];
    if (k == 2) boundary.push_back(c);
    if (w < 0 || (constrained[u] >> j & 1) || parent[w] != u) continue;
    const int p = triangles[u][(j + 1) % 3], q = triangles[u][j];  // child's outgoing edge (p, q)
    child[k - 1] = {leftover[w], p, q};
    leftover_boundary(leftover[w], boundary, inner);
    if (leftover[w].type == kLeftoverDent) split_own(tris, q, p, leftover[w].x);
    else leftover_triangles(leftover[w], p, q, kids);
  }
  tris.insert(tris.end(), kids.begin(), kids.end());
  // Close "x, c, x" (a vertex surrounded by the region: Fig. 3.6).
  bool changed = true;
  while (changed && boundary.size() >= 4) {
    changed = false;
    const std::size_t n = boundary.size();
    for (std::size_t i = 0; i < n; ++i) {
      if (boundary[(i + n - 1) % n] == boundary[(i + 1) % n] && i != 0 && i != 1 && (i + 1) % n != 0 &&
          (i + 1) % n != 1) {
        inner.push_back(boundary[i]);
        const std::size_t j = (i + 1) % n;
        if (j > i) { boundary.erase(boundary.begin() + j); boundary.erase(boundary.begin() + i); }
        else { boundary.erase(boundary.begin() + i); boundary.erase(boundary.begin() + j); }
        changed = true;
        break;
      }
    }
  }
}

// Fast paths for the two commonest nodes below the root (no pinch is
// possible with fewer than five boundary vertices): a lone triangle waits
// for its parent, a pair is a convex quad (the 4(c) shortcut) or goes to
// the grandparent. False when the node is neither.
bool Conversion::small_node(int u, int c) {
  const std::vector<int>& boundary = scratch_boundary;
  if (!scratch_inner.empty()) return false;
  if (boundary.size() == 3) {
    leftover[u] = {kLeftoverTriangle, 0, c, -1};
    return true;
  }
  if (boundary.size() != 4 || scratch_triangles.size() != 2) return false;
  const int* q = boundary.data();
  if (!options.convexity_test || good_quad(points[q[0]], points[q[1]], points[q[2]], points[q[3]])) {
    result.quads.push_back({q[0], q[1], q[2], q[3]});
    if (has_regions) result.region.push_back(attribute[u]);
    ++case_counts[kQuadConvex];
    leftover[u] = {};
  } else {
    ++case_counts[kQuadPassedUp];
    leftover[u] = {kLeftoverQuad, std::uint8_t(q[3] == c ? 0 : 1), q[2], q[3]};
  }
  return true;
}

// A vertex twice on the polygon's boundary or inside it: the polygon
// touches itself, and only the fallbacks handle it.
bool Conversion::is_pinched() {
  std::vector<int>& s = scratch_sorted;
  s.assign(scratch_boundary.begin(), scratch_boundary.end());
  s.insert(s.end(), scratch_inner.begin(), scratch_inner.end());
  std::sort(s.begin(), s.end());
  return std::adjacent_find(s.begin(), s.end()) != s.end();
}

// Steps 1-5 on the node's polygon (local ids: the boundary from 0, then the
// inner vertices), by its number of boundary and inner vertices and by what
// its children left: kClosed with lp's quads and the leftover r, kPassedUp
// when the whole region goes to the parent (leftover[u] set), else kOpen.
Conversion::Closing Conversion::close_polygon(int u, bool is_root, const Child* child, LocalPatch& lp,
                                              Leftover& r, int& split_m) {
  const int s0 = parent_slot[u];
  const int a = triangles[u][s0], b = triangles[u][(s0 + 1) % 3], c = triangles[u][(s0 + 2) % 3];
  const std::vector<int>& boundary = scratch_boundary;
  const std::size_t nb_ = boundary.size(), ni = scratch_inner.size();
  bool done = false;
  if (nb_ == 3 && ni == 0) {  // the root alone (small_node() took the others)
    r = {kLeftoverTriangle, 0, 2, -1};  // local id of c
    done = true;
  } else if (nb_ == 4 && ni == 0) {  // the root or a pair with a dent
    if (!options.convexity_test || good_quad(lp.p[0], lp.p[1], lp.p[2], lp.p[3])) {
      lp.quads.push_back({0, 1, 2, 3});
      ++case_counts[kQuadConvex];
      r = {};
      done = true;
    } else if (quad_nested_free(lp, {0, 1, 2, 3})) {
      ++case_counts[kRootNested];
      r = {};
      done = true;
    }
  } else if (nb_ == 5 && ni == 0 && is_root && !(options.allow_outside && component_parent[component[u]] < 0)) {
    // At the root the outgoing edge may take a point (as the thesis's
    // type 3 does): the hexagon (a, m, b, ...) by B.1.1 closes the
    // pentagon with at most 5 quads and 4 points, where a leftover
    // triangle plus Joe's split would cost at least 6 quads and 5 points.
    done = pentagon_edge_point(lp, r, a, b, c, is_root, split_m, 3) || pentagon_leaving_triangle(lp, r, 3);
  } else if (nb_ == 5 && ni == 0) {
    // B.2.1 within its budget (3 quads, 2 points for the 2 triangles
    // eliminated), else type 3: the point on the outgoing edge and B.1.1
    // with at most 2 more (4 quads, 3 points for 3 triangles).
    done = pentagon_leaving_triangle(lp, r, 1) || pentagon_edge_point(lp, r, a, b, c, is_root, split_m, 2) ||
           pentagon_leaving_triangle(lp, r, 3);
  } else if (nb_ == 6 && ni == 0) {
    if (hexagon(lp, {0, 1, 2, 3, 4, 5})) { ++case_counts[kHexagon]; r = {}; done = true; }
  } else if (nb_ == 7 && ni == 0) {
    done = close_heptagon(lp, r, a, b, c, is_root, split_m);
  } else if (nb_ == 3 && ni == 1) {
    // Non-empty triangle (a, b, w) around I (Fig. 3.6): it goes up to
    // the parent (a quad plus a leftover triangle is impossible here:
    // the remainder would be reflex at I).
    if (!is_root && scratch_triangles.size() == 3) {
      ++case_counts[kNonEmptyTriangle];
      leftover[u] = {kLeftoverNonEmpty, 0, boundary[2], scratch_inner[0]};
      return Closing::kPassedUp;
    } else if (is_root) {
      // Step 5(a) without an outside point: a point on the root edge
      // makes the quad (a, m, b, w) around I (B.1.2, flat corner at m).
      const auto mk = lp.mark();
      const int m = lp.add_new({0.5 * (points[a][0] + points[b][0]), 0.5 * (points[a][1] + points[b][1])});
      if (quad_with_point(lp, {0, m, 1, 2}, 3)) {
        ++case_counts[kQuadPoint];
        split_m = m;
        r = {};
        done = true;
      } else {
        lp.rollback(mk);
      }
    }
  } else if (nb_ == 4 && ni == 1) {
    if (quad_with_point(lp, {0, 1, 2, 3}, 4)) { ++case_counts[kQuadPoint]; r = {}; done = true; }
  } else if (nb_ == 5 && ni == 1) {
    done = pentagon_point(lp, r);
  } else if (nb_ == 3 && ni == 2) {
    done = triangle_two_points(lp, c, r);
  }
  const auto t0 = child[0].leftover.type, t1 = child[1].leftover.type;
  if (!done && ((t0 == kLeftoverQuad && t1 == kLeftoverNonEmpty) || (t0 == kLeftoverNonEmpty && t1 == kLeftoverQuad)))
    done = (nb_ == 6 && ni == 1 && hexagon_point(lp, r)) || pair_and_nonempty(lp, child, a, b, c, r);
  if (!done && t0 == kLeftoverNonEmpty && t1 == kLeftoverNonEmpty)
    done = two_nonempty(lp, child, a, b, c, is_root, r, split_m);
  return done ? Closing::kClosed : Closing::kOpen;
}

// B.2.1: a pentagon becomes quads plus a triangle passed up (its apex).
bool Conversion::pentagon_leaving_triangle(LocalPatch& lp, Leftover& r, int hexagon_budget) {
  int kind = 0;
  const int apex = pentagon(lp, {0, 1, 2, 3, 4}, &kind, hexagon_budget);
  if (apex < 0) return false;
  ++case_counts[kind == 0 ? kPentagonEar : kind == 1 ? kPentagonType1 : kind == 2 ? kPentagonType2 : kPentagonType3];
  r = {kLeftoverTriangle, 0, apex, -1};
  return true;
}

// B.2.1 type 3 (4(c)(ii)): a point m on the outgoing edge, B.1.1 on the
// hexagon (a, m, b, ...); below the root m goes to the parent.
bool Conversion::pentagon_edge_point(LocalPatch& lp, Leftover& r, int a, int b, int c, bool is_root, int& split_m,
                                     int hexagon_budget) {
  const auto m0 = lp.mark();
  for (const P2& x : edge_points(a, b, c, is_root)) {
    const int m = lp.add_new(x);
    if (hexagon(lp, {0, m, 1, 2, 3, 4}, hexagon_budget)) {
      if (is_root) { ++case_counts[kRootPentagonEdge]; split_m = m; r = {}; }
      else { ++case_counts[kPentagonType3Edge]; r = {kLeftoverDent, 0, m, -1}; }
      return true;
    }
    lp.rollback(m0);
  }
  return false;
}

// Triangles of a child's region attached to its outgoing edge (p, q).
void Conversion::leftover_triangles(const Leftover& r, int p, int q, std::vector<std::array<int, 3>>& tris) {
  switch (r.type) {
    case kNoLeftover: break;
    case kLeftoverTriangle: tris.push_back({p, q, r.x}); break;
    case kLeftoverQuad:
      if (r.diagonal == 0) { tris.push_back({p, q, r.y}); tris.push_back({r.y, q, r.x}); }
      else { tris.push_back({p, q, r.x}); tris.push_back({p, r.x, r.y}); }
      break;
    case kLeftoverNonEmpty:
      tris.push_back({p, q, r.y}); tris.push_back({r.y, q, r.x}); tris.push_back({p, r.y, r.x});
      break;
    case kLeftoverDent: break;
  }
}

void Conversion::leftover_boundary(const Leftover& r, std::vector<int>& b, std::vector<int>& inner) {
  switch (r.type) {
    case kNoLeftover: break;
    case kLeftoverTriangle: b.push_back(r.x); break;
    case kLeftoverQuad: b.push_back(r.x); b.push_back(r.y); break;
    case kLeftoverNonEmpty: b.push_back(r.x); inner.push_back(r.y); break;
    case kLeftoverDent: b.push_back(r.x); break;
  }
}

int Conversion::local_of(const LocalPatch& lp, int g) {
  for (std::size_t i = 0; i < lp.gid.size(); ++i)
    if (lp.gid[i] == g) return int(i);
  return -1;
}

// Split the node's own triangle that has the edge (p, q) at the dent m.
void Conversion::split_own(std::vector<std::array<int, 3>>& tris, int p, int q, int m) {
  for (std::size_t i = 0; i < tris.size(); ++i)
    for (int k = 0; k < 3; ++k)
      if (tris[i][k] == p && tris[i][(k + 1) % 3] == q) {
        const int r = tris[i][(k + 2) % 3];
        tris[i] = {p, m, r};
        tris.push_back({m, q, r});
        return;
      }
}

// Commit a patch whose returned region refers to local ids.
Leftover Conversion::commit_region(LocalPatch& lp, Leftover r, double a, int* local_to_global) {
  std::vector<int>& id = scratch_ids;
  id.resize(lp.p.size());
  for (std::size_t i = 0; i < lp.p.size(); ++i) {
    if (lp.gid[i] >= 0) { id[i] = lp.gid[i]; continue; }
    id[i] = int(points.size());
    points.push_back(lp.p[i]);
    ++result.steiner;
  }
  for (const auto& q : lp.quads) {
    result.quads.push_back({id[q[0]], id[q[1]], id[q[2]], id[q[3]]});
    if (has_regions) result.region.push_back(a);
  }
  if (r.x >= 0) r.x = id[r.x];
  if (r.y >= 0) r.y = id[r.y];
  if (local_to_global && *local_to_global >= 0) *local_to_global = id[*local_to_global];
  return r;
}

// Where a node closes with a point m on its outgoing edge (a, b): on the
// edge at the root; below it leaning a little into this node, so that
// the parent's triangle with m is a convex quadrilateral (the
// perturbation of step 1), or on the edge if that is all that works.
std::vector<P2> Conversion::edge_points(int a, int b, int c, bool is_root) const {
  const P2 mid = {0.5 * (points[a][0] + points[b][0]), 0.5 * (points[a][1] + points[b][1])};
  std::vector<P2> candidates;
  if (!is_root)
    for (double f : {0.03, 0.01}) candidates.push_back({mid[0] + f * (points[c][0] - mid[0]), mid[1] + f * (points[c][1] - mid[1])});
  candidates.push_back(mid);
  return candidates;
}

// 4(c)(v)(f), B.3.1: the heptagon (ring 0..6, local ids; apex 4 is c)
// leaves a triangle on the outgoing edge (6 quads, 4 points for 4
// triangles), or closes with a point m on that edge (7 quads, 5 points
// for 5 triangles; the parent gets m as a degenerate quadrilateral). At
// the root the closed form comes first: it costs less than a leftover
// triangle and step 5.
bool Conversion::close_heptagon(LocalPatch& lp, Leftover& r, int a, int b, int c, bool is_root, int& split_m) {
  const Ring v = {0, 1, 2, 3, 4, 5, 6};
  auto leave_triangle = [&] {
    const int apex = heptagon(lp, v);
    if (apex < 0) return false;
    ++case_counts[kHeptagon];
    r = {kLeftoverTriangle, 0, apex, -1};
    return true;
  };
  if (!is_root && leave_triangle()) return true;
  const auto m0 = lp.mark();
  for (const P2& x : edge_points(a, b, c, is_root)) {
    const int m = lp.add_new(x);
    if (heptagon_closed(lp, v, m)) {
      ++case_counts[kHeptagonClosed];
      if (is_root) { split_m = m; r = {}; }
      else r = {kLeftoverDent, 0, m, -1};
      return true;
    }
    lp.rollback(m0);
  }
  return is_root && leave_triangle();
}

bool Conversion::pentagon_point(LocalPatch& lp, Leftover& r) {
  // B.2.2: pentagon 0..4 with the point 5.
  const auto m = lp.mark();
  // (i) leftover (v0, v1, q), hexagon (v1, v2, v3, v4, v0, q).
  if (good_triangle(lp.p[0], lp.p[1], lp.p[5])) {
    std::vector<P2> hp = {lp.p[1], lp.p[2], lp.p[3], lp.p[4], lp.p[0], lp.p[5]};
    if (simple_ccw(hp) && hexagon(lp, {1, 2, 3, 4, 0, 5})) {
      ++case_counts[kPentagonPoint]; r = {kLeftoverTriangle, 0, 5, -1}; return true;
    }
    lp.rollback(m);
  }
  // (ii) an ear on the outgoing edge, B.1.2 on the rest.
  for (int side = 0; side < 2; ++side) {
    const Ring tri = side == 0 ? Ring{0, 1, 2} : Ring{4, 0, 1};
    const Ring quad = side == 0 ? Ring{0, 2, 3, 4} : Ring{1, 2, 3, 4};
    if (!good_triangle(lp.p[tri[0]], lp.p[tri[1]], lp.p[tri[2]])) continue;
    // q strictly inside the quad's side of the ear's diagonal.
    if (side == 0 && orientation(lp.p[0], lp.p[2], lp.p[5]) <= 0) continue;
    if (side == 1 && orientation(lp.p[4], lp.p[1], lp.p[5]) <= 0) continue;
    std::vector<P2> qp;
    for (int i : quad) qp.push_back(lp.p[i]);
    if (!simple_ccw(qp)) continue;
    if (quad_with_point(lp, quad, 5)) {
      ++case_counts[kPentagonPoint]; r = {kLeftoverTriangle, 0, side == 0 ? 2 : 4, -1}; return true;
    }
    lp.rollback(m);
  }
  // (iii) the middle case (doc/tri2quad.md 3.5): the outgoing edge in the centre
  // triangle (v0, v1, v3): the type-1 split (v0, v1, p1), (v0, p1, v3, v4),
  // (v3, p1, v1, v2), then B.1.2 on the quad holding q (6 quads, 4 points).
  if (good_triangle(lp.p[0], lp.p[1], lp.p[3]) && good_triangle(lp.p[1], lp.p[2], lp.p[3]) &&
      good_triangle(lp.p[3], lp.p[4], lp.p[0])) {
    const P2 v0 = lp.p[0], v1 = lp.p[1], v2 = lp.p[2], v3 = lp.p[3], v4 = lp.p[4], q = lp.p[5];
    const auto region = clip({v0, v1, v3}, {{v3, v0}, {v4, v0}, {v3, v4}, {v1, v3}, {v2, v3}, {v1, v2}, {v0, v1}});
    if (region.size() >= 3) {
      const P2 c = centroid(region);
      std::vector<P2> cand{c};
      for (const P2& x : region)
        for (double f : {0.3, 0.6}) cand.push_back({c[0] + f * (x[0] - c[0]), c[1] + f * (x[1] - c[1])});
      for (const P2& x : cand) {
        if (!good_quad(v0, x, v3, v4) || !good_quad(v3, x, v1, v2) || !good_triangle(v0, v1, x)) continue;
        auto inside = [&](const P2& a, const P2& b, const P2& cc, const P2& d) {
          return orientation(a, b, q) > 0 && orientation(b, cc, q) > 0 && orientation(cc, d, q) > 0 &&
                 orientation(d, a, q) > 0;
        };
        const bool inA = inside(v0, x, v3, v4), inB = inside(v3, x, v1, v2);
        if (inA == inB) continue;
        const int p1 = lp.add_new(x);
        const Ring A = {0, p1, 3, 4}, B = {3, p1, 1, 2};
        lp.quads.push_back(inA ? Quad{B[0], B[1], B[2], B[3]} : Quad{A[0], A[1], A[2], A[3]});
        if (quad_with_point(lp, inA ? A : B, 5)) {
          ++case_counts[kPentagonPointMid];
          r = {kLeftoverTriangle, 0, p1, -1};
          return true;
        }
        lp.rollback(m);
      }
    }
  }
  return false;
}

bool Conversion::hexagon_point(LocalPatch& lp, Leftover& r) {
  const auto m = lp.mark();
  auto good = [&](const Quad& q) { return good_quad(lp.p[q[0]], lp.p[q[1]], lp.p[q[2]], lp.p[q[3]]); };
  // The point joined to alternate vertices (T1 of B.1.1 with the point
  // given): 3 quads, no new point.
  for (int pi = 0; pi < 2; ++pi) {
    const Quad q0{pi, pi + 1, (pi + 2) % 6, 6}, q1{(pi + 2) % 6, (pi + 3) % 6, (pi + 4) % 6, 6},
        q2{(pi + 4) % 6, (pi + 5) % 6, pi, 6};
    if (good(q0) && good(q1) && good(q2)) {
      for (const auto& q : {q0, q1, q2}) lp.quads.push_back(q);
      ++case_counts[kHexagonPoint]; r = {}; return true;
    }
  }
  // The point cuts a quad off a corner; B.1.1 on the hexagon left.
  for (int j = 0; j < 6; ++j) {
    const Quad q{(j + 5) % 6, j, (j + 1) % 6, 6};
    if (!good(q)) continue;
    Ring rest = {0, 1, 2, 3, 4, 5};
    rest[j] = 6;
    std::vector<P2> rp;
    for (int k : rest) rp.push_back(lp.p[k]);
    if (!simple_ccw(rp)) continue;
    lp.quads.push_back(q);
    if (hexagon(lp, rest, 2)) { ++case_counts[kHexagonPoint]; r = {}; return true; }
    lp.rollback(m);
  }
  // A diagonal splits off a convex quad; B.1.2 on the quad with the point.
  for (int i = 0; i < 3; ++i) {
    const Ring q1 = {i, i + 1, i + 2, (i + 3) % 6}, q2 = {(i + 3) % 6, (i + 4) % 6, (i + 5) % 6, i};
    for (int s = 0; s < 2; ++s) {
      const Ring& cv = s ? q2 : q1;
      const Ring& pt = s ? q1 : q2;
      if (!good_quad(lp.p[cv[0]], lp.p[cv[1]], lp.p[cv[2]], lp.p[cv[3]])) continue;
      std::vector<P2> pp;
      for (int k : pt) pp.push_back(lp.p[k]);
      if (!simple_ccw(pp)) continue;
      if (orientation(pp[3], pp[0], lp.p[6]) <= 0) continue;  // the point is on pt's side
      lp.quads.push_back({cv[0], cv[1], cv[2], cv[3]});
      if (quad_with_point(lp, pt, 6)) { ++case_counts[kHexagonPoint]; r = {}; return true; }
      lp.rollback(m);
    }
  }
  return false;
}

// 3(c) with the cross-edge, 4(c)(v)(d)-(e): the region is the triangle
// (a, b, X) (local 0, 1, 2) with two vertices inside (3, 4), one of them
// c. The own triangle is the leftover; the rest is the quadrilateral
// (b, X, a, c), reflex at c, with the other vertex inside (B.1.2): 5
// quads and 3 points for the 4 triangles eliminated. If B.1.2 fails
// there, the other inside vertex may serve as the apex instead.
bool Conversion::triangle_two_points(LocalPatch& lp, int c, Leftover& r) {
  const int lc = local_of(lp, c);
  if (lc != 3 && lc != 4) return false;
  for (const int apex : {lc, 7 - lc}) {
    const int q = 7 - apex;
    const P2 &A = lp.p[0], &B = lp.p[1], &Z = lp.p[apex], &Q = lp.p[q];
    const int o1 = orientation(B, Z, Q), o2 = orientation(Z, A, Q);
    if (!good_triangle(A, B, Z) || o1 == 0 || o2 == 0 || (o1 > 0 && o2 > 0)) continue;
    if (quad_with_point(lp, {1, 2, 0, apex}, q)) {
      ++case_counts[kTriangleTwoPoints];
      r = {kLeftoverTriangle, 0, apex, -1};
      return true;
    }
  }
  return false;
}

// 4(c)(iv): a non-convex pair and a non-empty triangle (p, q, x) around y
// on the other edge. The pentagon P of the own triangle and the pair goes
// through B.2.1 with the edge (q, p) as its outgoing edge; the leftover
// (q, p, z) and the non-empty triangle form the quadrilateral (p, z, q, x)
// around y (B.1.2). Where B.2.1 needs type 3, its point m goes on that
// edge: the hexagon P + m by B.1.1 with at most two points, and B.1.2 on
// (p, m, q, x). At most 9 quads and 6 points for the 6 triangles.
bool Conversion::pair_and_nonempty(LocalPatch& lp, const Child* child, int a, int b, int c, Leftover& r) {
  const Child& pair = child[0].leftover.type == kLeftoverQuad ? child[0] : child[1];
  const Child& nt = child[0].leftover.type == kLeftoverNonEmpty ? child[0] : child[1];
  std::vector<int> ring = {a, b};
  if (&pair == &child[0]) { ring.push_back(pair.leftover.x); ring.push_back(pair.leftover.y); }
  ring.push_back(c);
  if (&pair == &child[1]) { ring.push_back(pair.leftover.x); ring.push_back(pair.leftover.y); }
  std::rotate(ring.begin(), std::find(ring.begin(), ring.end(), nt.q), ring.end());
  Ring P;
  for (int g : ring) P.push_back(local_of(lp, g));
  const int lp_ = local_of(lp, nt.p), lq = local_of(lp, nt.q), lx = local_of(lp, nt.leftover.x),
            ly = local_of(lp, nt.leftover.y);
  if (P[1] != lp_ || std::find(P.begin(), P.end(), -1) != P.end() || lx < 0 || ly < 0) return false;
  std::vector<P2> pp;
  for (int i : P) pp.push_back(lp.p[i]);
  if (!simple_ccw(pp)) return false;
  const auto m0 = lp.mark();
  const int z = pentagon(lp, P, nullptr, 1);
  if (z >= 0 && quad_with_point(lp, {lp_, z, lq, lx}, ly)) {
    ++case_counts[kPairNonEmpty];
    r = {};
    return true;
  }
  lp.rollback(m0);
  // Type 3: m on the edge, pushed a little to either side or not at all.
  const P2 Q = lp.p[lq], Pp = lp.p[lp_], X = lp.p[lx], Z = lp.p[P[3]];
  const P2 mid = {0.5 * (Q[0] + Pp[0]), 0.5 * (Q[1] + Pp[1])};
  for (const P2& toward : {X, Z, mid})
    for (double f : {0.05, 0.01}) {
      const int m = lp.add_new({mid[0] + f * (toward[0] - mid[0]), mid[1] + f * (toward[1] - mid[1])});
      std::vector<P2> hp = {Q, lp.p[m], Pp, pp[2], pp[3], pp[4]};
      if (simple_ccw(hp) && hexagon(lp, {lq, m, lp_, P[2], P[3], P[4]}, 2) &&
          quad_with_point(lp, {lp_, m, lq, lx}, ly)) {
        ++case_counts[kPairNonEmpty];
        r = {};
        return true;
      }
      lp.rollback(m0);
    }
  return false;
}

// 3(d): two non-empty triangles (p_k, q_k, x_k) around y_k. A point m on
// the outgoing edge (a, b) joined to c gives the quadrilaterals
// (p_k, m, q_k, x_k) around y_k (B.1.2 twice): 10 quads and 7 points for
// the 7 triangles; the parent gets m (edge_points()).
bool Conversion::two_nonempty(LocalPatch& lp, const Child* child, int a, int b, int c, bool is_root, Leftover& r, int& split_m) {
  const auto m0 = lp.mark();
  for (const P2& x : edge_points(a, b, c, is_root)) {
    const int m = lp.add_new(x);
    bool ok = true;
    for (int k = 0; k < 2 && ok; ++k) {
      const Child& nt = child[k];
      ok = quad_with_point(lp, {local_of(lp, nt.p), m, local_of(lp, nt.q), local_of(lp, nt.leftover.x)},
                                local_of(lp, nt.leftover.y));
    }
    if (ok) {
      ++case_counts[kTwoNonEmpty];
      if (is_root) { split_m = m; r = {}; }
      else r = {kLeftoverDent, 0, m, -1};
      return true;
    }
    lp.rollback(m0);
  }
  return false;
}

// Step 5: whatever the root leaves on its edge (a, b).
void Conversion::finish_root(int u, int a, int b, Leftover r, double at, int split_m) {
  if (split_m >= 0) {
    split_segment(a, b, split_m);
    repair(u, a, b, split_m);
  }
  if (r.type == kNoLeftover) return;
  // r is a triangle (a, b, z).
  const int z = r.x;
  const bool outer = component_parent[component[u]] < 0;
  if (outer && options.allow_outside) {
    // The point s outside, right of a -> b: the quad (a, s, b, z) is
    // strictly convex for s in L(z, a) and L(b, z) (placement rule);
    // the centroid of that wedge cut at a height of |ab| / 4 (Fig. 3.16).
    LocalPatch lp;
    const int la = lp.add_known(points[a], a), lb = lp.add_known(points[b], b), lz = lp.add_known(points[z], z);
    const P2 A = points[a], Bp = points[b], Z = points[z];
    const P2 n = {0.25 * (Bp[1] - A[1]), -0.25 * (Bp[0] - A[0])};
    const auto wedge = clip({A, {A[0] + n[0], A[1] + n[1]}, {Bp[0] + n[0], Bp[1] + n[1]}, Bp}, {{Z, A}, {Bp, Z}});
    if (wedge.size() >= 3) {
      const int ls = lp.add_new(centroid(wedge));
      if (good_quad(lp.p[la], lp.p[ls], lp.p[lb], lp.p[lz])) {
        lp.quads.push_back({la, ls, lb, lz});
        commit_region(lp, {}, at);
        split_segment(a, b, int(points.size()) - 1);
        ++result.steiner_outside;
        ++case_counts[kRootOutside];
        return;
      }
    }
  }
  // Joe's split of (a, b, z) with its point on the edge (a, b).
  LocalPatch lp;
  const int la = lp.add_known(points[a], a), lb = lp.add_known(points[b], b), lz = lp.add_known(points[z], z);
  const int lm = lp.add_new({0.5 * (points[a][0] + points[b][0]), 0.5 * (points[a][1] + points[b][1])});
  if (!joe_split(lp, lz, la, lm, lb))
    throw Error("internal error: Joe's split failed at edge " + edge_name(a, b), input.path);
  const std::size_t before = points.size();
  commit_region(lp, {}, at);
  const int m = int(before);  // the first new point is lm
  ++case_counts[kRootJoe];
  split_segment(a, b, m);
  repair(u, a, b, m);
}

} // namespace imgmesh::tri2quad_detail
