// Test-side helpers: images that are well-composed by construction or by a
// brute-force repair, and brute-force references for the distance.
#pragma once
#include "image/grid.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <random>

namespace imgmesh::test {

inline Geometry grid(std::size_t nx, std::size_t ny, std::size_t nz, Vec3 spacing = {1, 1, 1}) {
  Geometry g;
  g.dimension = 3;
  g.size = {nx, ny, nz};
  g.spacing = spacing;
  return g;
}

// A rotation about a non-axis direction, for world-geometry tests.
inline void rotate(Geometry& g) {
  const double a = 0.3, b = -0.5;
  const double ca = std::cos(a), sa = std::sin(a), cb = std::cos(b), sb = std::sin(b);
  // Rz(a) * Rx(b)
  g.direction = {ca, -sa * cb, sa * sb, sa, ca * cb, -ca * sb, 0, sb, cb};
  g.origin = {-3.25, 10.5, 2.0};
}

inline bool fg(const BinaryImage& im, long x, long y, long z) { return im.at(x, y, z, 0) != 0; }

// Whether the 2x2x2 block at (x, y, z) holds a critical configuration (C1 or
// C2, outside = background); if so, a background voxel of the block inside
// the grid in (rx, ry, rz) (false if it has none).
inline bool critical_block(const BinaryImage& im, long x, long y, long z, long& rx, long& ry, long& rz) {
  int v[2][2][2], count = 0;
  for (int c = 0; c < 2; ++c)
    for (int b = 0; b < 2; ++b)
      for (int a = 0; a < 2; ++a) count += v[c][b][a] = fg(im, x + a, y + b, z + c);
  bool critical = false;
  // C1: a 2x2 face of the block with a diagonal pattern.
  for (int axis = 0; axis < 3; ++axis)
    for (int s = 0; s < 2; ++s) {
      int f[2][2];
      for (int p = 0; p < 2; ++p)
        for (int q = 0; q < 2; ++q) f[p][q] = axis == 0 ? v[p][q][s] : axis == 1 ? v[p][s][q] : v[s][p][q];
      if (f[0][0] == f[1][1] && f[0][1] == f[1][0] && f[0][0] != f[0][1]) critical = true;
    }
  // C2: two antipodal voxels of one colour, the other six of the other.
  if (count == 2 || count == 6) {
    const int want = count == 2 ? 1 : 0;
    for (int c = 0; c < 2; ++c)
      for (int b = 0; b < 2; ++b)
        for (int a = 0; a < 2; ++a)
          if (v[c][b][a] == want && v[1 - c][1 - b][1 - a] == want) critical = true;
  }
  if (!critical) return false;
  for (int c = 0; c < 2; ++c)
    for (int b = 0; b < 2; ++b)
      for (int a = 0; a < 2; ++a)
        if (!v[c][b][a] && im.inside(x + a, y + b, z + c)) {
          rx = x + a, ry = y + b, rz = z + c;
          return true;
        }
  return false;
}

inline std::size_t count_critical(const BinaryImage& im) {
  std::size_t n = 0;
  long rx, ry, rz;
  for (long z = -1; z < long(im.size[2]); ++z)
    for (long y = -1; y < long(im.size[1]); ++y)
      for (long x = -1; x < long(im.size[0]); ++x) n += critical_block(im, x, y, z, rx, ry, rz);
  return n;
}

// Repair by adding foreground until no critical configuration is left
// (terminates: the foreground only grows).
inline void make_well_composed_slow(BinaryImage& im) {
  for (bool changed = true; changed;) {
    changed = false;
    long rx, ry, rz;
    for (long z = -1; z < long(im.size[2]); ++z)
      for (long y = -1; y < long(im.size[1]); ++y)
        for (long x = -1; x < long(im.size[0]); ++x)
          if (critical_block(im, x, y, z, rx, ry, rz)) {
            im(std::size_t(rx), std::size_t(ry), std::size_t(rz)) = 1;
            changed = true;
          }
  }
}

// A random union of balls, repaired to be well-composed.
inline BinaryImage random_wc(std::size_t n0, std::size_t n1, std::size_t n2, unsigned seed, Vec3 spacing = {1, 1, 1},
                             int balls = 6) {
  BinaryImage im(grid(n0, n1, n2, spacing), 0);
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(0, 1);
  for (int k = 0; k < balls; ++k) {
    const double cx = u(rng) * n0, cy = u(rng) * n1, cz = u(rng) * n2, r = 1 + u(rng) * 3;
    for (std::size_t z = 0; z < n2; ++z)
      for (std::size_t y = 0; y < n1; ++y)
        for (std::size_t x = 0; x < n0; ++x)
          if ((x - cx) * (x - cx) + (y - cy) * (y - cy) + (z - cz) * (z - cz) <= r * r) im(x, y, z) = 1;
  }
  // Also a little salt: isolated voxels are well-composed, diagonal pairs not.
  for (int k = 0; k < 8; ++k) im(std::size_t(u(rng) * n0), std::size_t(u(rng) * n1), std::size_t(u(rng) * n2)) = 1;
  make_well_composed_slow(im);
  return im;
}

// Brute force: distance (physical) from voxel centre p to the union of the
// closed boxes of opposite-class voxels, outside = background.
inline double brute_distance(const BinaryImage& im, long px, long py, long pz) {
  const bool own = fg(im, px, py, pz);
  const long n[3] = {long(im.size[0]), long(im.size[1]), long(im.size[2])};
  double best = std::numeric_limits<double>::infinity();
  auto consider = [&](long x, long y, long z) {
    const long m[3] = {px - x, py - y, pz - z};
    double s = 0;
    for (int i = 0; i < 3; ++i) {
      const double e = std::max(0.0, (std::abs(double(m[i])) - 0.5) * im.spacing[i]);
      s += e * e;
    }
    best = std::min(best, std::sqrt(s));
  };
  for (long z = -1; z <= n[2]; ++z)
    for (long y = -1; y <= n[1]; ++y)
      for (long x = -1; x <= n[0]; ++x) {
        const bool inside = im.inside(x, y, z);
        const bool f = inside && im(std::size_t(x), std::size_t(y), std::size_t(z));
        if (f != own) consider(x, y, z);
      }
  return own ? -best : best;
}

} // namespace imgmesh::test
