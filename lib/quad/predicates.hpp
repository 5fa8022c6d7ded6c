// The planar predicates of tri2quad and quadsmooth, in one place: exact
// orientation, strict convexity and the undirected edge key. Quads are
// corners a, b, c, d in counter-clockwise order. CGAL stays inside
// predicates.cpp.
#pragma once
#include "planar/triangle_io.hpp"

#include <cmath>
#include <cstdint>
#include <utility>
#include <vector>

namespace imgmesh {

// Exact orientation of the triangle (a, b, c) by CGAL's exact predicate:
// +1 left turn, -1 right, 0 collinear.
int orientation_exact(const Point2& a, const Point2& b, const Point2& c);
// The same, exact, with Shewchuk's static filter inlined: when the double
// determinant exceeds its worst rounding error its sign is exact, and only
// near-degenerate cases pay for the exact predicate (hot in the smoothing
// guard, which calls it tens of millions of times).
inline int orientation(const Point2& a, const Point2& b, const Point2& c) {
  const double l = (a[0] - c[0]) * (b[1] - c[1]);
  const double r = (a[1] - c[1]) * (b[0] - c[0]);
  const double det = l - r;
  const double bound = 3.3306690738754716e-16 * (std::fabs(l) + std::fabs(r));
  if (det > bound) return 1;
  if (-det > bound) return -1;
  return orientation_exact(a, b, c);
}

// Strict convexity, exact: every corner turns left. Four left turns make a
// convex polygon only if it winds once; a self-intersecting "bow-tie" has
// turns of both signs, and a doubly wound quad cannot have 4 vertices. A quad
// with a zero-length edge, a straight angle or clockwise order is not.
inline bool is_strictly_convex(const Point2& a, const Point2& b, const Point2& c, const Point2& d) {
  return orientation(a, b, c) > 0 && orientation(b, c, d) > 0 && orientation(c, d, a) > 0 &&
         orientation(d, a, b) > 0;
}

// Strictly convex (exact) and every turn above a tiny margin relative to the
// element's size (1e-10 of its squared bounding-box diagonal), so that
// independent floating-point checkers agree: the quad-goodness test of every
// quad tri2quad emits.
bool good_quad(const Point2& a, const Point2& b, const Point2& c, const Point2& d);
// The same for the triangle (a, b, c): counter-clockwise, above the margin.
bool good_triangle(const Point2& a, const Point2& b, const Point2& c);
// A simple polygon in counter-clockwise order (exact segment tests).
bool simple_ccw(const std::vector<Point2>& poly);

// The undirected edge {a, b} as one integer (hash and sort key).
inline std::uint64_t edge_key(int a, int b) {
  if (a > b) std::swap(a, b);
  return (std::uint64_t(std::uint32_t(a)) << 32) | std::uint32_t(b);
}

} // namespace imgmesh
