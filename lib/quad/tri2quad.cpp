// tri2quad: the mesh-level algorithm of thesis 3.2.1 and 3.3 (see the header
// for the outline). No recursion: BFS orders are explicit arrays, so meshes
// of 10^7 triangles run in linear time and bounded stack.
#include "quad/tri2quad.hpp"

#include "quad/tri2quad_polygons.hpp"
#include "quad/quality.hpp"
#include "util/error.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <map>
#include <unordered_map>
#include <unordered_set>

namespace imgmesh {
namespace {

using t2q::LocalPatch;
using t2q::P2;
using t2q::Ring;

enum Case : int {
  kQuadConvex,        // 4(c) shortcut / 5(c): two triangles form a convex quad
  kQuadPassedUp,      // 4(c): non-convex pair, handled with the grandparent
  kPentagonEar,       // B.2.1, leftover triangle is an ear (no point)
  kPentagonType1,     // 4(b), B.2.1 type 1
  kPentagonType2,     // 4(c)(ii), B.2.1 type 2
  kPentagonType3,     // in place of B.2.1 type 3: new apex + B.1.1
  kHexagon,           // 4(c)(i)/(iii), B.1.1
  kHeptagon,          // 4(c)(v)(f), B.3.1 (ear form)
  kNonEmptyTriangle,  // Fig. 3.6: non-empty triangle formed
  kQuadPoint,         // 3(b), 4(c)(iii)/(v)(d)-(e): B.1.2
  kPentagonPoint,     // 3(c), 4(c)(v)(a)-(c): B.2.2
  kHexagonPoint,      // 4(c)(iv)
  kRootJoe,           // step 5(b)/(d) without an outside point (Joe's split)
  kRootOutside,       // step 5(b)/(d) as in the thesis (--allow-outside)
  kRootNested,        // step 5(c): non-convex quad with a free point, B.1.2
  kDentTri,           // make_dents: a leftover triangle closed by a point on its edge
  kDentNonEmpty,      // make_dents: the same for a non-empty triangle (B.1.2)
  kFallback,          // safe odd-degree split of a region (see header)
  kRepair,            // Fig. 3.23: parent component triangle split
  kRootPentagonEdge,  // step 5: root pentagon + a point on its edge, B.1.1
  kPentagonPointMid,  // B.2.2 middle case: type-1 split, B.1.2 on the quad with q
  kPairNonEmpty,      // 4(c)(iv): B.2.1 on own triangle + pair, B.1.2 on the rest
  kTwoNonEmpty,       // 3(d): a point on the outgoing edge, B.1.2 twice
  kTriangleTwoPoints, // 3(c) cross-edge, 4(c)(v)(d)-(e): leftover + B.1.2
  kHeptagonClosed,    // B.3.1 with a point on the outgoing edge, no leftover
  kDentPair,          // make_dents: a non-convex pair closed alone (nested template)
  kPentagonType3Edge, // 4(c)(ii), B.2.1 type 3: a point on the outgoing edge, B.1.1
  kNumCases
};
const char* kCaseNames[kNumCases] = {
    "4c_convex_quad",        "4c_quad_to_grandparent", "B21_pentagon_ear",
    "4b_B21_type1",          "4cii_B21_type2",         "B21_type3_apex_hexagon",         "4ci_4ciii_B11_hexagon",
    "4cvf_B31_heptagon",     "3_nonempty_triangle",
    "3b_B12_quad_point",     "3c_B22_pentagon_point",  "4civ_hexagon_point",
    "5bd_joe_split",         "5bd_outside_point",      "5c_B12_nested",
    "fallback_dent_triangle", "fallback_dent_nonempty", "fallback_split",        "3_3_repair_split",
    "5_B11_root_pentagon_edge_point", "B22_middle_type1_B12", "4civ_B21_B12_pair_nonempty",
    "3d_edge_point_B12_twice",  "3c_4cvde_leftover_B12", "B31_heptagon_edge_point", "fallback_pair_nested",
    "4cii_B21_type3_edge_point"};

enum RegType : std::uint8_t { kEmpty = 0, kTri, kQuadR, kNTri, kDent };
struct Region {
  RegType type = kEmpty;
  std::uint8_t diag = 0;
  int x = -1, y = -1;
};

struct Converter {
  const Tri2QuadInput& in;
  const Tri2QuadOptions& opt;
  Tri2QuadResult& out;
  std::vector<P2>& pts;
  std::vector<std::array<int, 3>> T;
  std::vector<std::array<int, 3>> nb;
  std::vector<std::uint8_t> con;
  std::vector<double> attr;
  std::vector<int> comp;
  std::vector<int> par;
  std::vector<std::int8_t> pslot;
  std::vector<Region> reg;
  std::unordered_map<std::uint64_t, int> segs;  // current constraint/boundary edges -> marker
  std::size_t cases[kNumCases] = {};
  std::vector<int> sB, sI, sSort;
  std::vector<std::array<int, 3>> sTris, sKids;
  LocalPatch sLp;
  bool has_attr = false;
  int root_pick = 0;
  // Boundary edges that should not take a Steiner point (pair-first: the
  // edges of merged quads): a root edge is taken elsewhere when possible.
  const std::unordered_set<std::uint64_t>* avoid = nullptr;

  Converter(const Tri2QuadInput& i, const Tri2QuadOptions& o, Tri2QuadResult& r)
      : in(i), opt(o), out(r), pts(r.points) {}

  std::string vid(int v) const { return std::to_string(v + in.index_base); }
  std::string edge_name(int a, int b) const { return "(" + vid(a) + ", " + vid(b) + ")"; }

