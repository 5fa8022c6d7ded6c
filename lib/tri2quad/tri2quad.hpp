// Conversion of a (constrained) triangle mesh into a strictly convex
// quadrilateral mesh of bounded size (thesis chapter 3, appendix B).
//
// Unconstrained part (3.2.1): a BFS spanning tree of the dual graph, rooted
// at a triangle on a boundary edge, is pruned bottom-up (levels V_d .. V_0).
// Every node combines its own triangle with what its children left over (a
// triangle, a non-convex quadrilateral or a non-empty triangle, all attached
// to the shared edge) and quadrangulates the small polygon so formed with
// the lemmas of appendix B, leaving at most a triangle on its outgoing edge.
// Constrained part (3.3): the dual graph is cut at constraint edges, its
// components form the tree T^c, processed bottom-up; a point a component puts
// on the constraint edge shared with its parent splits the parent's triangle
// (the repair of Fig. 3.23) before the parent is processed.
//
// Every output quad is checked with exact predicates; a configuration whose
// construction fails its checks falls back to a split that always works (an
// odd-degree edge subset on the region's dual tree: triangles with three
// split edges get de Berg's 3 quads, with one split edge Joe's 5 quads),
// counted in the stats, so the output is always strictly convex.
// Every case of steps 1-5 has a construction within the thesis's per-step
// budget, so the size bounds hold by construction; only when a fallback
// ran (make_dents, the safe split) could a result exceed them, and then it
// is redone from other root edges and the smallest kept (a safety net,
// counted as size_bound_retry; never used on the random test meshes).
// conversion.hpp names the file of each part.
#pragma once
#include "planar/triangle_io.hpp"
#include "util/json.hpp"

#include <array>
#include <cstddef>
#include <string>
#include <utility>
#include <vector>

namespace imgmesh {

struct Tri2QuadInput {
  std::vector<Point2> points;
  std::vector<std::array<int, 3>> triangles;  // any orientation (made CCW)
  std::vector<double> region;                 // empty or one attribute a triangle
  std::vector<std::array<int, 2>> constraints;  // interior constraint (and boundary) segments
  std::vector<int> constraint_markers;          // empty or one a constraint
  int index_base = 0;      // how ids are printed in error messages
  std::string path;        // for error messages
};

struct Tri2QuadOptions {
  // The thesis's original step 5: one Steiner point outside the domain on
  // the root's boundary edge. Default: Joe's 5-quad split of the leftover
  // triangle, with its point on that edge (no point outside).
  bool allow_outside = false;
  // Rerun from other root edges when the result exceeds a size bound (off
  // only to measure the constructions themselves).
  bool size_retry = true;
  // Beyond the thesis: first merge adjacent triangles whose quad has Joe's
  // mu of at least this (degrees; 0: off), best first, and convert the rest
  // around them (see tri2quad()).
  double pair_above = 0;
  // Tests only: false takes every two-triangle polygon as a quad, convex or
  // not (step 4(c) without its test), so that the final convexity check
  // must find the bad quads (tri2quad's hidden --skip-convexity-test).
  bool convexity_test = true;
};

struct Tri2QuadResult {
  std::vector<Point2> points;                 // input points first, then Steiner points
  std::vector<std::array<int, 4>> quads;      // CCW, strictly convex
  std::vector<double> region;                 // one a quad when the input had regions
  std::vector<std::array<int, 2>> segments;   // constraints and boundary as chains of quad edges
  std::vector<int> segment_markers;
  std::size_t input_points = 0, triangles = 0, components = 0;  // t and h
  std::size_t steiner = 0, steiner_outside = 0, repairs = 0;
  // How often each step / case ran, in a fixed order (name, count).
  std::vector<std::pair<std::string, std::size_t>> cases;
  bool allow_outside = false;  // the option the Steiner bound is for
  std::size_t quad_bound() const { return 3 * triangles / 2 + 4 * components; }
  std::size_t steiner_bound(bool allow_outside) const {
    return triangles + (allow_outside ? 3 : 7) * components;
  }
  bool within_bounds() const {
    return quads.size() <= quad_bound() && steiner <= steiner_bound(allow_outside);
  }
  // The counts, the bounds, the cases and the quality of the quads (--stats).
  Json to_json() const;
  // Quads that are not strictly convex, else a size bound exceeded; empty
  // when both guarantees hold.
  std::string failed_guarantee() const;
};

// Throws Error (naming the edge, ids printed with index_base) when the input
// breaks the input restriction of 3.3 (a constraint edge with the same
// component on both sides, e.g. a dangling edge as in Fig. 3.26), when a
// constraint is not an edge of the mesh, the mesh is not a 2-manifold, or a
// triangle is degenerate.
Tri2QuadResult tri2quad(const Tri2QuadInput& in, const Tri2QuadOptions& opt = {});

// The input of tri2quad() from a planar mesh read from `path` (named in
// errors): its triangles, its segments as constraints with their markers
// (1 where it has none), its first element attribute as the region of each
// triangle (none when no element has one). The mesh's vectors are released
// as they are copied. Throws Error naming an element that is not a triangle.
Tri2QuadInput tri2quad_input(PlanarMesh&& mesh, const std::string& path);
// The quad mesh of a result as a planar mesh (regions as element attributes,
// segments with their markers), its ids printed from first_index.
PlanarMesh planar_mesh(const Tri2QuadResult& result, int first_index);

} // namespace imgmesh
