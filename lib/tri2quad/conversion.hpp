// The state of one run of the thesis's conversion (3.2.1, 3.3), shared by
// the files that do its parts. Internal to lib/tri2quad (and its tests).
//
//   build_mesh()              dual_tree.cpp  triangles made CCW, neighbours,
//                                            constrained edges, the input
//                                            restriction of 3.3
//   build_component_tree()    dual_tree.cpp  the components of the dual graph
//                                            cut at constraints, and T^c
//   convert_components()      dual_tree.cpp  T^c bottom-up; in each component
//                                            a BFS spanning tree of the dual
//                                            graph, pruned bottom-up:
//     process_node()          steps.cpp      steps 1-4 at a node, step 5
//                                            (finish_root) at the root
//     make_dents(), safe_split()  fallback.cpp  when no construction passes
//     repair()                repair.cpp     Fig. 3.23: a point a component
//                                            puts on its parent's edge
#pragma once
#include "tri2quad/polygons.hpp"
#include "tri2quad/tri2quad.hpp"

#include <array>
#include <cstddef>
#include <cstdint>
#include <string>
#include <unordered_map>
#include <unordered_set>
#include <vector>

namespace imgmesh::tri2quad_detail {

// How often each step / case ran (Tri2QuadResult::cases, in this order).
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
  kFallback,          // safe odd-degree split of a region (see tri2quad.hpp)
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
inline constexpr const char* kCaseNames[kNumCases] = {
    "4c_convex_quad",        "4c_quad_to_grandparent", "B21_pentagon_ear",
    "4b_B21_type1",          "4cii_B21_type2",         "B21_type3_apex_hexagon",         "4ci_4ciii_B11_hexagon",
    "4cvf_B31_heptagon",     "3_nonempty_triangle",
    "3b_B12_quad_point",     "3c_B22_pentagon_point",  "4civ_hexagon_point",
    "5bd_joe_split",         "5bd_outside_point",      "5c_B12_nested",
    "fallback_dent_triangle", "fallback_dent_nonempty", "fallback_split",        "3_3_repair_split",
    "5_B11_root_pentagon_edge_point", "B22_middle_type1_B12", "4civ_B21_B12_pair_nonempty",
    "3d_edge_point_B12_twice",  "3c_4cvde_leftover_B12", "B31_heptagon_edge_point", "fallback_pair_nested",
    "4cii_B21_type3_edge_point"};

// What a node leaves on its outgoing edge (p, q) for its parent: nothing, a
// triangle (p, q, x), a non-convex quadrilateral (p, q, x, y) (diagonal 0:
// split at (q, y), else at (p, x)), a non-empty triangle (p, q, x) around y,
// or a dent: the point x on that edge, leaning into the parent.
enum LeftoverType : std::uint8_t { kNoLeftover = 0, kLeftoverTriangle, kLeftoverQuad, kLeftoverNonEmpty, kLeftoverDent };
struct Leftover {
  LeftoverType type = kNoLeftover;
  std::uint8_t diagonal = 0;
  int x = -1, y = -1;
};

// A child's leftover and its outgoing edge (p, q) (its parent's edge (q, p)).
struct Child {
  Leftover leftover;
  int p = -1, q = -1;
};

struct Conversion {
  const Tri2QuadInput& input;
  const Tri2QuadOptions& options;
  Tri2QuadResult& result;
  std::vector<P2>& points;  // result.points: the input's, then the Steiner points
  // The mesh, counter-clockwise; the edge in slot j of triangle t is
  // (triangles[t][j], triangles[t][j + 1]). Repairs append triangles.
  std::vector<std::array<int, 3>> triangles;
  std::vector<std::array<int, 3>> neighbours;  // across each slot, -1 on the boundary
  std::vector<std::uint8_t> constrained;       // bit j: slot j is a constraint or boundary edge
  std::vector<double> attribute;               // the region of each triangle
  bool has_regions = false;
  std::vector<int> component;                  // each triangle's component of the cut dual graph
  // T^c: the components in BFS order from the outer ones, each one's parent
  // component (-1 for a root), and a triangle of each.
  std::vector<int> component_order, component_parent, component_seed;
  // The spanning tree of a component: each triangle's parent (-3 at the
  // root) and the slot of its outgoing edge; what it leaves its parent.
  std::vector<int> parent;
  std::vector<std::int8_t> parent_slot;
  std::vector<Leftover> leftover;
  std::unordered_map<std::uint64_t, int> segments;  // current constraint/boundary edges -> marker
  std::size_t case_counts[kNumCases] = {};
  // The root_pick-th candidate root edge of each component (the size-bound
  // retry tries other spanning trees).
  int root_pick = 0;
  // Boundary edges that should not take a Steiner point (pair-first: the
  // edges of merged quads): a root edge is taken elsewhere when possible.
  const std::unordered_set<std::uint64_t>* avoid_edges = nullptr;
  // Scratch buffers kept across nodes: no allocation on the common paths.
  std::vector<int> scratch_boundary, scratch_inner, scratch_sorted, scratch_ids;
  std::vector<std::array<int, 3>> scratch_triangles, scratch_child_triangles;
  LocalPatch scratch_patch;