  // ------------------------------------------------------------ set-up
  void setup() {
    const std::size_t n = in.points.size();
    if (in.triangles.empty()) throw Error("the triangle mesh has no triangles", in.path);
    if (n > std::size_t(1) << 30 || in.triangles.size() > std::size_t(1) << 29)
      throw Error("mesh too large", in.path);
    pts = in.points;
    for (const P2& p : pts)
      if (!std::isfinite(p[0]) || !std::isfinite(p[1])) throw Error("non-finite coordinate", in.path);
    T.resize(in.triangles.size());
    has_attr = in.region.size() == in.triangles.size();
    attr.assign(T.size(), 0.0);
    for (std::size_t t = 0; t < T.size(); ++t) {
      auto tr = in.triangles[t];
      for (int v : tr)
        if (v < 0 || std::size_t(v) >= n)
          throw Error("triangle " + std::to_string(t + in.index_base) + " has a vertex id out of range", in.path);
      const int o = orientation(pts[tr[0]], pts[tr[1]], pts[tr[2]]);
      if (o == 0)
        throw Error("triangle " + std::to_string(t + in.index_base) + " (" + vid(tr[0]) + ", " + vid(tr[1]) +
                        ", " + vid(tr[2]) + ") is degenerate (zero area)",
                    in.path);
      if (o < 0) std::swap(tr[1], tr[2]);
      T[t] = tr;
      if (has_attr) attr[t] = in.region[t];
    }
    // Edge adjacency through the triangles around each vertex (CSR, 4 bytes
    // a corner): less memory and time than sorting the 3t edges.
    std::vector<std::uint32_t> start(n + 1, 0), around(3 * T.size());
    for (const auto& tr : T) for (int v : tr) ++start[v + 1];
    for (std::size_t v = 0; v < n; ++v) start[v + 1] += start[v];
    {
      std::vector<std::uint32_t> pos(start.begin(), start.end() - 1);
      for (std::size_t t = 0; t < T.size(); ++t) for (int v : T[t]) around[pos[v]++] = std::uint32_t(t);
    }
    // Slot of the edge (a, b) or (b, a) in triangle w, or -1.
    auto slot_of = [&](int w, int x, int y) {
      for (int k = 0; k < 3; ++k) {
        const int p = T[w][k], q = T[w][(k + 1) % 3];
        if ((p == x && q == y) || (p == y && q == x)) return k;
      }
      return -1;
    };
    nb.assign(T.size(), {-1, -1, -1});
    con.assign(T.size(), 0);
    for (std::size_t t = 0; t < T.size(); ++t)
      for (int j = 0; j < 3; ++j) {
        const int a = T[t][j], b = T[t][(j + 1) % 3];
        int found = 0;
        for (std::uint32_t i = start[a]; i < start[a + 1]; ++i) {
          const int w = int(around[i]);
          if (std::size_t(w) == t) continue;
          const int k = slot_of(w, a, b);
          if (k < 0) continue;
          if (++found > 1) throw Error("edge " + edge_name(a, b) + " is shared by more than two triangles (not a 2-manifold)", in.path);
          if (T[w][k] == a)
            throw Error("triangles on both sides of edge " + edge_name(a, b) + " overlap (folded mesh)", in.path);
          nb[t][j] = w;
        }
      }
    // Constraint segments.
    for (std::size_t k = 0; k < in.constraints.size(); ++k) {
      const auto s = in.constraints[k];
      const int marker = k < in.constraint_markers.size() ? in.constraint_markers[k] : 1;
      if (s[0] < 0 || s[1] < 0 || std::size_t(s[0]) >= n || std::size_t(s[1]) >= n)
        throw Error("constraint segment " + std::to_string(k + in.index_base) + " has a vertex id out of range", in.path);
      bool edge = false;
      for (std::uint32_t i = start[s[0]]; i < start[s[0] + 1]; ++i) {
        const int w = int(around[i]);
        const int j = slot_of(w, s[0], s[1]);
        if (j >= 0) { con[w] |= std::uint8_t(1u << j); edge = true; }
      }
      if (!edge)
        throw Error("constraint segment " + edge_name(s[0], s[1]) + " is not an edge of the triangle mesh", in.path);
      segs[edge_key(s[0], s[1])] = marker;
    }
    // Every boundary edge is a constraint too.
    for (std::size_t t = 0; t < T.size(); ++t)
      for (int j = 0; j < 3; ++j)
        if (nb[t][j] < 0) {
          con[t] |= std::uint8_t(1u << j);
          segs.emplace(edge_key(T[t][j], T[t][(j + 1) % 3]), 1);
        }
    // Input restriction (3.3): the constraint complex has no dangling end.
    std::vector<std::uint8_t> deg(n, 0);
    for (std::size_t t = 0; t < T.size(); ++t)
      for (int j = 0; j < 3; ++j)
        if ((con[t] >> j & 1) && (nb[t][j] < 0 || std::size_t(nb[t][j]) > t)) {
          for (int v : {T[t][j], T[t][(j + 1) % 3]}) deg[v] = std::uint8_t(std::min(deg[v] + 1, 3));
        }
    for (std::size_t t = 0; t < T.size(); ++t)
      for (int j = 0; j < 3; ++j)
        if (con[t] >> j & 1)
          for (int v : {T[t][(j + 1) % 3], T[t][j]})
            if (deg[v] == 1)
              throw Error("constraint edge " + edge_name(T[t][j], T[t][(j + 1) % 3]) + " dangles at vertex " + vid(v) +
                              " (no other constraint or boundary edge ends there): the input restriction of "
                              "thesis 3.3 (Fig. 3.26) is not met",
                          in.path);
    out.input_points = n;
    out.triangles = T.size();
  }

  // ------------------------------------------------------------ components
  std::vector<int> comp_order, comp_parent, comp_seed;
  void components() {
    comp.assign(T.size(), -1);
    std::vector<int> q;
    q.reserve(T.size());
    int h = 0;
    for (std::size_t s = 0; s < T.size(); ++s) {
      if (comp[s] >= 0) continue;
      comp[s] = h;
      comp_seed.push_back(int(s));
      q.clear();
      q.push_back(int(s));
      for (std::size_t i = 0; i < q.size(); ++i) {
        const int t = q[i];
        for (int j = 0; j < 3; ++j) {
          const int u = nb[t][j];
          if (u >= 0 && !(con[t] >> j & 1) && comp[u] < 0) { comp[u] = h; q.push_back(u); }
        }
      }
      ++h;
    }
    for (std::size_t t = 0; t < T.size(); ++t)
      for (int j = 0; j < 3; ++j)
        if ((con[t] >> j & 1) && nb[t][j] >= 0 && comp[nb[t][j]] == comp[t])
          throw Error("constraint edge " + edge_name(T[t][j], T[t][(j + 1) % 3]) +
                          " has the same region on both sides (an open constraint curve): the input "
                          "restriction of thesis 3.3 (Fig. 3.26) is not met",
                      in.path);
    out.components = std::size_t(h);
    // Triangles of each component (CSR), then T^c by BFS from components
    // with a boundary edge.
    std::vector<int> start(h + 1, 0), list(T.size());
    for (int c : comp) ++start[c + 1];
    for (int c = 0; c < h; ++c) start[c + 1] += start[c];
    {
      std::vector<int> pos(start.begin(), start.end() - 1);
      for (std::size_t t = 0; t < T.size(); ++t) list[pos[comp[t]]++] = int(t);
    }
    comp_parent.assign(h, -2);
    // With edges to avoid, roots of T^c go first to a boundary edge that
    // may take a point.
    auto free_boundary = [&](std::size_t t) {
      for (int j = 0; j < 3; ++j)
        if (nb[t][j] < 0 && !(avoid && avoid->count(edge_key(T[t][j], T[t][(j + 1) % 3])))) return true;
      return false;
    };
    for (std::size_t i = 0; i < 2 * T.size(); ++i) {
      const std::size_t t = i % T.size();
      const bool boundary = i < T.size() ? free_boundary(t) : (nb[t][0] < 0 || nb[t][1] < 0 || nb[t][2] < 0);
      if (!boundary || comp_parent[comp[t]] != -2) continue;
      const std::size_t first = comp_order.size();
      comp_parent[comp[t]] = -1;
      comp_order.push_back(comp[t]);
      for (std::size_t i = first; i < comp_order.size(); ++i) {
        const int c = comp_order[i];
        for (int k = start[c]; k < start[c + 1]; ++k) {
          const int u = list[k];
          for (int j = 0; j < 3; ++j) {
            const int w = nb[u][j];
            if (w >= 0 && comp_parent[comp[w]] == -2) {
              comp_parent[comp[w]] = c;
              comp_order.push_back(comp[w]);
            }
          }
        }
      }
    }
  }

  // ------------------------------------------------------------ output
  int commit(const LocalPatch& lp, double a, std::size_t first_quad = 0) {
    std::vector<int> id(lp.p.size());
    for (std::size_t i = 0; i < lp.p.size(); ++i) {
      if (lp.gid[i] >= 0) { id[i] = lp.gid[i]; continue; }
      id[i] = int(pts.size());
      pts.push_back(lp.p[i]);
      ++out.steiner;
    }
    for (std::size_t k = first_quad; k < lp.quads.size(); ++k) {
      const auto& q = lp.quads[k];
      out.quads.push_back({id[q[0]], id[q[1]], id[q[2]], id[q[3]]});
      if (has_attr) out.region.push_back(a);
    }
    return 0;
  }

