// The cube grid between voxel centres (thesis ch. 6): signs, active cubes and
// their components (F1, F4), and f sampled inside the grid's box with the
// root finder every subroutine uses to put a point on S. No CGAL.
#pragma once
#include "surface/implicit_surface.hpp"
#include "surface/vec3.hpp"
#include "util/zeroed.hpp"

#include <algorithm>
#include <array>
#include <atomic>
#include <cstdint>
#include <utility>
#include <vector>

namespace imgmesh::surface_detail {

// An active cube as key << 24 | its S component: 8 bytes, where a pair
// took 16 (keys < 2^40: PartitionOfUnity's grid limit).
struct ActiveCube {
  std::uint64_t bits;
  static constexpr int kCompBits = 24;
  ActiveCube(long long key, int comp) : bits(std::uint64_t(key) << kCompBits | std::uint64_t(comp)) {}
  long long key() const { return (long long)(bits >> kCompBits); }
  int comp() const { return int(bits & ((std::uint64_t(1) << kCompBits) - 1)); }
  bool operator<(const ActiveCube& o) const { return bits < o.bits; }
};

struct CubeGrid {
  const SampleGrid& g;
  long n[3];
  double s[3];
  double hi[3];
  double delta;
  // The active cubes in key order, with their S components (a hash map
  // took about 40 bytes a cube; liver: MB of them beside f's samples).
  std::vector<ActiveCube> comp;
  int components = 0;

  // Activity of every cube, one bit each, kept only for the blocks of
  // kBlock^3 cubes that hold an active one (a whole-grid bit set took 3.2 MB
  // on a CT's liver, its active blocks 0.3 MB): per block its brick of
  // activity, 0 (a brick of zeros) when none is active, so EdgeSurface also
  // crosses empty space a block at a time. Word z of a brick holds
  // the block's layer z, bit x + 8 y.
  static constexpr int kBlockShift = 3;
  static constexpr long kBlock = 1L << kBlockShift, kBlockMask = kBlock - 1;
  ZeroedVector<std::uint32_t> block_brick;
  std::vector<std::uint64_t> bricks;
  std::size_t active_cubes = 0;
  long nb[3];

  explicit CubeGrid(const SampleGrid& img);
  bool neg(long x, long y, long z) const { return g(std::size_t(x), std::size_t(y), std::size_t(z)) < 0; }
  long long key(long x, long y, long z) const { return x + (long long)n[0] * (y + (long long)n[1] * z); }
  bool active(long x, long y, long z) const {
    if (x < 0 || y < 0 || z < 0 || x > n[0] - 2 || y > n[1] - 2 || z > n[2] - 2) return false;
    const std::uint32_t brick = block_brick[block_index(x >> kBlockShift, y >> kBlockShift, z >> kBlockShift)];
    const std::uint64_t layer = bricks[std::size_t(kBlock * brick + (z & kBlockMask))];
    return (layer >> ((x & kBlockMask) + kBlock * (y & kBlockMask))) & 1;
  }
  std::size_t block_index(long bx, long by, long bz) const { return std::size_t(bx + nb[0] * (by + nb[1] * bz)); }
  std::size_t cube_index(long x, long y, long z) const { return std::size_t(x + (n[0] - 1) * (y + (n[1] - 1) * z)); }
  // Bit i of a bit set of one bit a cube.
  static bool test_bit(const ZeroedVector<std::uint64_t>& bits, std::size_t i) { return (bits[i >> 6] >> (i & 63)) & 1; }
  static void set_bit(ZeroedVector<std::uint64_t>& bits, std::size_t i) { bits[i >> 6] |= std::uint64_t(1) << (i & 63); }
  // f(x) for each active cube x of x0..x1 on line (y, z), by x: the line's
  // bits a block at a time (a facet's lines hold ~3 cubes, ~1 active).
  // The caller keeps x0 >= 0, x1 <= n[0] - 2 and (y, z) in the grid.
  template <class F> void for_active_on_line(long x0, long x1, long y, long z, F&& f) const {
    if (x0 > x1) return;
    const int row = int(kBlock * (y & kBlockMask));
    const long layer = z & kBlockMask, b0 = x0 >> kBlockShift, b1 = x1 >> kBlockShift;
    for (long bx = b0; bx <= b1; ++bx) {
      const std::uint32_t brick = block_brick[block_index(bx, y >> kBlockShift, z >> kBlockShift)];
      if (brick == 0) continue;
      unsigned bits = unsigned(bricks[std::size_t(kBlock * brick + layer)] >> row) & 0xffu;
      if (bx == b0) bits &= 0xffu << (x0 & kBlockMask);
      if (bx == b1) bits &= 0xffu >> (kBlockMask - (x1 & kBlockMask));
      for (; bits; bits &= bits - 1) f(bx * kBlock + __builtin_ctz(bits));
    }
  }
  bool block(long x, long y, long z) const { return block_brick[block_index(x, y, z)] != 0; }
  int comp_of(long x, long y, long z) const {
    const long long k = key(x, y, z);
    auto it = std::lower_bound(comp.begin(), comp.end(), k, [](const ActiveCube& e, long long v) { return e.key() < v; });
    return it == comp.end() || it->key() != k ? -1 : it->comp();
  }
  // f has no zero on the local box [lo, hi] (F1): the box lies inside the
  // grid's box and every closed cube it meets is inactive (the box widened
  // by 1e-9 delta, for rounding in the caller's corners and in q / s).
  bool inactive_box(const Vec3& lo, const Vec3& hi) const;
  // Label active cubes by components joined through mixed faces (F4).
  void label();
  // The cubes that meet the box of samples given (SampleGrid::box_lo/hi):
  // c0[i]..c1[i] per axis; the others have 8 corners at +T, inactive.
  void sampled_cubes(long c0[3], long c1[3]) const;
  // Component of the active cube containing a local point (or a neighbour).
  int comp_at(const Vec3& q) const;
  // The active cubes (key, component) in key order (deterministic).
  const std::vector<ActiveCube>& sorted_cubes() const { return comp; }
  // Cube (x, y, z) of a key.
  std::array<long, 3> cube_of_key(long long k) const {
    return {long(k % n[0]), long((k / n[0]) % n[1]), long(k / n[0] / n[1])};
  }
};

// f on the box of voxel centres (points beyond it are clamped onto it),
// every evaluation counted for --stats; safe to call from several threads.
class SurfaceSampler {
public:
  SurfaceSampler(const ImplicitSurface& f, const CubeGrid& grid) : f_(f), grid_(grid) {}
  const CubeGrid& grid() const { return grid_; }
  const ImplicitSurface& surface() const { return f_; }
  long long evaluations() const {
    long long n = 0;
    for (const Count& c : evaluations_) n += c.n.load();
    return n;
  }

