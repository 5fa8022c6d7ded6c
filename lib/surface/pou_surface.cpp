// The adapter lives in its own file: it is built only when the implicit
// module (chapter 6) is part of the build.
#include "implicit/partition_of_unity.hpp"
#include "surface/implicit_surface.hpp"
#include "surface/vec3.hpp"

#include <algorithm>
#include <cmath>

namespace imgmesh {

namespace {
// The sample cells [k s, (k+1) s], dilated by the support d_i, that meet the
// box [a, b]: k0[i]..k1[i] on each axis.
void cells_meeting(const Geometry& g, const Vec3& d, const Vec3& a, const Vec3& b, long k0[3], long k1[3]) {
  for (int i = 0; i < 3; ++i) {
    const double s = g.spacing[i];
    const long cells = long(g.size[i]) - 1;
    k0[i] = std::clamp(surface_detail::floor_long((a[i] - d[i]) / s), 0L, cells - 1);
    k1[i] = std::clamp(surface_detail::floor_long((b[i] + d[i]) / s), 0L, cells - 1);
  }
}
}  // namespace

PartitionOfUnitySurface::PartitionOfUnitySurface(const PartitionOfUnity& pu) : pu_(pu) {}

double PartitionOfUnitySurface::value(const Vec3& q) const { return pu_.value(to_world(q)); }

double PartitionOfUnitySurface::value_gradient(const Vec3& q, Vec3& gradient) const {
  Vec3 gw;
  const double v = pu_.value_gradient(to_world(q), gw);
  gradient = vector_to_local(gw);
  return v;
}

const SampleGrid& PartitionOfUnitySurface::samples() const { return pu_.samples(); }

bool PartitionOfUnitySurface::range(const Vec3& a, const Vec3& b, double& lo, double& hi, bool until_zero) const {
  const SampleGrid& g = pu_.samples();
  long k0[3], k1[3];
  cells_meeting(g, pu_.d(), a, b, k0, k1);
  // The box's corners in index units: t = a / s - k (or b / s - k) in cell k.
  double ta[3], tb[3];
  for (int i = 0; i < 3; ++i) ta[i] = a[i] / g.spacing[i], tb[i] = b[i] / g.spacing[i];
  // min and max over the cells in any order: until_zero stops at the first
  // cell that brings 0 into [l, h] (the pad below keeps it there). Locals,
  // not lo and hi: through references they went to memory at every step.
  double l = HUGE_VAL, h = -HUGE_VAL;
  [&] {
    for (long z = k0[2]; z <= k1[2]; ++z)
      for (long y = k0[1]; y <= k1[1]; ++y)
        for (long x = k0[0]; x <= k1[0]; ++x) {
          double c[8];
          g.cube(x, y, z, c);
          // f_j at the box's 8 corners, lerp by lerp along x, y, z: the corners
          // with the same t0 (or t0, t1) share the first lerps.
          const double t0[2] = {ta[0] - double(x), tb[0] - double(x)}, t1[2] = {ta[1] - double(y), tb[1] - double(y)},
                       t2[2] = {ta[2] - double(z), tb[2] - double(z)};
          for (double s0 : t0) {
            const double c00 = c[0] + s0 * (c[1] - c[0]), c10 = c[2] + s0 * (c[3] - c[2]);
            const double c01 = c[4] + s0 * (c[5] - c[4]), c11 = c[6] + s0 * (c[7] - c[6]);
            for (double s1 : t1) {
              const double c0 = c00 + s1 * (c10 - c00), c1 = c01 + s1 * (c11 - c01);
              for (double s2 : t2) {
                const double v = c0 + s2 * (c1 - c0);
                l = std::min(l, v);
                h = std::max(h, v);
              }
            }
          }
          if (until_zero && l <= 0 && h >= 0) return;
        }
  }();
  lo = l;
  hi = h;
  // Rounding: f is evaluated in double from float samples; widen a little.
  const double pad = 1e-9 * (std::abs(lo) + std::abs(hi) + 1e-300) + 1e-12 * g.spacing[0];
  lo -= pad;
  hi += pad;
  return true;
}

bool PartitionOfUnitySurface::slope_range(const Vec3& a, const Vec3& b, const Vec3& v, double& lo, double& hi,
                                          bool until_zero) const {
  const SampleGrid& g = pu_.samples();
  const Vec3& d = pu_.d();
  long k0[3], k1[3];
  cells_meeting(g, d, a, b, k0, k1);
  // An inner grid plane within d_i of the box on axis i: the blend term.
  bool blend[3];
  for (int i = 0; i < 3; ++i) {
    const double s = g.spacing[i];
    const long cells = long(g.size[i]) - 1;
    const long p0 = std::max(1L, surface_detail::ceil_long((a[i] - d[i]) / s)), p1 = std::min(cells - 1, surface_detail::floor_long((b[i] + d[i]) / s));
    blend[i] = p0 <= p1;
  }
  // The slopes' ranges as ranges of the differences e1 - e0 below, each
  // divided by its spacing only when used: division by s > 0 is monotone,
  // so the quotient of the least difference is the least quotient (the
  // same bits as dividing every one, at a 24th of the divisions).
  double dlo[3] = {HUGE_VAL, HUGE_VAL, HUGE_VAL}, dhi[3] = {-HUGE_VAL, -HUGE_VAL, -HUGE_VAL};
  // [lo, hi] from the slopes' ranges so far: it only widens as they do
  // (every step is monotone), so until_zero stops once it holds 0. In
  // locals, as in range().
  double elo = 0, ehi = 0;
  auto enclose = [&] {
    elo = ehi = 0;
    for (int i = 0; i < 3; ++i) {
      double l = dlo[i] / g.spacing[i], h = dhi[i] / g.spacing[i];
      if (blend[i]) {
        const double w = kBlendSlope * (h - l);
        l -= w;
        h += w;
      }
      elo += std::min(v[i] * l, v[i] * h);
      ehi += std::max(v[i] * l, v[i] * h);
    }
  };
  // The box's corners in index units, as in range().
  double ta[3], tb[3];
  for (int i = 0; i < 3; ++i) ta[i] = a[i] / g.spacing[i], tb[i] = b[i] / g.spacing[i];
  [&] {
    for (long z = k0[2]; z <= k1[2]; ++z)
      for (long y = k0[1]; y <= k1[1]; ++y)
        for (long x = k0[0]; x <= k1[0]; ++x) {
          const double k[3] = {double(x), double(y), double(z)};
          double c[8];
          g.cube(x, y, z, c);
          // d f_j / d x_i at the box's corner m does not depend on m's bit
          // i: the four corners with it clear, in the order of m.
          for (int i = 0; i < 3; ++i) {
            const int j = (i + 1) % 3, l = (i + 2) % 3;
            for (int m = 0; m < 8; ++m) {
              if ((m >> i) & 1) continue;
              const double tj = ((m >> j) & 1 ? tb[j] : ta[j]) - k[j], tl = ((m >> l) & 1 ? tb[l] : ta[l]) - k[l];
              double e[2];  // f_j on the faces t_i = 0 and 1, bilinear in t_j, t_l
              for (int side = 0; side < 2; ++side) {
                auto at = [&](int bj, int bl) { return c[(side << i) | (bj << j) | (bl << l)]; };
                const double e0 = at(0, 0) + tj * (at(1, 0) - at(0, 0)), e1 = at(0, 1) + tj * (at(1, 1) - at(0, 1));
                e[side] = e0 + tl * (e1 - e0);
              }
              const double sl = e[1] - e[0];
              dlo[i] = std::min(dlo[i], sl);
              dhi[i] = std::max(dhi[i], sl);
            }
          }
          if (until_zero) {
            enclose();
            if (elo <= 0 && ehi >= 0) return;
          }
        }
  }();
  if (!until_zero) enclose();
  lo = elo;
  hi = ehi;
  // Rounding: as in range().
  const double pad = 1e-9 * (std::abs(lo) + std::abs(hi) + 1e-300);
  lo -= pad;
  hi += pad;
  return true;
}

} // namespace imgmesh