  void split_segment(int a, int b, int m) {
    auto it = segs.find(edge_key(a, b));
    if (it == segs.end()) return;
    const int marker = it->second;
    segs.erase(it);
    segs[edge_key(a, m)] = marker;
    segs[edge_key(m, b)] = marker;
  }

  // Fig. 3.23: the triangle across (a, b) from `from` gets the point m.
  void repair(int from, int a, int b, int m) {
    int N = -1, sN = -1;
    for (int j = 0; j < 3; ++j) {
      const int w = nb[from][j];
      if (w >= 0 && ((T[from][j] == a && T[from][(j + 1) % 3] == b))) N = w;
    }
    if (N < 0) return;
    for (int j = 0; j < 3; ++j)
      if (T[N][j] == b && T[N][(j + 1) % 3] == a) sN = j;
    if (sN < 0) return;
    const int z = T[N][(sN + 2) % 3];
    const int oldnb = nb[N][(sN + 1) % 3];
    const int oldbit = con[N] >> ((sN + 1) % 3) & 1;
    const int N2 = int(T.size());
    T.push_back({m, a, z});
    nb.push_back({from, oldnb, N});
    con.push_back(std::uint8_t(1u | (oldbit << 1)));
    attr.push_back(attr[N]);
    comp.push_back(comp[N]);
    par.push_back(-1);
    pslot.push_back(0);
    reg.push_back({});
    T[N][(sN + 1) % 3] = m;
    nb[N][(sN + 1) % 3] = N2;
    con[N] = std::uint8_t((con[N] & ~(1u << ((sN + 1) % 3))) | (1u << sN));
    if (oldnb >= 0)
      for (int j = 0; j < 3; ++j)
        if (nb[oldnb][j] == N && T[oldnb][j] == z && T[oldnb][(j + 1) % 3] == a) nb[oldnb][j] = N2;
    ++cases[kRepair];
    ++out.repairs;
  }

  // ------------------------------------------------------------ regions
  // Triangles of a child's region attached to its outgoing edge (p, q).
  static void region_triangles(const Region& r, int p, int q, std::vector<std::array<int, 3>>& tris) {
    switch (r.type) {
      case kEmpty: break;
      case kTri: tris.push_back({p, q, r.x}); break;
      case kQuadR:
        if (r.diag == 0) { tris.push_back({p, q, r.y}); tris.push_back({r.y, q, r.x}); }
        else { tris.push_back({p, q, r.x}); tris.push_back({p, r.x, r.y}); }
        break;
      case kNTri:
        tris.push_back({p, q, r.y}); tris.push_back({r.y, q, r.x}); tris.push_back({p, r.y, r.x});
        break;
      case kDent: break;
    }
  }
  // A child's region and its outgoing edge (p, q) (u's edge (q, p)).
  struct Kid {
    Region r;
    int p = -1, q = -1;
  };
  static int local_of(const LocalPatch& lp, int g) {
    for (std::size_t i = 0; i < lp.gid.size(); ++i)
      if (lp.gid[i] == g) return int(i);
    return -1;
  }

  static void region_ext(const Region& r, std::vector<int>& b, std::vector<int>& inner) {
    switch (r.type) {
      case kEmpty: break;
      case kTri: b.push_back(r.x); break;
      case kQuadR: b.push_back(r.x); b.push_back(r.y); break;
      case kNTri: b.push_back(r.x); inner.push_back(r.y); break;
      case kDent: b.push_back(r.x); break;
    }
  }

  // The safe split. tris[0] is the node's triangle with its outgoing edge
  // first. Returns the leftover region (kEmpty or kTri) and fills lp.
  Region fallback(LocalPatch& lp, const std::vector<std::array<int, 3>>& tris, bool root, int* split_m) {
    const int n = int(tris.size());
    // Spanning tree of the region's dual graph (shared edges).
    std::vector<int> parent(n, -1), order{0}, pe(n, -1);  // pe: slot in child of edge to parent
    std::vector<char> seen(n, 0);
    seen[0] = 1;
    for (std::size_t i = 0; i < order.size(); ++i) {
      const int u = order[i];
      for (int j = 0; j < 3; ++j) {
        const int a = tris[u][j], b = tris[u][(j + 1) % 3];
        for (int w = 0; w < n; ++w) {
          if (seen[w]) continue;
          for (int k = 0; k < 3; ++k)
            if (tris[w][k] == b && tris[w][(k + 1) % 3] == a) {
              seen[w] = 1; parent[w] = u; pe[w] = k; order.push_back(w);
            }
        }
      }
    }
    if (int(order.size()) != n) throw Error("internal error: disconnected region in tri2quad fallback", in.path);
    // Odd-degree edge subset (a T-join): every triangle but a non-root
    // node's own triangle ends with 1 or 3 split edges.
    std::vector<std::array<int, 3>> split(n, {-1, -1, -1});  // local point id per slot
    std::vector<int> deg(n, 0);
    std::vector<std::pair<int, int>> chosen;  // (child, slot)
    for (int i = n - 1; i > 0; --i) {
      const int w = order[i];
      if (deg[w] % 2 == 0) { ++deg[w]; ++deg[parent[w]]; chosen.push_back({w, pe[w]}); }
    }
    const bool split_root_edge = root && deg[0] % 2 == 0;
    if (split_root_edge) ++deg[0];
    auto local = [&](int g) {
      for (std::size_t i = 0; i < lp.p.size(); ++i) if (lp.gid[i] == g) return int(i);
      return lp.add_known(pts[g], g);
    };
    for (const auto& t : tris) for (int v : t) local(v);
    const auto base = lp.mark();
    for (double push : {0.0, 0.05, 0.01, 0.002}) {
      if (push > 0 && deg[0] != 2) break;
      lp.rollback(base);
      for (auto& s : split) s = {-1, -1, -1};
      bool ok = true;
      for (const auto& [w, k] : chosen) {
        const int a = tris[w][k], b = tris[w][(k + 1) % 3];
        const int m = lp.add_new({0.5 * (pts[a][0] + pts[b][0]), 0.5 * (pts[a][1] + pts[b][1])});
        split[w][k] = m;
        const int u = parent[w];
        for (int j = 0; j < 3; ++j)
          if (tris[u][j] == b && tris[u][(j + 1) % 3] == a) split[u][j] = m;
      }
      if (split_root_edge) {
        const int a = tris[0][0], b = tris[0][1];
        split[0][0] = lp.add_new({0.5 * (pts[a][0] + pts[b][0]), 0.5 * (pts[a][1] + pts[b][1])});
      }
      Region res;
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
          lp.p[m2] = {lp.p[m2][0] + push * (pts[opp][0] - lp.p[m2][0]), lp.p[m2][1] + push * (pts[opp][1] - lp.p[m2][1])};
          lp.quads.push_back({a, m1, c, m2});
          if (!good_quad(lp.p[a], lp.p[m1], lp.p[c], lp.p[m2]) ||
              !good_triangle(lp.p[a], lp.p[b], lp.p[m1]))
            ok = false;
          res.type = kTri;
          res.x = m1;  // local id; mapped below
        }
      } else if (deg[0] == 0) {
        res.type = kTri;
        res.x = local(tris[0][2]);
      }
      for (int w = 0; w < n && ok; ++w) {
        if (w == 0 && (deg[0] == 0 || deg[0] == 2)) continue;
        const int A = local(tris[w][0]), B = local(tris[w][1]), C = local(tris[w][2]);
        const int L[3] = {A, B, C};
        int cnt = 0, slot = -1;
        for (int k = 0; k < 3; ++k) if (split[w][k] >= 0) { ++cnt; slot = k; }
        if (cnt == 3) ok = t2q::deberg_split(lp, A, B, C, split[w][0], split[w][1], split[w][2]);
        else if (cnt == 1)
          ok = t2q::joe_split(lp, L[(slot + 2) % 3], L[slot], split[w][slot], L[(slot + 1) % 3]);
        else ok = false;
      }
      if (!ok) continue;
      if (split_root_edge && split_m) *split_m = split[0][0];
      ++cases[kFallback];
      return res;
    }
    throw Error("internal error: tri2quad could not quadrangulate a region near vertex " + vid(tris[0][0]), in.path);
  }

