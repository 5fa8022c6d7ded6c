// A 2D or 3D scalar image on a regular grid with ITK's world geometry:
// world = origin + direction * diag(spacing) * index. 2D images have
// size[2] == 1 and dimension == 2. Voxels are stored x fastest, then y, then z.
// Plain data, no ITK: every module can use it without the heavy headers.
#pragma once
#include <array>
#include <cstddef>
#include <cstdint>
#include <vector>

namespace imgmesh {

using Index3 = std::array<std::ptrdiff_t, 3>;
using Vec3 = std::array<double, 3>;

struct Geometry {
  int dimension = 3;                       // 2 or 3
  std::array<std::size_t, 3> size{1, 1, 1};
  Vec3 origin{0, 0, 0};                    // world position of voxel (0,0,0)'s centre
  Vec3 spacing{1, 1, 1};                   // > 0
  std::array<double, 9> direction{1, 0, 0, 0, 1, 0, 0, 0, 1};  // row-major, orthonormal

  std::size_t count() const { return size[0] * size[1] * size[2]; }
  std::size_t index(std::size_t x, std::size_t y, std::size_t z) const {
    return x + size[0] * (y + size[1] * z);
  }
  bool inside(std::ptrdiff_t x, std::ptrdiff_t y, std::ptrdiff_t z) const {
    return x >= 0 && y >= 0 && z >= 0 && std::size_t(x) < size[0] && std::size_t(y) < size[1] &&
           std::size_t(z) < size[2];
  }
  // World coordinates of a continuous index (voxel centres at integers).
  Vec3 world(double i, double j, double k) const {
    const double a = i * spacing[0], b = j * spacing[1], c = k * spacing[2];
    return {origin[0] + direction[0] * a + direction[1] * b + direction[2] * c,
            origin[1] + direction[3] * a + direction[4] * b + direction[5] * c,
            origin[2] + direction[6] * a + direction[7] * b + direction[8] * c};
  }
  // Continuous index of a world point (inverse of world(); direction is orthonormal).
  Vec3 continuous_index(const Vec3& p) const {
    const double u = p[0] - origin[0], v = p[1] - origin[1], w = p[2] - origin[2];
    return {(direction[0] * u + direction[3] * v + direction[6] * w) / spacing[0],
            (direction[1] * u + direction[4] * v + direction[7] * w) / spacing[1],
            (direction[2] * u + direction[5] * v + direction[8] * w) / spacing[2]};
  }
  // Same grid shape and world placement.
  bool same_grid(const Geometry& o) const {
    return dimension == o.dimension && size == o.size && origin == o.origin &&
           spacing == o.spacing && direction == o.direction;
  }
};

template <class T> struct Image : Geometry {
  std::vector<T> data;

  Image() = default;
  explicit Image(const Geometry& g, T fill = T()) : Geometry(g), data(g.count(), fill) {}
  const Geometry& geometry() const { return *this; }

  T& operator()(std::size_t x, std::size_t y, std::size_t z = 0) { return data[index(x, y, z)]; }
  const T& operator()(std::size_t x, std::size_t y, std::size_t z = 0) const {
    return data[index(x, y, z)];
  }
  // Value at a possibly outside index; outside reads as `outside`.
  T at(std::ptrdiff_t x, std::ptrdiff_t y, std::ptrdiff_t z, T outside = T()) const {
    return inside(x, y, z) ? data[index(std::size_t(x), std::size_t(y), std::size_t(z))] : outside;
  }
};

// Foreground = 1, background = 0.
using BinaryImage = Image<std::uint8_t>;
using FloatImage = Image<float>;
using LabelImage = Image<std::int32_t>;

// Grow the grid by `before[i]` voxels before and `after[i]` after on axis i,
// moving the origin so that world coordinates of existing voxels stay exact.
template <class T>
Image<T> pad(const Image<T>& in, std::array<std::size_t, 3> before, std::array<std::size_t, 3> after,
             T fill = T()) {
  Geometry g = in.geometry();
  for (int i = 0; i < 3; ++i) g.size[i] = in.size[i] + before[i] + after[i];
  g.origin = in.world(-double(before[0]), -double(before[1]), -double(before[2]));
  Image<T> out(g, fill);
  for (std::size_t z = 0; z < in.size[2]; ++z)
    for (std::size_t y = 0; y < in.size[1]; ++y)
      for (std::size_t x = 0; x < in.size[0]; ++x)
        out(x + before[0], y + before[1], z + before[2]) = in(x, y, z);
  return out;
}

} // namespace imgmesh