  double value(const Vec3& q) const {
    evaluations_[count_slot()].n.fetch_add(1, std::memory_order_relaxed);
    Vec3 c = q;
    for (int i = 0; i < 3; ++i) c[i] = std::clamp(c[i], 0.0, grid_.hi[i]);
    return f_.value(c);
  }
  Vec3 gradient(const Vec3& q) const {
    Vec3 c = q, gr;
    for (int i = 0; i < 3; ++i) c[i] = std::clamp(c[i], 0.0, grid_.hi[i]);
    f_.value_gradient(c, gr);
    return gr;
  }
  // An enclosure of f on the local box [a, b] when the surface has one, for
  // the callers' only question, whether it excludes 0: with until_zero (see
  // ImplicitSurface::range).
  bool range(const Vec3& a, const Vec3& b, double& lo, double& hi) const { return f_.range(a, b, lo, hi, true); }
  // The same for f's derivative along the unit vector v on [a, b].
  bool slope_range(const Vec3& a, const Vec3& b, const Vec3& v, double& lo, double& hi) const {
    return f_.slope_range(a, b, v, lo, hi, true);
  }
  // Sign convention for zeros (8.4(1)): f == 0 counts as outside, i.e. we
  // mesh f^-1(-eps) symbolically, consistently on every edge.
  static bool inside(double v) { return v < 0; }
  // Which side of S a local point is on: f's sign, read off the samples
  // where the cube around q has one sign (no zero there, thesis F1); beyond
  // the box of samples, outside.
  bool inside_at(const Vec3& q) const {
    long c[3];
    for (int i = 0; i < 3; ++i) {
      if (!(q[i] >= 0 && q[i] <= grid_.hi[i])) return false;
      c[i] = std::min(long(q[i] / grid_.s[i]), grid_.n[i] - 2);
    }
    if (!grid_.active(c[0], c[1], c[2])) return grid_.neg(c[0], c[1], c[2]);
    return inside(value(q));
  }
  // The point x of S on segment [a, b] (fa = f(a)), to ~1e-11 delta, when
  // the ends have opposite signs; false (x untouched) when they do not: the
  // pair brackets no root, and a point found there need not be on S.
  bool bisect(Vec3 a, Vec3 b, double fa, Vec3& x) const { return bisect(a, b, fa, value(b), x); }
  // The same with fb = f(b) known (EdgeSurface has both ends' values).
  bool bisect(Vec3 a, Vec3 b, double fa, double fb, Vec3& x) const;

private:
  const ImplicitSurface& f_;
  const CubeGrid& grid_;
  // The evaluations, counted in one slot per thread (threads beyond
  // kSlots share, still atomically), each on its own cache line: one
  // counter shared by every thread bounced between the cores.
  static constexpr unsigned kSlots = 16;
  struct alignas(64) Count { std::atomic<long long> n{0}; };
  mutable std::array<Count, kSlots> evaluations_;
  static unsigned count_slot() {
    static std::atomic<unsigned> next{0};
    thread_local const unsigned slot = next.fetch_add(1, std::memory_order_relaxed) % kSlots;
    return slot;
  }
};

} // namespace imgmesh::surface_detail