  // Commit a patch whose returned region refers to local ids.
  std::vector<int> sId;
  Region commit_region(LocalPatch& lp, Region r, double a, int* local_to_global = nullptr) {
    std::vector<int>& id = sId;
    id.resize(lp.p.size());
    for (std::size_t i = 0; i < lp.p.size(); ++i) {
      if (lp.gid[i] >= 0) { id[i] = lp.gid[i]; continue; }
      id[i] = int(pts.size());
      pts.push_back(lp.p[i]);
      ++out.steiner;
    }
    for (const auto& q : lp.quads) {
      out.quads.push_back({id[q[0]], id[q[1]], id[q[2]], id[q[3]]});
      if (has_attr) out.region.push_back(a);
    }
    if (r.x >= 0) r.x = id[r.x];
    if (r.y >= 0) r.y = id[r.y];
    if (local_to_global && *local_to_global >= 0) *local_to_global = id[*local_to_global];
    return r;
  }

  // Node u with outgoing edge (a, b): combine with the children's regions.
  void process(int u, bool is_root) {
    const int s0 = pslot[u];
    const int a = T[u][s0], b = T[u][(s0 + 1) % 3], c = T[u][(s0 + 2) % 3];
    for (int attempt = 0;; ++attempt) {
    // Scratch buffers kept across nodes: no allocation on the common paths.
    std::vector<int>& B = sB;
    std::vector<int>& I = sI;
    std::vector<std::array<int, 3>>& tris = sTris;
    std::vector<std::array<int, 3>>& kids = sKids;
    B.assign({a, b});
    I.clear();
    tris.assign({{a, b, c}});
    kids.clear();
    Kid kid[2];
    for (int k = 1; k <= 2; ++k) {
      const int j = (s0 + k) % 3;
      const int w = nb[u][j];
      if (k == 2) B.push_back(c);
      if (w < 0 || (con[u] >> j & 1) || par[w] != u) continue;
      const int p = T[u][(j + 1) % 3], q = T[u][j];  // child's outgoing edge (p, q)
      kid[k - 1] = {reg[w], p, q};
      region_ext(reg[w], B, I);
      if (reg[w].type == kDent) split_own(tris, q, p, reg[w].x);
      else region_triangles(reg[w], p, q, kids);
    }
    tris.insert(tris.end(), kids.begin(), kids.end());
    // Close "x, c, x" (a vertex surrounded by the region: Fig. 3.6).
    bool changed = true;
    while (changed && B.size() >= 4) {
      changed = false;
      const std::size_t n = B.size();
      for (std::size_t i = 0; i < n; ++i) {
        if (B[(i + n - 1) % n] == B[(i + 1) % n] && i != 0 && i != 1 && (i + 1) % n != 0 && (i + 1) % n != 1) {
          I.push_back(B[i]);
          const std::size_t j = (i + 1) % n;
          if (j > i) { B.erase(B.begin() + j); B.erase(B.begin() + i); }
          else { B.erase(B.begin() + i); B.erase(B.begin() + j); }
          changed = true;
          break;
        }
      }
    }
    // Fast paths for the two commonest nodes (no pinch is possible with
    // fewer than five boundary vertices): a lone triangle, and a pair that
    // is a convex quad (the 4(c) shortcut) or goes to the grandparent.
    if (!is_root && I.empty() && B.size() == 3) {
      reg[u] = {kTri, 0, c, -1};
      return;
    }
    if (!is_root && I.empty() && B.size() == 4 && tris.size() == 2) {
      if (good_quad(pts[B[0]], pts[B[1]], pts[B[2]], pts[B[3]])) {
        out.quads.push_back({B[0], B[1], B[2], B[3]});
        if (has_attr) out.region.push_back(attr[u]);
        ++cases[kQuadConvex];
        reg[u] = {};
      } else {
        ++cases[kQuadPassedUp];
        reg[u] = {kQuadR, std::uint8_t(B[3] == c ? 0 : 1), B[2], B[3]};
      }
      return;
    }
    bool pinched = false;
    {
      std::vector<int>& s = sSort;
      s.assign(B.begin(), B.end());
      s.insert(s.end(), I.begin(), I.end());
      std::sort(s.begin(), s.end());
      pinched = std::adjacent_find(s.begin(), s.end()) != s.end();
    }
    if (!pinched && B.size() == 3 && I.empty() && !is_root) {
      reg[u] = {kTri, 0, c, -1};  // a lone triangle waits for its parent
      return;
    }
    LocalPatch& lp = sLp;
    lp.p.clear();
    lp.gid.clear();
    lp.quads.clear();
    int split_m = -1;  // local id of a point put on the root edge
    std::vector<int> LB, LI;
    for (int v : B) LB.push_back(lp.add_known(pts[v], v));
    for (int v : I) LI.push_back(lp.add_known(pts[v], v));
    const double at = attr[u];
    Region r;
    bool done = false;
    const std::size_t nb_ = B.size(), ni = I.size();
    // B.2.1: a pentagon becomes quads plus a triangle passed up (its apex).
    auto pentagon_leaving_triangle = [&](int hexagon_budget) {
      int kind = 0;
      const int apex = t2q::pentagon(lp, {0, 1, 2, 3, 4}, &kind, hexagon_budget);
      if (apex < 0) return false;
      ++cases[kind == 0 ? kPentagonEar : kind == 1 ? kPentagonType1 : kind == 2 ? kPentagonType2 : kPentagonType3];
      r = {kTri, 0, apex, -1};
      return true;
    };
    // B.2.1 type 3 (4(c)(ii)): a point m on the outgoing edge, B.1.1 on the
    // hexagon (a, m, b, ...); below the root m goes to the parent.
    auto pentagon_edge_point = [&](int hexagon_budget) {
      const auto m0 = lp.mark();
      for (const P2& x : edge_points(a, b, c, is_root)) {
        const int m = lp.add_new(x);
        if (t2q::hexagon(lp, {0, m, 1, 2, 3, 4}, hexagon_budget)) {
          if (is_root) { ++cases[kRootPentagonEdge]; split_m = m; r = {}; }
          else { ++cases[kPentagonType3Edge]; r = {kDent, 0, m, -1}; }
          return true;
        }
        lp.rollback(m0);
      }
      return false;
    };
    if (!pinched) {
      if (nb_ == 3 && ni == 0) {
        if (!is_root) { reg[u] = {kTri, 0, c, -1}; return; }
        r = {kTri, 0, 2, -1};  // local id of c
        done = true;
      } else if (nb_ == 4 && ni == 0) {
        if (good_quad(lp.p[0], lp.p[1], lp.p[2], lp.p[3])) {
          lp.quads.push_back({0, 1, 2, 3});
          ++cases[kQuadConvex];
          r = {};
          done = true;
        } else if (!is_root && tris.size() == 2) {
          Region q{kQuadR, std::uint8_t(B[3] == c ? 0 : 1), B[2], B[3]};
          ++cases[kQuadPassedUp];
          reg[u] = q;
          return;
        } else if (t2q::quad_nested_free(lp, {0, 1, 2, 3})) {
          ++cases[kRootNested];
          r = {};
          done = true;
        }
      } else if (nb_ == 5 && ni == 0 && is_root && !(opt.allow_outside && comp_parent[comp[u]] < 0)) {
        // At the root the outgoing edge may take a point (as the thesis's
        // type 3 does): the hexagon (a, m, b, ...) by B.1.1 closes the
        // pentagon with at most 5 quads and 4 points, where a leftover
        // triangle plus Joe's split would cost at least 6 quads and 5 points.
        done = pentagon_edge_point(3) || pentagon_leaving_triangle(3);
      } else if (nb_ == 5 && ni == 0) {
        // B.2.1 within its budget (3 quads, 2 points for the 2 triangles
        // eliminated), else type 3: the point on the outgoing edge and B.1.1
        // with at most 2 more (4 quads, 3 points for 3 triangles).
        done = pentagon_leaving_triangle(1) || pentagon_edge_point(2) || pentagon_leaving_triangle(3);
      } else if (nb_ == 6 && ni == 0) {
        if (t2q::hexagon(lp, {0, 1, 2, 3, 4, 5})) { ++cases[kHexagon]; r = {}; done = true; }
      } else if (nb_ == 7 && ni == 0) {
        done = heptagon(lp, r, a, b, c, is_root, split_m);
      } else if (nb_ == 3 && ni == 1) {
        // Non-empty triangle (a, b, w) around I (Fig. 3.6): it goes up to
        // the parent (a quad plus a leftover triangle is impossible here:
        // the remainder would be reflex at I).
        if (!is_root && tris.size() == 3) {
          ++cases[kNonEmptyTriangle];
          reg[u] = {kNTri, 0, B[2], I[0]};
          return;
        } else if (is_root) {
          // Step 5(a) without an outside point: a point on the root edge
          // makes the quad (a, m, b, w) around I (B.1.2, flat corner at m).
          const auto mk = lp.mark();
          const int m = lp.add_new({0.5 * (pts[a][0] + pts[b][0]), 0.5 * (pts[a][1] + pts[b][1])});
          if (t2q::quad_with_point(lp, {0, m, 1, 2}, 3)) {
            ++cases[kQuadPoint];
            split_m = m;
            r = {};
            done = true;
          } else {
            lp.rollback(mk);
          }
        }
      } else if (nb_ == 4 && ni == 1) {
        if (t2q::quad_with_point(lp, {0, 1, 2, 3}, 4)) { ++cases[kQuadPoint]; r = {}; done = true; }
      } else if (nb_ == 5 && ni == 1) {
        done = pentagon_point(lp, r);
      } else if (nb_ == 3 && ni == 2) {
        done = triangle_two_points(lp, c, r);
      }
      const auto t0 = kid[0].r.type, t1 = kid[1].r.type;
      if (!done && ((t0 == kQuadR && t1 == kNTri) || (t0 == kNTri && t1 == kQuadR)))
        done = (nb_ == 6 && ni == 1 && hexagon_point(lp, r)) || pair_and_nonempty(lp, kid, a, b, c, r);
      if (!done && t0 == kNTri && t1 == kNTri)
        done = two_nonempty(lp, kid, a, b, c, is_root, r, split_m);
    }
    if (!done && attempt == 0 && make_dents(u, s0)) continue;
    if (!done) {
      lp.p.clear();
      lp.gid.clear();
      lp.quads.clear();
      r = fallback(lp, tris, is_root, &split_m);
      done = true;
    }
    r = commit_region(lp, r, at, &split_m);  // split_m: a point put on the root edge
    if (is_root) finish_root(u, a, b, r, at, split_m);
    else reg[u] = r;
    return;
    }
  }

