// Analytic surfaces for the mesher's room tests (sampled on a grid so the
// cube grid and the certificate see them as they see wc2implicit's f), and
// a DelMesh started on one. Inline, namespace-scoped: the room tests compile
// as one unity translation unit.
#pragma once
#include "checks.hpp"
#include "surface/implicit_surface.hpp"

#include <cmath>

namespace imgmesh::test {

inline Geometry box(std::size_t nx, std::size_t ny, std::size_t nz) {
  Geometry g;
  g.size = {nx, ny, nz};
  return g;
}
inline double sphere_f(const Vec3& p, const Vec3& c, double r) { return std::sqrt(dist2(p, c)) - r; }
// A torus around the z axis through c: ring radius R, tube radius r.
inline double torus_f(const Vec3& p, const Vec3& c, double R, double r) {
  const double q = std::hypot(p[0] - c[0], p[1] - c[1]) - R;
  return std::hypot(q, p[2] - c[2]) - r;
}
// Two close sheets x = x0 - t and x = x0 + t, joined where y or z leaves
// [lo, hi] (a flat box).
inline double sheets_f(const Vec3& p, double x0, double t, double lo, double hi) {
  return std::max({std::abs(p[0] - x0) - t, lo - p[1], p[1] - hi, lo - p[2], p[2] - hi});
}

} // namespace imgmesh::test