  Conversion(const Tri2QuadInput& in, const Tri2QuadOptions& opt, Tri2QuadResult& out)
      : input(in), options(opt), result(out), points(out.points) {}

  std::string vid(int v) const { return std::to_string(v + input.index_base); }
  std::string edge_name(int a, int b) const { return "(" + vid(a) + ", " + vid(b) + ")"; }

  // dual_tree.cpp
  struct VertexTriangles {
    std::vector<std::uint32_t> start, around;  // the triangles at v: around[start[v] .. start[v + 1])
  };
  void build_mesh();
  void orient_triangles();
  VertexTriangles triangles_around_vertices() const;
  int slot_of(int w, int x, int y) const;
  void find_neighbours(const VertexTriangles& around);
  void mark_constraints(const VertexTriangles& around);
  void check_input_restriction() const;
  void build_component_tree();
  void convert_components();

  // steps.cpp
  enum class Closing { kClosed, kOpen, kPassedUp };
  void process_node(int u, bool is_root);
  void node_polygon(int u, int s0, Child* child);
  bool small_node(int u, int c);
  bool is_pinched();
  Closing close_polygon(int u, bool is_root, const Child* child, LocalPatch& lp, Leftover& r, int& split_m);
  bool pentagon_leaving_triangle(LocalPatch& lp, Leftover& r, int hexagon_budget);
  bool pentagon_edge_point(LocalPatch& lp, Leftover& r, int a, int b, int c, bool is_root, int& split_m,
                           int hexagon_budget);
  static void leftover_triangles(const Leftover& r, int p, int q, std::vector<std::array<int, 3>>& tris);
  static void leftover_boundary(const Leftover& r, std::vector<int>& b, std::vector<int>& inner);
  static int local_of(const LocalPatch& lp, int g);
  static void split_own(std::vector<std::array<int, 3>>& tris, int p, int q, int m);
  Leftover commit_region(LocalPatch& lp, Leftover r, double a, int* local_to_global = nullptr);
  std::vector<P2> edge_points(int a, int b, int c, bool is_root) const;
  bool close_heptagon(LocalPatch& lp, Leftover& r, int a, int b, int c, bool is_root, int& split_m);
  bool pentagon_point(LocalPatch& lp, Leftover& r);
  bool hexagon_point(LocalPatch& lp, Leftover& r);
  bool triangle_two_points(LocalPatch& lp, int c, Leftover& r);
  bool pair_and_nonempty(LocalPatch& lp, const Child* child, int a, int b, int c, Leftover& r);
  bool two_nonempty(LocalPatch& lp, const Child* child, int a, int b, int c, bool is_root, Leftover& r,
                    int& split_m);
  void finish_root(int u, int a, int b, Leftover r, double at, int split_m);

  // fallback.cpp
  bool make_dents(int u, int s0);
  Leftover safe_split(LocalPatch& lp, const std::vector<std::array<int, 3>>& tris, bool root, int* split_m);

  // repair.cpp
  void split_segment(int a, int b, int m);
  void repair(int from, int a, int b, int m);
};

// The thesis's conversion alone, with the size-bound retry (tri2quad.cpp).
Tri2QuadResult convert(const Tri2QuadInput& in, const Tri2QuadOptions& opt,
                       const std::unordered_set<std::uint64_t>* avoid_edges = nullptr);
// --pair-above (pair_above.cpp).
Tri2QuadResult pairs_first(const Tri2QuadInput& in, const Tri2QuadOptions& opt);

} // namespace imgmesh::tri2quad_detail