  // Split the node's own triangle that has the edge (p, q) at the dent m.
  static void split_own(std::vector<std::array<int, 3>>& tris, int p, int q, int m) {
    for (std::size_t i = 0; i < tris.size(); ++i)
      for (int k = 0; k < 3; ++k)
        if (tris[i][k] == p && tris[i][(k + 1) % 3] == q) {
          const int r = tris[i][(k + 2) % 3];
          tris[i] = {p, m, r};
          tris.push_back({m, q, r});
          return;
        }
  }

  // Fallback when no construction for this node's polygon passes its
  // checks (on random meshes: a few extreme heptagons and regions that
  // touch themselves at a vertex): each child is closed alone, a leftover
  // (a triangle or a non-empty triangle) with a point m on the shared edge
  // pushed slightly into this node's triangle (the node keeps m as a reflex
  // boundary vertex), a non-convex pair by the nested template. This can
  // cost more than the per-step budget; each use is counted.
  bool make_dents(int u, int s0) {
    bool any = false;
    for (int k = 1; k <= 2; ++k) {
      const int j = (s0 + k) % 3;
      const int w = nb[u][j];
      if (w < 0 || (con[u] >> j & 1) || par[w] != u) continue;
      const int p = T[u][(j + 1) % 3], q = T[u][j], opp = T[u][(j + 2) % 3];
      if (reg[w].type == kQuadR) {
        // A non-convex pair closes by itself (nested template with a free
        // point, as in step 5(c)); the shared edge stays whole.
        LocalPatch lp;
        const int l0 = lp.add_known(pts[p], p), l1 = lp.add_known(pts[q], q);
        const int l2 = lp.add_known(pts[reg[w].x], reg[w].x), l3 = lp.add_known(pts[reg[w].y], reg[w].y);
        if (t2q::quad_nested_free(lp, {l0, l1, l2, l3})) {
          commit_region(lp, {}, attr[w]);
          ++cases[kDentPair];
          reg[w] = {};
          any = true;
        }
        continue;
      }
      if (reg[w].type != kTri && reg[w].type != kNTri) continue;
      const P2 mm = {0.5 * (pts[p][0] + pts[q][0]), 0.5 * (pts[p][1] + pts[q][1])};
      for (double d : {0.15, 0.05, 0.015}) {
        LocalPatch lp;
        const int lp_ = lp.add_known(pts[p], p), lq = lp.add_known(pts[q], q), lo = lp.add_known(pts[opp], opp);
        const int lx = lp.add_known(pts[reg[w].x], reg[w].x);
        const int lm = lp.add_new({mm[0] + d * (pts[opp][0] - mm[0]), mm[1] + d * (pts[opp][1] - mm[1])});
        // This node keeps the dent: both halves of its triangle stay proper.
        if (!good_triangle(lp.p[lq], lp.p[lm], lp.p[lo]) || !good_triangle(lp.p[lm], lp.p[lp_], lp.p[lo]))
          continue;
        bool ok;
        if (reg[w].type == kTri) {
          ok = good_quad(lp.p[lp_], lp.p[lm], lp.p[lq], lp.p[lx]);
          if (ok) lp.quads.push_back({lp_, lm, lq, lx});
        } else {
          const int li = lp.add_known(pts[reg[w].y], reg[w].y);
          ok = t2q::quad_with_point(lp, {lp_, lm, lq, lx}, li);
        }
        if (!ok) continue;
        int mg = lm;
        commit_region(lp, {}, attr[w], &mg);
        ++cases[reg[w].type == kTri ? kDentTri : kDentNonEmpty];
        reg[w] = {kDent, 0, mg, -1};
        any = true;
        break;
      }
    }
    return any;
  }

