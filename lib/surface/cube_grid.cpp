#include "surface/cube_grid.hpp"
#include "util/error.hpp"

#include <algorithm>
#include <cmath>

namespace imgmesh::surface_detail {

CubeGrid::CubeGrid(const SampleGrid& img) : g(img) {
  for (int i = 0; i < 3; ++i) {
    n[i] = long(img.size[i]);
    s[i] = img.spacing[i];
    hi[i] = double(n[i] - 1) * s[i];
    nb[i] = std::max(1L, (n[i] - 1 + kBlock - 1) / kBlock);
  }
  delta = std::min({s[0], s[1], s[2]});
  if (n[0] < 2 || n[1] < 2 || n[2] < 2) return;
  block_brick.resize(std::size_t(nb[0] * nb[1] * nb[2]));  // zeros, no memset
  bricks.assign(kBlock, 0);  // brick 0: no active cube
  long c0[3], c1[3];
  sampled_cubes(c0, c1);
  // The cubes of a line a sample block's width at a time: none is active
  // where every block their corners lie in is constant of one sign (most
  // of a thin tissue's box, read from blocks).
  constexpr int kShift = SampleGrid::kShift;
  const auto one_sign = [&](long bx0, long bx1, long y, long z) {
    const int sign = g.constant_block(bx0, y >> kShift, z >> kShift);
    if (sign == 0) return false;
    for (long by : {y >> kShift, (y + 1) >> kShift})
      for (long bz : {z >> kShift, (z + 1) >> kShift})
        for (long bx : {bx0, bx1})
          if (g.constant_block(bx, by, bz) != sign) return false;
    return true;
  };
  for (long z = c0[2]; z <= c1[2]; ++z)
    for (long y = c0[1]; y <= c1[1]; ++y)
      for (long x = c0[0]; x <= c1[0]; ++x) {
        if ((x == c0[0] || (x & SampleGrid::kMask) == 0)) {
          const long last = std::min(c1[0], x | SampleGrid::kMask);  // this block's cubes on the line
          if (one_sign(x >> kShift, (last + 1) >> kShift, y, z)) {
            x = last;
            continue;
          }
        }
        double c[8];
        g.cube(x, y, z, c);
        bool mixed = false;
        for (int k = 1; k < 8; ++k) mixed = mixed || ((c[k] < 0) != (c[0] < 0));
        if (!mixed) continue;
        std::uint32_t& brick = block_brick[block_index(x >> kBlockShift, y >> kBlockShift, z >> kBlockShift)];
        if (brick == 0) {
          brick = std::uint32_t(bricks.size() / kBlock);
          bricks.resize(bricks.size() + kBlock, 0);
        }
        bricks[std::size_t(kBlock * brick + (z & kBlockMask))] |= std::uint64_t(1) << ((x & kBlockMask) + kBlock * (y & kBlockMask));
        ++active_cubes;
      }
  bricks.shrink_to_fit();  // grown by doubling: held through the run
}

// The labelled cubes are marked in a bit set of their own; the pairs are
// sorted by key at the end.
void CubeGrid::label() {
  std::vector<std::array<long, 3>> stack;
  ZeroedVector<std::uint64_t> done((std::size_t((n[0] - 1) * (n[1] - 1) * (n[2] - 1)) + 63) / 64);
  auto labelled = [&](long x, long y, long z) { return test_bit(done, cube_index(x, y, z)); };
  auto set = [&](long x, long y, long z, int c) {
    set_bit(done, cube_index(x, y, z));
    comp.emplace_back(key(x, y, z), c);
  };
  comp.reserve(active_cubes);
  long c0[3], c1[3];
  sampled_cubes(c0, c1);
  // The active cubes a line at a time (not a lookup per cube of the box).
  for (long z = c0[2]; z <= c1[2]; ++z)
    for (long y = c0[1]; y <= c1[1]; ++y)
      for_active_on_line(c0[0], c1[0], y, z, [&](long x) {
        if (labelled(x, y, z)) return;
        if (components == (1 << ActiveCube::kCompBits) - 1)
          throw Error("the surface has more than " + std::to_string(components) + " components");
        const int c = components++;
        set(x, y, z, c);
        stack.push_back({x, y, z});
        while (!stack.empty()) {
          auto q = stack.back();
          stack.pop_back();
          for (int a = 0; a < 3; ++a)
            for (int dir = -1; dir <= 1; dir += 2) {
              std::array<long, 3> r = q;
              r[a] += dir;
              if (!active(r[0], r[1], r[2]) || labelled(r[0], r[1], r[2])) continue;
              // The shared face: plane coordinate max(q[a], r[a]) on axis a.
              const long pa = std::max(q[a], r[a]);
              const int b = (a + 1) % 3, c2 = (a + 2) % 3;
              bool any_neg = false, any_pos = false;
              for (int k = 0; k < 4; ++k) {
                std::array<long, 3> v = q;
                v[a] = pa;
                v[b] += k & 1;
                v[c2] += (k >> 1) & 1;
                (neg(v[0], v[1], v[2]) ? any_neg : any_pos) = true;
              }
              if (!(any_neg && any_pos)) continue;
              set(r[0], r[1], r[2], c);
              stack.push_back(r);
            }
        }
      });
  std::sort(comp.begin(), comp.end());
}

void CubeGrid::sampled_cubes(long c0[3], long c1[3]) const {
  for (int i = 0; i < 3; ++i) {
    c0[i] = std::max(0L, long(g.box_lo()[i]) - 1);
    c1[i] = std::min(n[i] - 2, long(g.box_hi()[i]));
  }
}

bool CubeGrid::inactive_box(const Vec3& lo, const Vec3& hi) const {
  long c0[3], c1[3];
  for (int i = 0; i < 3; ++i) {
    if (!(lo[i] >= 0 && hi[i] <= this->hi[i] && lo[i] <= hi[i])) return false;  // NaN too
    c0[i] = std::max(floor_long((lo[i] - 1e-9 * delta) / s[i]), 0L);
    c1[i] = std::min(floor_long((hi[i] + 1e-9 * delta) / s[i]), n[i] - 2);
  }
  // Whole blocks of inactive cubes first, then the cubes of active blocks.
  for (long bz = c0[2] / kBlock; bz <= c1[2] / kBlock; ++bz)
    for (long by = c0[1] / kBlock; by <= c1[1] / kBlock; ++by)
      for (long bx = c0[0] / kBlock; bx <= c1[0] / kBlock; ++bx) {
        if (!block(bx, by, bz)) continue;
        for (long z = std::max(c0[2], bz * kBlock); z <= std::min(c1[2], bz * kBlock + kBlock - 1); ++z)
          for (long y = std::max(c0[1], by * kBlock); y <= std::min(c1[1], by * kBlock + kBlock - 1); ++y)
            for (long x = std::max(c0[0], bx * kBlock); x <= std::min(c1[0], bx * kBlock + kBlock - 1); ++x)
              if (active(x, y, z)) return false;
      }
  return true;
}

int CubeGrid::comp_at(const Vec3& q) const {
  long c[3];
  for (int i = 0; i < 3; ++i) c[i] = std::clamp(floor_long(q[i] / s[i]), 0L, n[i] - 2);
  int r = comp_of(c[0], c[1], c[2]);
  if (r >= 0) return r;
  for (int dz = -1; dz <= 1; ++dz)
    for (int dy = -1; dy <= 1; ++dy)
      for (int dx = -1; dx <= 1; ++dx)
        if ((r = comp_of(c[0] + dx, c[1] + dy, c[2] + dz)) >= 0) return r;
  return -1;
}

// Illinois regula falsi with a bisection safeguard (when the bracket
// shrinks slowly).
bool SurfaceSampler::bisect(Vec3 a, Vec3 b, double fa, double fb, Vec3& x) const {
  const bool ia = inside(fa);
  if (inside(fb) == ia) return false;
  const double tol2 = std::pow(1e-11 * grid_.delta, 2);
  int side = 0;
  double width2 = dist2(a, b);
  for (int it = 0; it < 200 && dist2(a, b) > tol2; ++it) {
    double t = (fa - fb) != 0 ? fa / (fa - fb) : 0.5;
    if (!(t > 0 && t < 1)) t = 0.5;
    if (it % 3 == 2) {  // less than halved in three steps: bisect
      const double w2 = dist2(a, b);
      if (w2 > width2 / 4) t = 0.5;
      width2 = w2;
    }
    Vec3 m{a[0] + t * (b[0] - a[0]), a[1] + t * (b[1] - a[1]), a[2] + t * (b[2] - a[2])};
    const double fm = value(m);
    if (inside(fm) == ia) {
      a = m; fa = fm;
      if (side == -1) fb /= 2;
      side = -1;
    } else {
      b = m; fb = fm;
      if (side == 1) fa /= 2;
      side = 1;
    }
  }
  x = std::abs(fa) <= std::abs(fb) ? a : b;
  return true;
}

} // namespace imgmesh::surface_detail
