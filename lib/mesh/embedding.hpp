// What the surface certificate (surface_certificate.hpp) asks of a triangle
// surface's geometry: whether two of its triangles intersect other than in
// a shared edge or vertex (CGAL Polygon_mesh_processing's
// self_intersections, exact predicates), how its components nest and which
// side of it a point is on (CGAL's Side_of_triangle_mesh: rays against the
// triangles, exact predicates, another ray when one grazes an edge; for
// many points, LineSides: axis-parallel rays through bins, exact), and
// distances to a component's triangles (an AABB tree); the same
// intersection test on a triangle soup (any number of triangles at an edge,
// as surface nets' interfaces meet along curves), pair by pair or over all
// pairs. CGAL stays in embedding.cpp.
#pragma once
#include "image/grid.hpp"

#include <array>
#include <cstddef>
#include <memory>
#include <vector>

namespace imgmesh {

struct SelfIntersections {
  std::size_t pairs = 0;       // intersecting pairs found, degenerate triangles included (at most the cap)
  std::size_t degenerate = 0;  // triangles whose corners are collinear (each a pair with itself)
  bool capped = false;         // the search stopped at the cap: there may be more
  std::array<std::size_t, 2> first{0, 0};  // the least pair found (triangle ids, ascending)
};
// The summary of the pairs found by a search stopped at `cap` (0: no cap).
SelfIntersections summarize_intersections(const std::vector<std::array<std::size_t, 2>>& pairs, std::size_t cap);

// Triangle soups: triangles of vertex ids into `points`, vertices shared by
// id, any number of triangles at an edge (a multi-label mesh, which
// SurfaceGeometry cannot hold). The rules are self_intersections' (CGAL's do_faces_intersect): two
// triangles sharing an edge cross when they are coplanar with their third
// corners on the same side of it; sharing one vertex, when the edge of
// either opposite it meets the other; sharing none, when they meet at all
// (touching counts). A degenerate triangle (collinear corners) is a pair
// with itself and is tested against no other.
bool triangle_degenerate(const std::vector<Vec3>& points, const std::array<int, 3>& t);
// Whether two non-degenerate triangles cross by those rules (exact).
bool triangles_cross(const std::vector<Vec3>& points, const std::array<int, 3>& a, const std::array<int, 3>& b);
// Every crossing pair of the soup (a triangle given twice crosses its
// copy), found by box intersection over all its triangles (the reference
// for local searches, and for soups without a lattice): triangle ids, each
// pair ascending, sorted; the search stops at `cap` pairs (which ones are
// found first is CGAL's order). Points must be finite.
std::vector<std::array<std::size_t, 2>> soup_crossing_pairs(const std::vector<Vec3>& points,
                                                            const std::vector<std::array<int, 3>>& triangles,
                                                            std::size_t cap = std::size_t(-1));

// Sides of points against a closed surface (each edge in an even number
// of triangles), without SurfaceGeometry's mesh and tree: a ray along the
// axis from each point, through the triangles whose projection on the
// plane of the other two axes holds the point's strictly (a grid of bins
// over that plane finds them; the list is kept while points come on one
// line, as voxel centres do along x), each crossed beyond the point or not
// by one exact orientation; inside when an odd number are. Any ray's
// parity is the same, so these are SurfaceGeometry::side's answers; a line
// through the projection of an edge or a vertex has none (kGrazing: ask
// another axis's, or SurfaceGeometry::side). points and triangles are kept
// by reference.
class LineSides {
public:
  static constexpr int kGrazing = 2;
  LineSides(const std::vector<Vec3>& points, const std::vector<std::array<int, 3>>& triangles, int axis = 0);
  ~LineSides();
  LineSides(const LineSides&) = delete;
  LineSides& operator=(const LineSides&) = delete;
  // -1 inside, 0 on a triangle, 1 outside, or kGrazing.
  int side(const Vec3& p);

private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

// SurfaceGeometry(points, triangles, component, components)
// .nesting_depths(component_of), by each component's LineSides (along x,
// then y, z where a line grazes; its SurfaceGeometry's rays where all do):
// the same depths without the mesh, trees and search tree of them all.
std::vector<int> nesting_depths(const std::vector<Vec3>& points, const std::vector<std::array<int, 3>>& triangles,
                                const std::vector<int>& component, std::size_t components,
                                const std::vector<int>& component_of);

class SurfaceGeometry {
public:
  // triangles: a 2-manifold, consistently oriented surface (mesh_topology
  // says so: checked by the caller; Error if CGAL cannot build it); points
  // in no triangle are ignored. component: per triangle, its component in
  // 0 .. components - 1.
  SurfaceGeometry(const std::vector<Vec3>& points, const std::vector<std::array<int, 3>>& triangles,
                  const std::vector<int>& component, std::size_t components);
  ~SurfaceGeometry();
  SurfaceGeometry(const SurfaceGeometry&) = delete;
  SurfaceGeometry& operator=(const SurfaceGeometry&) = delete;

  // Pairs of triangles that meet other than in a shared edge or vertex
  // (triangles of different components included), up to `cap`.
  SelfIntersections self_intersections(std::size_t cap) const;
  // The same pairs themselves (triangle ids, each pair ascending), up to
  // `cap` (> 0): for callers that repair them (surfacenets' untangling).
  std::vector<std::array<std::size_t, 2>> intersecting_pairs(std::size_t cap) const;
  // Closed components only: per component, how many others enclose it:
  // those its first vertex is strictly inside (by vertex id; a vertex on
  // the other's surface is passed over for the next). component_of: per
  // vertex, its component or -1 (MeshTopology's).
  std::vector<int> nesting_depths(const std::vector<int>& component_of) const;
  // World distance from p to the triangles of a component.
  double distance(const Vec3& p, int component) const;
  // Closed surface only: -1 when p is inside (enclosed by an odd number of
  // components), 0 on a triangle, 1 outside.
  int side(const Vec3& p) const;

private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

} // namespace imgmesh