  // Where a node closes with a point m on its outgoing edge (a, b): on the
  // edge at the root; below it leaning a little into this node, so that
  // the parent's triangle with m is a convex quadrilateral (the
  // perturbation of step 1), or on the edge if that is all that works.
  std::vector<P2> edge_points(int a, int b, int c, bool is_root) const {
    const P2 mid = {0.5 * (pts[a][0] + pts[b][0]), 0.5 * (pts[a][1] + pts[b][1])};
    std::vector<P2> out;
    if (!is_root)
      for (double f : {0.03, 0.01}) out.push_back({mid[0] + f * (pts[c][0] - mid[0]), mid[1] + f * (pts[c][1] - mid[1])});
    out.push_back(mid);
    return out;
  }

  // 4(c)(v)(f), B.3.1: the heptagon (ring 0..6, local ids; apex 4 is c)
  // leaves a triangle on the outgoing edge (6 quads, 4 points for 4
  // triangles), or closes with a point m on that edge (7 quads, 5 points
  // for 5 triangles; the parent gets m as a degenerate quadrilateral). At
  // the root the closed form comes first: it costs less than a leftover
  // triangle and step 5.
  bool heptagon(LocalPatch& lp, Region& r, int a, int b, int c, bool is_root, int& split_m) {
    const t2q::Ring v = {0, 1, 2, 3, 4, 5, 6};
    auto leftover = [&] {
      const int apex = t2q::heptagon(lp, v);
      if (apex < 0) return false;
      ++cases[kHeptagon];
      r = {kTri, 0, apex, -1};
      return true;
    };
    if (!is_root && leftover()) return true;
    const auto m0 = lp.mark();
    for (const P2& x : edge_points(a, b, c, is_root)) {
      const int m = lp.add_new(x);
      if (t2q::heptagon_closed(lp, v, m)) {
        ++cases[kHeptagonClosed];
        if (is_root) { split_m = m; r = {}; }
        else r = {kDent, 0, m, -1};
        return true;
      }
      lp.rollback(m0);
    }
    return is_root && leftover();
  }

  bool pentagon_point(LocalPatch& lp, Region& r) {
    // B.2.2: pentagon 0..4 with the point 5.
    const auto m = lp.mark();
    // (i) leftover (v0, v1, q), hexagon (v1, v2, v3, v4, v0, q).
    if (good_triangle(lp.p[0], lp.p[1], lp.p[5])) {
      std::vector<P2> hp = {lp.p[1], lp.p[2], lp.p[3], lp.p[4], lp.p[0], lp.p[5]};
      if (simple_ccw(hp) && t2q::hexagon(lp, {1, 2, 3, 4, 0, 5})) {
        ++cases[kPentagonPoint]; r = {kTri, 0, 5, -1}; return true;
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
      if (t2q::quad_with_point(lp, quad, 5)) {
        ++cases[kPentagonPoint]; r = {kTri, 0, side == 0 ? 2 : 4, -1}; return true;
      }
      lp.rollback(m);
    }
    // (iii) the middle case (notes 3.5): the outgoing edge in the centre
    // triangle (v0, v1, v3): the type-1 split (v0, v1, p1), (v0, p1, v3, v4),
    // (v3, p1, v1, v2), then B.1.2 on the quad holding q (6 quads, 4 points).
    if (good_triangle(lp.p[0], lp.p[1], lp.p[3]) && good_triangle(lp.p[1], lp.p[2], lp.p[3]) &&
        good_triangle(lp.p[3], lp.p[4], lp.p[0])) {
      const P2 v0 = lp.p[0], v1 = lp.p[1], v2 = lp.p[2], v3 = lp.p[3], v4 = lp.p[4], q = lp.p[5];
      const auto region = t2q::clip({v0, v1, v3}, {{v3, v0}, {v4, v0}, {v3, v4}, {v1, v3}, {v2, v3}, {v1, v2}, {v0, v1}});
      if (region.size() >= 3) {
        const P2 c = t2q::centroid(region);
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
          const t2q::Ring A = {0, p1, 3, 4}, B = {3, p1, 1, 2};
          lp.quads.push_back(inA ? t2q::Quad{B[0], B[1], B[2], B[3]} : t2q::Quad{A[0], A[1], A[2], A[3]});
          if (t2q::quad_with_point(lp, inA ? A : B, 5)) {
            ++cases[kPentagonPointMid];
            r = {kTri, 0, p1, -1};
            return true;
          }
          lp.rollback(m);
        }
      }
    }
    return false;
  }

