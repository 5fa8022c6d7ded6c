// implicit2tet --outside: the box B that region 2 fills, its 8 corners in
// the surface mesher's triangulation so that the convex hull is B, and
// Shewchuk's boundary rule (Tetrahedral mesh generation by Delaunay
// refinement, 1998) for a bad cell whose circumcentre c cannot go in: c
// outside B, or c in the diametral ball of a box subsegment or subfacet (a
// hull edge on an edge of B, a hull triangle) of its conflict zone. Then
//   an encroached subsegment: split at its midpoint;
//   else the encroached subfacet (c outside B: the largest hull triangle
//   in the conflict zone of c's projection onto B): its circumcentre p,
//   unless p encroaches a subsegment or lies off its face, when that
//   subsegment is split instead.
// Private to lib/volume (CGAL).
//
// Termination (why B is the image extent, half a voxel beyond the samples):
// S lies in the cubes of voxel centres, so every point of the box is at
// least g = min spacing / 2 from S. Box points are inserted without any
// test against the surface Delaunay balls: a box point never makes the
// surface refine near the box (the cascade box split -> facet split ->
// smaller box split ...), and if its Voronoi cell reaches S, the restricted
// facet it makes has a surface ball of radius >= g, whose centre goes in
// (off-surface facets, tet_refinement.cpp) >= g from every vertex: finitely
// many on S. Each box point goes in at least `floor` from every vertex
// (else it is refused and the bad cell stays, reported), so the box points
// are a floor-packing of the box's surface: finitely many. The cells: a
// circumcentre of a cell with radius-edge ratio above R >= 2 is more than
// 2 l_min from every vertex, and l_min >= m, the least insertion radius so
// far, so it never lowers m; size-bad cells' are farther than --cell-size;
// slivers', encroached facets' and box points have floors (1e-3 voxel,
// `floor`). So within a round every point goes in at least min(m, floors)
// > 0 from the others, inside bounded B: finitely many; rounds are capped.
#pragma once
#include "surface/delaunay_types.hpp"

#include <array>
#include <vector>

namespace imgmesh::surface_detail {

class BoxRefinement {
public:
  // B = [lo, hi] in local coordinates; floor: the least distance from a box
  // point to the other vertices when it goes in.
  BoxRefinement(const Vec3& lo, const Vec3& hi, double floor) : lo_(lo), hi_(hi), floor_(floor) {}

  std::array<Vec3, 8> corners() const;
  bool contains(const Point& p) const;  // closed
  Point project(const Point& p) const;  // the point of B nearest p
  const Vec3& lo() const { return lo_; }
  const Vec3& hi() const { return hi_; }

  enum Kind { kNone, kSegment, kFacet, kRefused };
  struct Split {
    Kind kind = kNone;
    Vec3 x{0, 0, 0};
    Ch near;  // a cell in conflict with x, to start its insertion
  };
  // What to insert instead of circumcentre c, given the conflict zone
  // (finite and infinite cells) of c, or of its projection onto B when c
  // is beyond B: kNone when c is in B and encroaches no box subsegment or
  // subfacet of the zone.
  Split split_for(const Tr& tr, const Point& c, const std::vector<Ch>& zone) const;

private:
  struct Sub {
    Vh a, b, d;  // d null for a subsegment
    Vec3 centre;
    double r2;
  };
  int bound(const Point& p, int axis) const;  // -1 on lo, 1 on hi, 0 between
  bool segment(Vh a, Vh b, Sub& s) const;
  bool facet(Vh a, Vh b, Vh d, Sub& s) const;
  void subs(const Tr& tr, const std::vector<Ch>& zone, std::vector<Sub>& segs, std::vector<Sub>& facets) const;
  Split checked(const Tr& tr, Kind kind, const Vec3& x, Ch near) const;
  Vec3 lo_, hi_;
  double floor_;
};

} // namespace imgmesh::surface_detail
