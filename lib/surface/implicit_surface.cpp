#include "surface/implicit_surface.hpp"

#include <cmath>

namespace imgmesh {

Vec3 ImplicitSurface::to_world(const Vec3& q) const {
  const Geometry& g = samples();
  return g.world(q[0] / g.spacing[0], q[1] / g.spacing[1], q[2] / g.spacing[2]);
}

Vec3 ImplicitSurface::to_local(const Vec3& w) const {
  const Geometry& g = samples();
  Vec3 c = g.continuous_index(w);
  return {c[0] * g.spacing[0], c[1] * g.spacing[1], c[2] * g.spacing[2]};
}

Vec3 ImplicitSurface::vector_to_world(const Vec3& v) const {
  const auto& d = samples().direction;
  return {d[0] * v[0] + d[1] * v[1] + d[2] * v[2], d[3] * v[0] + d[4] * v[1] + d[5] * v[2],
          d[6] * v[0] + d[7] * v[1] + d[8] * v[2]};
}

Vec3 ImplicitSurface::vector_to_local(const Vec3& v) const {
  const auto& d = samples().direction;  // orthonormal: inverse = transpose
  return {d[0] * v[0] + d[3] * v[1] + d[6] * v[2], d[1] * v[0] + d[4] * v[1] + d[7] * v[2],
          d[2] * v[0] + d[5] * v[1] + d[8] * v[2]};
}

bool ImplicitSurface::reflects() const {
  const auto& d = samples().direction;
  const double det = d[0] * (d[4] * d[8] - d[5] * d[7]) - d[1] * (d[3] * d[8] - d[5] * d[6]) +
                     d[2] * (d[3] * d[7] - d[4] * d[6]);
  return det < 0;
}

FunctionSurface::FunctionSurface(const Geometry& grid, Function f) : f_(std::move(f)) {
  FloatImage g(grid);
  for (std::size_t z = 0; z < grid.size[2]; ++z)
    for (std::size_t y = 0; y < grid.size[1]; ++y)
      for (std::size_t x = 0; x < grid.size[0]; ++x) g(x, y, z) = float(f_(grid.world(double(x), double(y), double(z))));
  samples_ = SampleGrid(std::move(g));
}

bool ImplicitSurface::range(const Vec3&, const Vec3&, double&, double&, bool) const { return false; }
bool ImplicitSurface::slope_range(const Vec3&, const Vec3&, const Vec3&, double&, double&, bool) const { return false; }

double FunctionSurface::value(const Vec3& q) const { return f_(to_world(q)); }

double FunctionSurface::value_gradient(const Vec3& q, Vec3& gradient) const {
  const double h = 1e-6 * samples_.spacing[0];
  for (int i = 0; i < 3; ++i) {
    Vec3 a = q, b = q;
    a[i] -= h;
    b[i] += h;
    gradient[i] = (value(b) - value(a)) / (2 * h);
  }
  return value(q);
}

} // namespace imgmesh
