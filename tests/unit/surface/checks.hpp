// Independent checks of implicit2mesh's guarantees, shared by the tests.
#pragma once
#include "mesh/surface_io.hpp"
#include "surface/implicit_surface.hpp"

#include <algorithm>
#include <cmath>
#include <vector>

namespace imgmesh::test {

// Generalised winding number of a closed oriented mesh at p: ~1 inside, ~0 outside.
inline double winding_number(const SurfaceMesh& m, const Vec3& p) {
  double total = 0;
  for (const auto& t : m.triangles) {
    Vec3 a, b, c;
    for (int i = 0; i < 3; ++i) {
      a[i] = m.points[t[0]][i] - p[i];
      b[i] = m.points[t[1]][i] - p[i];
      c[i] = m.points[t[2]][i] - p[i];
    }
    const double la = std::sqrt(a[0] * a[0] + a[1] * a[1] + a[2] * a[2]);
    const double lb = std::sqrt(b[0] * b[0] + b[1] * b[1] + b[2] * b[2]);
    const double lc = std::sqrt(c[0] * c[0] + c[1] * c[1] + c[2] * c[2]);
    const double det = a[0] * (b[1] * c[2] - b[2] * c[1]) - a[1] * (b[0] * c[2] - b[2] * c[0]) +
                       a[2] * (b[0] * c[1] - b[1] * c[0]);
    const double ab = a[0] * b[0] + a[1] * b[1] + a[2] * b[2], bc = b[0] * c[0] + b[1] * c[1] + b[2] * c[2],
                 ca = c[0] * a[0] + c[1] * a[1] + c[2] * a[2];
    total += 2 * std::atan2(det, la * lb * lc + ab * lc + bc * la + ca * lb);
  }
  return total / (4 * M_PI);
}

inline double dist2(const Vec3& a, const Vec3& b) {
  return (a[0] - b[0]) * (a[0] - b[0]) + (a[1] - b[1]) * (a[1] - b[1]) + (a[2] - b[2]) * (a[2] - b[2]);
}

// Restricted Delaunay (brute force): the ball centred at each triangle's
// surface centre through its vertices is empty of mesh vertices, and the
// centre is equidistant from the three vertices. Returns the violations.
inline int empty_ball_violations(const SurfaceMesh& m, const std::vector<Vec3>& centers) {
  int bad = 0;
  for (std::size_t k = 0; k < m.triangles.size(); ++k) {
    const auto& t = m.triangles[k];
    const double r0 = dist2(centers[k], m.points[t[0]]);
    const double r1 = dist2(centers[k], m.points[t[1]]), r2 = dist2(centers[k], m.points[t[2]]);
    if (std::abs(r1 - r0) > 1e-6 * r0 || std::abs(r2 - r0) > 1e-6 * r0) { ++bad; continue; }
    for (const Vec3& p : m.points)
      if (dist2(centers[k], p) < r0 * (1 - 1e-7)) { ++bad; break; }
  }
  return bad;
}

} // namespace imgmesh::test
