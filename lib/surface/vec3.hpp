// Small vector maths on Vec3 for the restricted Delaunay mesher (private to
// lib/surface; no CGAL, so the rooms that need no triangulation stay light).
#pragma once
#include "image/grid.hpp"

#include <algorithm>
#include <cmath>

namespace imgmesh::surface_detail {

inline Vec3 sub(const Vec3& a, const Vec3& b) { return {a[0] - b[0], a[1] - b[1], a[2] - b[2]}; }
inline double dot(const Vec3& a, const Vec3& b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }
inline Vec3 cross(const Vec3& a, const Vec3& b) {
  return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
}
inline double norm(const Vec3& a) { return std::sqrt(dot(a, a)); }
inline double dist2(const Vec3& a, const Vec3& b) { Vec3 d = sub(a, b); return dot(d, d); }

// std::floor and std::ceil to a long, inline: without SSE4.1 they are libm
// calls, and the cube walks and enclosures take several per step. The same
// value for |x| < 2^63.
inline long floor_long(double x) {
  const long i = long(x);
  return i - (double(i) > x);
}
inline long ceil_long(double x) { return -floor_long(-x); }

// An undirected mesh edge as one number.
inline long long edge_key(int a, int b) { return (static_cast<long long>(std::min(a, b)) << 32) | std::max(a, b); }

} // namespace imgmesh::surface_detail