  bool hexagon_point(LocalPatch& lp, Region& r) {
    const auto m = lp.mark();
    auto good = [&](const t2q::Quad& q) { return good_quad(lp.p[q[0]], lp.p[q[1]], lp.p[q[2]], lp.p[q[3]]); };
    // The point joined to alternate vertices (T1 of B.1.1 with the point
    // given): 3 quads, no new point.
    for (int pi = 0; pi < 2; ++pi) {
      const t2q::Quad q0{pi, pi + 1, (pi + 2) % 6, 6}, q1{(pi + 2) % 6, (pi + 3) % 6, (pi + 4) % 6, 6},
          q2{(pi + 4) % 6, (pi + 5) % 6, pi, 6};
      if (good(q0) && good(q1) && good(q2)) {
        for (const auto& q : {q0, q1, q2}) lp.quads.push_back(q);
        ++cases[kHexagonPoint]; r = {}; return true;
      }
    }
    // The point cuts a quad off a corner; B.1.1 on the hexagon left.
    for (int j = 0; j < 6; ++j) {
      const t2q::Quad q{(j + 5) % 6, j, (j + 1) % 6, 6};
      if (!good(q)) continue;
      t2q::Ring rest = {0, 1, 2, 3, 4, 5};
      rest[j] = 6;
      std::vector<P2> rp;
      for (int k : rest) rp.push_back(lp.p[k]);
      if (!simple_ccw(rp)) continue;
      lp.quads.push_back(q);
      if (t2q::hexagon(lp, rest, 2)) { ++cases[kHexagonPoint]; r = {}; return true; }
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
        if (t2q::quad_with_point(lp, pt, 6)) { ++cases[kHexagonPoint]; r = {}; return true; }
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
  bool triangle_two_points(LocalPatch& lp, int c, Region& r) {
    const int lc = local_of(lp, c);
    if (lc != 3 && lc != 4) return false;
    for (const int apex : {lc, 7 - lc}) {
      const int q = 7 - apex;
      const P2 &A = lp.p[0], &B = lp.p[1], &Z = lp.p[apex], &Q = lp.p[q];
      const int o1 = orientation(B, Z, Q), o2 = orientation(Z, A, Q);
      if (!good_triangle(A, B, Z) || o1 == 0 || o2 == 0 || (o1 > 0 && o2 > 0)) continue;
      if (t2q::quad_with_point(lp, {1, 2, 0, apex}, q)) {
        ++cases[kTriangleTwoPoints];
        r = {kTri, 0, apex, -1};
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
  bool pair_and_nonempty(LocalPatch& lp, const Kid* kid, int a, int b, int c, Region& r) {
    const Kid& pair = kid[0].r.type == kQuadR ? kid[0] : kid[1];
    const Kid& nt = kid[0].r.type == kNTri ? kid[0] : kid[1];
    std::vector<int> ring = {a, b};
    if (&pair == &kid[0]) { ring.push_back(pair.r.x); ring.push_back(pair.r.y); }
    ring.push_back(c);
    if (&pair == &kid[1]) { ring.push_back(pair.r.x); ring.push_back(pair.r.y); }
    std::rotate(ring.begin(), std::find(ring.begin(), ring.end(), nt.q), ring.end());
    Ring P;
    for (int g : ring) P.push_back(local_of(lp, g));
    const int lp_ = local_of(lp, nt.p), lq = local_of(lp, nt.q), lx = local_of(lp, nt.r.x),
              ly = local_of(lp, nt.r.y);
    if (P[1] != lp_ || std::find(P.begin(), P.end(), -1) != P.end() || lx < 0 || ly < 0) return false;
    std::vector<P2> pp;
    for (int i : P) pp.push_back(lp.p[i]);
    if (!simple_ccw(pp)) return false;
    const auto m0 = lp.mark();
    const int z = t2q::pentagon(lp, P, nullptr, 1);
    if (z >= 0 && t2q::quad_with_point(lp, {lp_, z, lq, lx}, ly)) {
      ++cases[kPairNonEmpty];
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
        if (simple_ccw(hp) && t2q::hexagon(lp, {lq, m, lp_, P[2], P[3], P[4]}, 2) &&
            t2q::quad_with_point(lp, {lp_, m, lq, lx}, ly)) {
          ++cases[kPairNonEmpty];
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
  bool two_nonempty(LocalPatch& lp, const Kid* kid, int a, int b, int c, bool is_root, Region& r, int& split_m) {
    const auto m0 = lp.mark();
    for (const P2& x : edge_points(a, b, c, is_root)) {
      const int m = lp.add_new(x);
      bool ok = true;
      for (int k = 0; k < 2 && ok; ++k) {
        const Kid& nt = kid[k];
        ok = t2q::quad_with_point(lp, {local_of(lp, nt.p), m, local_of(lp, nt.q), local_of(lp, nt.r.x)},
                                  local_of(lp, nt.r.y));
      }
      if (ok) {
        ++cases[kTwoNonEmpty];
        if (is_root) { split_m = m; r = {}; }
        else r = {kDent, 0, m, -1};
        return true;
      }
      lp.rollback(m0);
    }
    return false;
  }

  // Step 5: whatever the root leaves on its edge (a, b).
  void finish_root(int u, int a, int b, Region r, double at, int split_m) {
    if (split_m >= 0) {
      split_segment(a, b, split_m);
      repair(u, a, b, split_m);
    }
    if (r.type == kEmpty) return;
    // r is a triangle (a, b, z).
    const int z = r.x;
    const bool outer = comp_parent[comp[u]] < 0;
    if (outer && opt.allow_outside) {
      // The point s outside, right of a -> b: the quad (a, s, b, z) is
      // strictly convex for s in L(z, a) and L(b, z) (placement rule);
      // the centroid of that wedge cut at a height of |ab| / 4 (Fig. 3.16).
      LocalPatch lp;
      const int la = lp.add_known(pts[a], a), lb = lp.add_known(pts[b], b), lz = lp.add_known(pts[z], z);
      const P2 A = pts[a], Bp = pts[b], Z = pts[z];
      const P2 n = {0.25 * (Bp[1] - A[1]), -0.25 * (Bp[0] - A[0])};
      const auto wedge = t2q::clip({A, {A[0] + n[0], A[1] + n[1]}, {Bp[0] + n[0], Bp[1] + n[1]}, Bp}, {{Z, A}, {Bp, Z}});
      if (wedge.size() >= 3) {
        const int ls = lp.add_new(t2q::centroid(wedge));
        if (good_quad(lp.p[la], lp.p[ls], lp.p[lb], lp.p[lz])) {
          lp.quads.push_back({la, ls, lb, lz});
          commit_region(lp, {}, at);
          split_segment(a, b, int(pts.size()) - 1);
          ++out.steiner_outside;
          ++cases[kRootOutside];
          return;
        }
      }
    }
    // Joe's split of (a, b, z) with its point on the edge (a, b).
    LocalPatch lp;
    const int la = lp.add_known(pts[a], a), lb = lp.add_known(pts[b], b), lz = lp.add_known(pts[z], z);
    const int lm = lp.add_new({0.5 * (pts[a][0] + pts[b][0]), 0.5 * (pts[a][1] + pts[b][1])});
    if (!t2q::joe_split(lp, lz, la, lm, lb))
      throw Error("internal error: Joe's split failed at edge " + edge_name(a, b), in.path);
    const std::size_t before = pts.size();
    commit_region(lp, {}, at);
    const int m = int(before);  // the first new point is lm
    ++cases[kRootJoe];
    split_segment(a, b, m);
    repair(u, a, b, m);
  }

  // ------------------------------------------------------------ driver
  void run() {
    components();
    par.assign(T.size(), -1);
    pslot.assign(T.size(), 0);
    reg.assign(T.size(), Region{});
    std::vector<int> order;
    for (auto ci = comp_order.rbegin(); ci != comp_order.rend(); ++ci) {
      const int C = *ci, PC = comp_parent[C];
      // Collect the component (it may have grown by repairs), find the root.
      order.clear();
      order.push_back(comp_seed[C]);
      par[comp_seed[C]] = -2;
      for (std::size_t i = 0; i < order.size(); ++i) {
        const int t = order[i];
        for (int j = 0; j < 3; ++j) {
          const int w = nb[t][j];
          if (w >= 0 && !(con[t] >> j & 1) && par[w] == -1) { par[w] = -2; order.push_back(w); }
        }
      }
      // The root edge: the first candidate, or the root_pick-th one (the
      // size-bound retry in tri2quad() tries other spanning trees).
      int root = -1, rslot = -1, seen_roots = 0;
      for (int strict = avoid ? 1 : 0; strict >= 0 && root < 0; --strict)
        for (int t : order) {
          for (int j = 0; j < 3; ++j) {
            const int w = nb[t][j];
            if (strict && w < 0 && avoid->count(edge_key(T[t][j], T[t][(j + 1) % 3]))) continue;
            if ((PC < 0 && w < 0) || (PC >= 0 && w >= 0 && (con[t] >> j & 1) && comp[w] == PC)) {
              if (root < 0 || seen_roots <= root_pick) { root = t; rslot = j; }
              ++seen_roots;
            }
          }
          if (root >= 0 && seen_roots > root_pick) break;
        }
      if (root < 0) throw Error("internal error: component without a root edge", in.path);
      for (int t : order) par[t] = -1;
      // BFS tree from the root over non-constraint dual edges.
      order.clear();
      order.push_back(root);
      par[root] = -3;
      pslot[root] = std::int8_t(rslot);
      for (std::size_t i = 0; i < order.size(); ++i) {
        const int t = order[i];
        for (int j = 0; j < 3; ++j) {
          const int w = nb[t][j];
          if (w >= 0 && !(con[t] >> j & 1) && par[w] == -1) {
            par[w] = t;
            for (int k = 0; k < 3; ++k) if (nb[w][k] == t && T[w][k] == T[t][(j + 1) % 3]) pslot[w] = std::int8_t(k);
            order.push_back(w);
          }
        }
      }
      // Bottom-up: reverse BFS order visits the levels V_d, ..., V_0.
      for (std::size_t i = order.size(); i-- > 1;) process(order[i], false);
      process(root, true);
    }
  }
};

} // namespace

// The thesis's conversion alone.
static Tri2QuadResult convert(const Tri2QuadInput& in, const Tri2QuadOptions& opt,
                              const std::unordered_set<std::uint64_t>* avoid = nullptr) {
  Tri2QuadResult out;
  out.allow_outside = opt.allow_outside;
  Converter cv(in, opt, out);
  cv.avoid = avoid;
  cv.setup();
  out.points.reserve(in.points.size() + in.triangles.size() / 4);
  out.quads.reserve(in.triangles.size() * 2 / 3 + 16);
  cv.run();
  // The local constructions do not all stay inside the per-node budget of
  // Table 3.1 (notes: B.1.1 and B.2.2 may need one quad more, a dent or a
  // nested closing costs extra), which only shows on small meshes where the
  // additive 4h does not absorb it. Then other root edges (other BFS trees)
  // are tried, and the smallest result kept.
  auto excess = [&](const Tri2QuadResult& r) {
    return std::max<long>(0, long(r.quads.size()) - long(r.quad_bound())) +
           std::max<long>(0, long(r.steiner) - long(r.steiner_bound(opt.allow_outside)));
  };
  std::size_t retries = 0;
  for (int pick = 1; opt.size_retry && pick <= 12 && excess(out) > 0; ++pick) {
    Tri2QuadResult alt;
    alt.allow_outside = opt.allow_outside;
    Converter c2(in, opt, alt);
    c2.root_pick = pick;
    c2.avoid = avoid;
    c2.setup();
    c2.run();
    ++retries;
    if (excess(alt) < excess(out)) {
      out = std::move(alt);
      std::copy(std::begin(c2.cases), std::end(c2.cases), std::begin(cv.cases));
      cv.segs.swap(c2.segs);
    }
  }
  // Segments: the constraint and boundary edges as chains of quad edges.
  std::vector<std::pair<std::uint64_t, int>> s(cv.segs.begin(), cv.segs.end());
  std::sort(s.begin(), s.end());
  for (const auto& [k, m] : s) {
    out.segments.push_back({int(k >> 32), int(k & 0xffffffffu)});
    out.segment_markers.push_back(m);
  }
  for (int i = 0; i < kNumCases; ++i) out.cases.push_back({kCaseNames[i], cv.cases[i]});
  out.cases.push_back({"size_bound_retry", retries});
  return out;
}

// Pairs first (--pair-above): adjacent triangles that make a quad of Joe's
// mu >= the threshold are merged greedily, best first; the thesis's
// conversion then runs on the other triangles, with the merged quads as
// holes. A merged quad on whose edge it puts a Steiner point goes back to
// the triangles and the conversion runs again. If that does not settle, or
// the result exceeds the thesis's size bounds (of the whole mesh), the plain
// conversion's result is returned.
Tri2QuadResult tri2quad(const Tri2QuadInput& in, const Tri2QuadOptions& opt) {
  if (!(opt.pair_above > 0)) return convert(in, opt);
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
  Converter cv(in, opt, whole);
  cv.setup();
  cv.components();
  const auto& T = cv.T;
  const auto& nbr = cv.nb;
  const std::size_t h = whole.components;
  // Constraint bits of interior edges only (con also marks the boundary).
  std::vector<std::uint8_t> conb(nt, 0);
  for (std::size_t t = 0; t < nt; ++t)
    for (int j = 0; j < 3; ++j)
      if ((cv.con[t] >> j & 1) && nbr[t][j] >= 0) conb[t] |= std::uint8_t(1u << j);
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
        if (!(cv.con[t] >> j & 1) || (u > int(t) && mate[std::size_t(u)] < 0)) continue;
        const int a = T[t][j], b = T[t][(j + 1) % 3];
        r.constraints.push_back({a, b});
        r.constraint_markers.push_back(cv.segs.at(edge_key(a, b)));
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
  // input boundary (cv.segs, with their markers).
  std::vector<std::pair<std::uint64_t, int>> segs;
  for (std::size_t k = 0; k < out.segments.size(); ++k) {
    const std::uint64_t kk = edge_key(out.segments[k][0], out.segments[k][1]);
    if (holes.count(kk) && !cv.segs.count(kk)) continue;
    segs.push_back({kk, out.segment_markers[k]});
  }
  for (std::size_t m = 0; m < merged.size(); ++m) {
    if (!alive(m)) continue;
    for (const int t : {merged[m].t, merged[m].u})
      for (int j = 0; j < 3; ++j) {
        const int u = nbr[std::size_t(t)][j];
        if (u == merged[m].t || u == merged[m].u) continue;  // the merged diagonal
        const std::uint64_t kk = edge_key(T[std::size_t(t)][j], T[std::size_t(t)][(j + 1) % 3]);
        const auto c = cv.segs.find(kk);  // constraints and boundary
        if (c != cv.segs.end()) segs.push_back({kk, c->second});
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

Json Tri2QuadResult::to_json() const {
  Json j = Json::object();
  j["triangles"] = triangles;
  j["components"] = components;
  j["quads"] = quads.size();
  j["steiner_points"] = steiner;
  j["steiner_outside"] = steiner_outside;
  j["repair_splits"] = repairs;
  j["quad_bound"] = quad_bound();
  j["steiner_bound"] = steiner_bound(allow_outside);
  j["within_bounds"] = within_bounds();
  j["quads_per_triangle"] = double(quads.size()) / double(triangles);
  j["steiner_per_triangle"] = double(steiner) / double(triangles);
  const QualityReport quality = quality_report(points, quads);
  j["non_convex"] = quality.non_convex;
  Json counts = Json::object();
  for (const auto& [name, n] : cases) counts[name] = n;
  j["cases"] = counts;
  j["quality"] = quality.to_json();
  return j;
}

std::string Tri2QuadResult::failed_guarantee() const {
  std::size_t non_convex = 0;
  for (const auto& q : quads)
    if (!is_strictly_convex(points[q[0]], points[q[1]], points[q[2]], points[q[3]])) ++non_convex;
  if (non_convex) return std::to_string(non_convex) + " quads not strictly convex";
  if (!within_bounds())
    return "size bound exceeded (quads " + std::to_string(quads.size()) + " / " + std::to_string(quad_bound()) +
           ", Steiner points " + std::to_string(steiner) + " / " + std::to_string(steiner_bound(allow_outside)) + ")";
  return "";
}

Tri2QuadInput tri2quad_input(PlanarMesh&& mesh, const std::string& path) {
  Tri2QuadInput in;
  in.path = path;
  in.index_base = mesh.first_index;
  in.points = std::move(mesh.points);
  in.triangles.reserve(mesh.elements.size());
  for (std::size_t i = 0; i < mesh.elements.size(); ++i) {
    const auto& e = mesh.elements[i];
    if (e.size() != 3) throw Error("element " + std::to_string(i + mesh.first_index) + " is not a triangle", path);
    in.triangles.push_back({e[0], e[1], e[2]});
  }
  // The per-element vectors cost ~56 bytes a triangle: free them now.
  std::vector<std::vector<int>>().swap(mesh.elements);
  const auto& attributes = mesh.element_attributes;
  if (!attributes.empty() && attributes.size() == in.triangles.size()) {
    bool any = false;
    for (const auto& a : attributes) any = any || !a.empty();
    if (any)
      for (const auto& a : attributes) in.region.push_back(a.empty() ? 0.0 : a[0]);
  }
  std::vector<std::vector<double>>().swap(mesh.element_attributes);
  in.constraints = std::move(mesh.segments);
  in.constraint_markers = std::move(mesh.segment_markers);
  return in;
}

PlanarMesh planar_mesh(const Tri2QuadResult& r, int first_index) {
  PlanarMesh q;
  q.first_index = first_index;
  q.points = r.points;
  q.elements.reserve(r.quads.size());
  for (const auto& f : r.quads) q.elements.push_back({f[0], f[1], f[2], f[3]});
  for (double a : r.region) q.element_attributes.push_back({a});
  q.segments = r.segments;
  q.segment_markers = r.segment_markers;
  return q;
}

} // namespace imgmesh
