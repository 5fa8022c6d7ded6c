// The adapter lives in its own file: it is built only when the implicit
// module (chapter 6) is part of the build.
#include "implicit/partition_of_unity.hpp"
#include "surface/implicit_surface.hpp"

#include <algorithm>
#include <cmath>

namespace imgmesh {

PartitionOfUnitySurface::PartitionOfUnitySurface(const PartitionOfUnity& pu) : pu_(pu) {}

double PartitionOfUnitySurface::value(const Vec3& q) const { return pu_.value(to_world(q)); }

double PartitionOfUnitySurface::value_gradient(const Vec3& q, Vec3& gradient) const {
  Vec3 gw;
  const double v = pu_.value_gradient(to_world(q), gw);
  gradient = vector_to_local(gw);
  return v;
}

const FloatImage& PartitionOfUnitySurface::samples() const { return pu_.samples(); }

bool PartitionOfUnitySurface::range(const Vec3& a, const Vec3& b, double& lo, double& hi) const {
  const FloatImage& g = pu_.samples();
  const Vec3& d = pu_.d();
  long k0[3], k1[3];
  for (int i = 0; i < 3; ++i) {  // cells [k s, (k+1) s] dilated by d_i meeting [a_i, b_i]
    const double s = g.spacing[i];
    const long cells = long(g.size[i]) - 1;
    k0[i] = std::clamp(long(std::floor((a[i] - d[i]) / s)), 0L, cells - 1);
    k1[i] = std::clamp(long(std::floor((b[i] + d[i]) / s)), 0L, cells - 1);
  }
  lo = HUGE_VAL;
  hi = -HUGE_VAL;
  for (long z = k0[2]; z <= k1[2]; ++z)
    for (long y = k0[1]; y <= k1[1]; ++y)
      for (long x = k0[0]; x <= k1[0]; ++x) {
        const long k[3] = {x, y, z};
        double c[8];
        for (int m = 0; m < 8; ++m) c[m] = g(std::size_t(x + (m & 1)), std::size_t(y + ((m >> 1) & 1)), std::size_t(z + ((m >> 2) & 1)));
        for (int m = 0; m < 8; ++m) {  // f_j at the box's corner m, in cell-relative coordinates
          double t[3];
          for (int i = 0; i < 3; ++i) t[i] = ((m >> i) & 1 ? b[i] : a[i]) / g.spacing[i] - double(k[i]);
          const double c00 = c[0] + t[0] * (c[1] - c[0]), c10 = c[2] + t[0] * (c[3] - c[2]);
          const double c01 = c[4] + t[0] * (c[5] - c[4]), c11 = c[6] + t[0] * (c[7] - c[6]);
          const double c0 = c00 + t[1] * (c10 - c00), c1 = c01 + t[1] * (c11 - c01);
          const double v = c0 + t[2] * (c1 - c0);
          lo = std::min(lo, v);
          hi = std::max(hi, v);
        }
      }
  // Rounding: f is evaluated in double from float samples; widen a little.
  const double pad = 1e-9 * (std::abs(lo) + std::abs(hi) + 1e-300) + 1e-12 * g.spacing[0];
  lo -= pad;
  hi += pad;
  return true;
}

} // namespace imgmesh
