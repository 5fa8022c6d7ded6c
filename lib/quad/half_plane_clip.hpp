// The region in which the placement rule (doc/tri2quad.md section 1) puts a
// Steiner point: a bounding polygon clipped by the open half-planes left of
// each (a -> b), in floating point, and a point well inside it.
#pragma once
#include "planar/triangle_io.hpp"

#include <vector>

namespace imgmesh {

struct HalfPlane { Point2 a, b; };
// poly (counter-clockwise) clipped by every half-plane; empty when fewer
// than 3 vertices are left.
std::vector<Point2> clip(const std::vector<Point2>& poly, const std::vector<HalfPlane>& hp);
// The area centroid of a polygon (the vertex mean when its area is zero).
Point2 centroid(const std::vector<Point2>& poly);

} // namespace imgmesh
