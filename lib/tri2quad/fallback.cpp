// When no construction of steps 1-5 passes its checks at a node: first the
// dents (each child closed alone), then the safe split of the node's region
// (an odd-degree edge subset on its dual tree; de Berg's and Joe's splits).
// Both can cost more than the per-step budget; each use is counted.
#include "tri2quad/conversion.hpp"

#include "util/error.hpp"

namespace imgmesh::tri2quad_detail {

// Fallback when no construction for this node's polygon passes its
// checks (on random meshes: a few extreme heptagons and regions that
// touch themselves at a vertex): each child is closed alone, a leftover
// (a triangle or a non-empty triangle) with a point m on the shared edge
// pushed slightly into this node's triangle (the node keeps m as a reflex
// boundary vertex), a non-convex pair by the nested template. This can
// cost more than the per-step budget; each use is counted.
bool Conversion::make_dents(int u, int s0) {
  bool any = false;
  for (int k = 1; k <= 2; ++k) {
    const int j = (s0 + k) % 3;
    const int w = neighbours[u][j];
    if (w < 0 || (constrained[u] >> j & 1) || parent[w] != u) continue;
    const int p = triangles[u][(j + 1) % 3], q = triangles[u][j], opp = triangles[u][(j + 2) % 3];
    if (leftover[w].type == kLeftoverQuad) {
      // A non-convex pair closes by itself (nested template with a free
      // point, as in step 5(c)); the shared edge stays whole.
      LocalPatch lp;
      const int l0 = lp.add_known(points[p], p), l1 = lp.add_known(points[q], q);
      const int l2 = lp.add_known(points[leftover[w].x], leftover[w].x), l3 = lp.add_known(points[leftover[w].y], leftover[w].y);
      if (quad_nested_free(lp, {l0, l1, l2, l3})) {
        commit_region(lp, {}, attribute[w]);
        ++case_counts[kDentPair];
        leftover[w] = {};
        any = true;
      }
      continue;
    }
    if (leftover[w].type != kLeftoverTriangle && leftover[w].type != kLeftoverNonEmpty) continue;
    const P2 mm = {0.5 * (points[p][0] + points[q][0]), 0.5 * (points[p][1] + points[q][1])};
    for (double d : {0.15, 0.05, 0.015}) {
      LocalPatch lp;
      const int lp_ = lp.add_known(points[p], p), lq = lp.add_known(points[q], q), lo = lp.add_known(points[opp], opp);
      const int lx = lp.add_known(points[leftover[w].x], leftover[w].x);
      const int lm = lp.add_new({mm[0] + d * (points[opp][0] - mm[0]), mm[1] + d * (points[opp][1] - mm[1])});
      // This node keeps the dent: both halves of its triangle stay proper.
      if (!good_triangle(lp.p[lq], lp.p[lm], lp.p[lo]) || !good_triangle(lp.p[lm], lp.p[lp_], lp.p[lo]))
        continue;
      bool ok;
      if (leftover[w].type == kLeftoverTriangle) {
        ok = good_quad(lp.p[lp_], lp.p[lm], lp.p[lq], lp.p[lx]);
        if (ok) lp.quads.push_back({lp_, lm, lq, lx});
      } else {
        const int li = lp.add_known(points[leftover[w].y], leftover[w].y);
        ok = quad_with_point(lp, {lp_, lm, lq, lx}, li);
      }
      if (!ok) continue;
      int mg = lm;
      commit_region(lp, {}, attribute[w], &mg);
      ++case_counts[leftover[w].type == kLeftoverTriangle ? kDentTri : kDentNonEmpty];
      leftover[w] = {kLeftoverDent, 0, mg, -1};
      any = true;
      break;
    }
  }
  return any;
}

namespace {

// A spanning tree of the dual graph of a region's triangles (through shared
// edges), by BFS from tris[0]: each triangle's parent and the slot of its
// edge to it, in BFS order (shorter than the region when it is not connected).
struct RegionTree {
  std::vector<int> parent, order, slot;
};
RegionTree region_tree(const std::vector<std::array<int, 3>>& tris) {
  const int n = int(tris.size());
  RegionTree tree{std::vector<int>(n, -1), {0}, std::vector<int>(n, -1)};
  std::vector<char> seen(n, 0);
  seen[0] = 1;
  for (std::size_t i = 0; i < tree.order.size(); ++i) {
    const int u = tree.order[i];
    for (int j = 0; j < 3; ++j) {
      const int a = tris[u][j], b = tris[u][(j + 1) % 3];
      for (int w = 0; w < n; ++w) {
        if (seen[w]) continue;
        for (int k = 0; k < 3; ++k)
          if (tris[w][k] == b && tris[w][(k + 1) % 3] == a) {
            seen[w] = 1; tree.parent[w] = u; tree.slot[w] = k; tree.order.push_back(w);
          }
      }
    }
  }
  return tree;
}

// Odd-degree edge subset (a T-join) of the tree, bottom-up: every triangle
// but the first ends with 1 or 3 split edges. The chosen (child, slot)
// edges; deg gets each triangle's count.
std::vector<std::pair<int, int>> odd_degree_edges(const RegionTree& tree, std::vector<int>& deg) {
  const int n = int(tree.order.size());
  deg.assign(n, 0);
  std::vector<std::pair<int, int>> chosen;
  for (int i = n - 1; i > 0; --i) {
    const int w = tree.order[i];
    if (deg[w] % 2 == 0) { ++deg[w]; ++deg[tree.parent[w]]; chosen.push_back({w, tree.slot[w]}); }
  }
  return chosen;
}

// The local id of the output vertex g in lp, added as known if missing.
int local_id(LocalPatch& lp, const std::vector<P2>& points, int g) {
  for (std::size_t i = 0; i < lp.p.size(); ++i) if (lp.gid[i] == g) return int(i);
  return lp.add_known(points[g], g);
}

} // namespace

// The safe split. tris[0] is the node's triangle with its outgoing edge
// first. Returns the leftover region (kNoLeftover or kLeftoverTriangle) and fills lp.
Leftover Conversion::safe_split(LocalPatch& lp, const std::vector<std::array<int, 3>>& tris, bool root, int* split_m) {
  const int n = int(tris.size());
  const RegionTree tree = region_tree(tris);
  if (int(tree.order.size()) != n) throw Error("internal error: disconnected region in tri2quad fallback", input.path);
  const std::vector<int>& tree_parent = tree.parent;
  std::vector<int> deg;
  const std::vector<std::pair<int, int>> chosen = odd_degree_edges(tree, deg);  // (child, slot)
  std::vector<std::array<int, 3>> split(n, {-1, -1, -1});  // local point id per slot
  const bool split_root_edge = root && deg[0] % 2 == 0;
  if (split_root_edge) ++deg[0];
  auto local = [&](int g) { return local_id(lp, points, g); };
  for (const auto& t : tris) for (int v : t) local(v);
  const auto base = lp.mark();
  for (double push : {0.0, 0.05, 0.01, 0.002}) {
    if (push > 0 && deg[0] != 2) break;
    lp.rollback(base);
    for (auto& s : split) s = {-1, -1, -1};
    bool ok = true;
    for (const auto& [w, k] : chosen) {
      const int a = tris[w][k], b = tris[w][(k + 1) % 3];
      const int m = lp.add_new({0.5 * (points[a][0] + points[b][0]), 0.5 * (points[a][1] + points[b][1])});
      split[w][k] = m;
      const int u = tree_parent[w];
      for (int j = 0; j < 3; ++j)
        if (tris[u][j] == b && tris[u][(j + 1) % 3] == a) split[u][j] = m;
    }
    if (split_root_edge) {
      const int a = tris[0][0], b = tris[0][1];
      split[0][0] = lp.add_new({0.5 * (points[a][0] + points[b][0]), 0.5 * (points[a][1] + points[b][1])});
    }
    Leftover res;
    int pushed_tri = -1;
    if (deg[0] == 2) {
      // Step 2 of the thesis: quad (a, m1, c, m2) and the triangle
      // (a, b, m1), with m2 pushed off its edge into the child.
      if (push == 0) continue;
      const int a = local(tris[0][0]), b = local(tris[0][1]), c = local(tris[0][2]);
      const int m1 = split[0][1], m2 = split[0][2];
      // Child across (c, a): the triangle whose split point is m2.
      for (int w = 1; w < n; ++w) for (int k = 0; k < 3; ++k) if (split[w][k] == m2) pushed_tri = w;
      if (pushed_tri < 0) { ok = false; }
      else {
        int opp = -1;
        for (int k = 0; k < 3; ++k) if (split[pushed_tri][k] == m2) opp = tris[pushed_tri][(k + 2) % 3];
        lp.p[m2] = {lp.p[m2][0] + push * (points[opp][0] - lp.p[m2][0]), lp.p[m2][1] + push * (points[opp][1] - lp.p[m2][1])};
        lp.quads.push_back({a, m1, c, m2});
        if (!good_quad(lp.p[a], lp.p[m1], lp.p[c], lp.p[m2]) ||
            !good_triangle(lp.p[a], lp.p[b], lp.p[m1]))
          ok = false;
        res.type = kLeftoverTriangle;
        res.x = m1;  // local id; mapped below
      }
    } else if (deg[0] == 0) {
      res.type = kLeftoverTriangle;
      res.x = local(tris[0][2]);
    }
    for (int w = 0; w < n && ok; ++w) {
      if (w == 0 && (deg[0] == 0 || deg[0] == 2)) continue;
      const int A = local(tris[w][0]), B = local(tris[w][1]), C = local(tris[w][2]);
      const int L[3] = {A, B, C};
      int cnt = 0, slot = -1;
      for (int k = 0; k < 3; ++k) if (split[w][k] >= 0) { ++cnt; slot = k; }
      if (cnt == 3) ok = deberg_split(lp, A, B, C, split[w][0], split[w][1], split[w][2]);
      else if (cnt == 1)
        ok = joe_split(lp, L[(slot + 2) % 3], L[slot], split[w][slot], L[(slot + 1) % 3]);
      else ok = false;
    }
    if (!ok) continue;
    if (split_root_edge && split_m) *split_m = split[0][0];
    ++case_counts[kFallback];
    return res;
  }
  throw Error("internal error: tri2quad could not quadrangulate a region near vertex " + vid(tris[0][0]), input.path);
}

} // namespace imgmesh::tri2quad_detail
