// Label images for the interface complex's tests: boxes painted on a grid,
// random well-composed partitions (balls, kept when every label's indicator
// is free of C1 and C2), indicators as the binary code path reads them.
#pragma once
#include "image/grid.hpp"
#include "wellcomposed/well_composed.hpp"

#include <algorithm>
#include <array>
#include <cstdint>
#include <random>
#include <set>

namespace imgmesh::test {

inline LabelImage label_grid(std::size_t nx, std::size_t ny, std::size_t nz, int dim = 3) {
  Geometry g;
  g.dimension = dim;
  g.size = {nx, ny, nz};
  return LabelImage(g, 0);
}

// Voxels lo..hi (inclusive) set to `label`.
inline void paint(LabelImage& img, Index3 lo, Index3 hi, std::int32_t label) {
  for (std::ptrdiff_t z = lo[2]; z <= hi[2]; ++z)
    for (std::ptrdiff_t y = lo[1]; y <= hi[1]; ++y)
      for (std::ptrdiff_t x = lo[0]; x <= hi[0]; ++x) img(std::size_t(x), std::size_t(y), std::size_t(z)) = label;
}

// {X = L} as a binary image; label 0: X != 0 (its complement, with beyond the
// grid, is {X = 0}: the same faces, the same critical configurations).
inline BinaryImage indicator(const LabelImage& img, std::int32_t label) {
  BinaryImage b(img.geometry(), 0);
  for (std::size_t i = 0; i < img.data.size(); ++i)
    b.data[i] = label == 0 ? img.data[i] != 0 : img.data[i] == label;
  return b;
}

inline std::set<std::int32_t> labels_of(const LabelImage& img) {
  std::set<std::int32_t> s(img.data.begin(), img.data.end());
  s.insert(0);
  return s;
}

inline bool partition_well_composed(const LabelImage& img) {
  for (std::int32_t l : labels_of(img))
    if (!is_well_composed(indicator(img, l))) return false;
  return true;
}

// A few balls of random labels 1..labels (later balls drawn over earlier
// ones), centres anywhere on the grid so that some touch its sides.
inline LabelImage random_balls(std::mt19937_64& rng, int dim, int labels) {
  std::uniform_int_distribution<int> side(6, dim == 2 ? 24 : 14), count(2, 7), label(1, labels);
  LabelImage img = label_grid(std::size_t(side(rng)), std::size_t(side(rng)), dim == 2 ? 1 : std::size_t(side(rng)), dim);
  std::uniform_real_distribution<double> u(0, 1), radius(1.2, 5.0);
  for (int b = count(rng); b > 0; --b) {
    const double c[3] = {u(rng) * double(img.size[0]), u(rng) * double(img.size[1]),
                         dim == 2 ? 0.0 : u(rng) * double(img.size[2])};
    const double r = radius(rng);
    const std::int32_t l = label(rng);
    for (std::size_t z = 0; z < img.size[2]; ++z)
      for (std::size_t y = 0; y < img.size[1]; ++y)
        for (std::size_t x = 0; x < img.size[0]; ++x) {
          const double d[3] = {double(x) - c[0], double(y) - c[1], double(z) - c[2]};
          if (d[0] * d[0] + d[1] * d[1] + d[2] * d[2] <= r * r) img(x, y, z) = l;
        }
  }
  return img;
}

// The next random ball image that is a well-composed partition.
inline LabelImage random_well_composed(std::mt19937_64& rng, int dim, int labels) {
  for (;;) {
    LabelImage img = random_balls(rng, dim, labels);
    if (partition_well_composed(img)) return img;
  }
}

// f(img) for every partition of a 2x2x2 grid's voxels into labels 0, 1, ...
// (numbered in order of first voxel: the 4140 restricted growth strings).
template <class F> void for_each_block_partition(F&& f) {
  std::array<int, 8> a{};
  auto next = [&a] {
    int i = 7;
    for (; i > 0; --i)
      if (a[std::size_t(i)] <= *std::max_element(a.begin(), a.begin() + i)) break;
    if (i == 0) return false;
    ++a[std::size_t(i)];
    for (int j = i + 1; j < 8; ++j) a[std::size_t(j)] = 0;
    return true;
  };
  do {
    LabelImage img = label_grid(2, 2, 2);
    for (int v = 0; v < 8; ++v) img.data[std::size_t(v)] = a[std::size_t(v)];
    f(img);
  } while (next());
}

} // namespace imgmesh::test
