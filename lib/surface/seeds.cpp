#include "surface/seeds.hpp"

#include <algorithm>
#include <array>
#include <random>

namespace imgmesh::surface_detail {

Seeds::Seeds(const SurfaceSampler& f) : f_(f), grid_(f.grid()), cubes_(grid_.sorted_cubes()) {}

std::vector<Vec3> Seeds::points(std::uint64_t seed) const {
  std::vector<std::array<long, 4>> extreme(std::size_t(grid_.components) * 6, {-1, 0, 0, 0});
  for (const ActiveCube& kc : cubes_) {
    const auto [x, y, z] = grid_.cube_of_key(kc.key());
    const long c[3] = {x, y, z};
    for (int a = 0; a < 3; ++a)
      for (int s = 0; s < 2; ++s) {
        auto& e = extreme[std::size_t(kc.comp()) * 6 + a * 2 + s];
        if (e[0] < 0 || (s == 0 ? c[a] < e[1 + a] : c[a] > e[1 + a])) e = {1, x, y, z};
      }
  }
  std::vector<Vec3> pts;
  for (auto& e : extreme) {
    Vec3 x;
    if (e[0] >= 0 && crossing(e[1], e[2], e[3], x)) pts.push_back(x);
  }
  std::sort(pts.begin(), pts.end());
  pts.erase(std::unique(pts.begin(), pts.end()), pts.end());
  std::mt19937_64 rng(seed);
  std::shuffle(pts.begin(), pts.end(), rng);
  return pts;
}

bool Seeds::next_extra(Vec3& x) {
  const std::size_t stride = std::max<std::size_t>(1, cubes_.size() / 64);
  for (; next_cube_ < cubes_.size(); next_cube_ += stride, next_edge_ = 0) {
    const auto [cx, cy, cz] = grid_.cube_of_key(cubes_[next_cube_].key());
    while (next_edge_ < 12)
      if (crossing(cx, cy, cz, x, next_edge_++)) return true;
  }
  return false;
}

bool Seeds::crossing(long x, long y, long z, Vec3& out, int which) const {
  static const int edges[12][2] = {{0, 1}, {2, 3}, {4, 5}, {6, 7}, {0, 2}, {1, 3}, {4, 6}, {5, 7}, {0, 4}, {1, 5}, {2, 6}, {3, 7}};
  for (auto& e : edges) {
    long p[2][3];
    for (int k = 0; k < 2; ++k) {
      p[k][0] = x + (e[k] & 1);
      p[k][1] = y + ((e[k] >> 1) & 1);
      p[k][2] = z + ((e[k] >> 2) & 1);
    }
    if (grid_.neg(p[0][0], p[0][1], p[0][2]) == grid_.neg(p[1][0], p[1][1], p[1][2])) continue;
    if (which-- > 0) continue;
    const Vec3 a{p[0][0] * grid_.s[0], p[0][1] * grid_.s[1], p[0][2] * grid_.s[2]};
    const Vec3 b{p[1][0] * grid_.s[0], p[1][1] * grid_.s[1], p[1][2] * grid_.s[2]};
    return f_.bisect(a, b, f_.value(a), out);
  }
  return false;
}

} // namespace imgmesh::surface_detail
