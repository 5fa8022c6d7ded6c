#include "mesh/voxel_sides.hpp"

#include "mesh/embedding.hpp"

#include <algorithm>
#include <cstddef>
#include <memory>
#include <vector>

namespace imgmesh {

Json VoxelSides::to_json() const {
  Json j = Json::object();
  j["voxel_centres_checked"] = checked;
  j["wrong_side"] = wrong();
  j["foreground_outside"] = foreground_outside;
  j["background_inside"] = background_inside;
  j["on_surface"] = on_surface;
  return j;
}

VoxelSides voxel_sides(const std::vector<Vec3>& points, const std::vector<std::array<int, 3>>& triangles,
                       const std::vector<int>& component, std::size_t components, const BinaryImage& img) {
  return voxel_sides(points, triangles, component, components, img,
                     [&img](std::size_t i, std::size_t j, std::size_t k) { return img(i, j, k) != 0; });
}

namespace {
// visit(i, j, k, in) for every voxel with a face on bdCA(X): a
// face-neighbour (or the outside, for foreground) on the other side.
// Beyond box (grown by one voxel) no voxel has a foreground neighbour.
// foreground is asked once per voxel of the scanned box grown by one (not
// once per face-neighbour: its calls were most of the bunny's count), the
// answers kept for three z-slices at a time.
template <class Visit>
void for_each_centre_next_to_boundary(const Geometry& grid, const Foreground& foreground, Visit visit,
                                      const std::array<Index3, 2>* box = nullptr) {
  std::size_t lo[3] = {0, 0, 0}, end[3] = {grid.size[0], grid.size[1], grid.size[2]};
  if (box)
    for (int a = 0; a < 3; ++a) {
      lo[a] = std::size_t(std::clamp<std::ptrdiff_t>((*box)[0][a] - 1, 0, std::ptrdiff_t(grid.size[a])));
      end[a] = std::size_t(std::clamp<std::ptrdiff_t>((*box)[1][a] + 2, 0, std::ptrdiff_t(grid.size[a])));
    }
  if (lo[0] >= end[0] || lo[1] >= end[1] || lo[2] >= end[2]) return;
  // A slice: x in [lo0 - 1, end0], y in [lo1 - 1, end1]; 0 beyond the grid.
  const std::size_t nx = end[0] - lo[0] + 2, ny = end[1] - lo[1] + 2;
  std::vector<char> slices[3];
  auto fill = [&](std::vector<char>& s, std::ptrdiff_t z) {
    s.assign(nx * ny, 0);
    if (z < 0 || z >= std::ptrdiff_t(grid.size[2])) return;
    for (std::size_t v = 0; v < ny; ++v) {
      const std::ptrdiff_t y = std::ptrdiff_t(lo[1] + v) - 1;
      if (y < 0 || y >= std::ptrdiff_t(grid.size[1])) continue;
      for (std::size_t u = 0; u < nx; ++u) {
        const std::ptrdiff_t x = std::ptrdiff_t(lo[0] + u) - 1;
        if (x >= 0 && x < std::ptrdiff_t(grid.size[0]))
          s[v * nx + u] = foreground(std::size_t(x), std::size_t(y), std::size_t(z));
      }
    }
  };
  fill(slices[0], std::ptrdiff_t(lo[2]) - 1);
  fill(slices[1], std::ptrdiff_t(lo[2]));
  for (std::size_t k = lo[2]; k < end[2]; ++k) {
    fill(slices[2], std::ptrdiff_t(k) + 1);
    const std::vector<char>&below = slices[0], &here = slices[1], &above = slices[2];
    for (std::size_t j = lo[1]; j < end[1]; ++j)
      for (std::size_t i = lo[0]; i < end[0]; ++i) {
        const std::size_t at = (j - lo[1] + 1) * nx + (i - lo[0] + 1);
        const char in = here[at];
        const bool next = here[at - 1] != in || here[at + 1] != in || here[at - nx] != in || here[at + nx] != in ||
                          below[at] != in || above[at] != in;
        if (next) visit(i, j, k, in != 0);
      }
    std::swap(slices[0], slices[1]);
    std::swap(slices[1], slices[2]);
  }
}
} // namespace

std::size_t centres_next_to_boundary(const BinaryImage& img) {
  std::size_t n = 0;
  for_each_centre_next_to_boundary(img, [&img](std::size_t i, std::size_t j, std::size_t k) { return img(i, j, k) != 0; },
                                   [&n](std::size_t, std::size_t, std::size_t, bool) { ++n; });
  return n;
}

VoxelSides voxel_sides(const std::vector<Vec3>& points, const std::vector<std::array<int, 3>>& triangles,
                       const std::vector<int>& component, std::size_t components, const Geometry& grid,
                       const Foreground& foreground, const std::array<Index3, 2>* box) {
  // Rays along the lines of centres (x); where one grazes an edge or a
  // vertex, along y, then z (their bins made when first needed), then
  // SurfaceGeometry's (a mesh and a tree of every triangle).
  std::unique_ptr<LineSides> lines[3];
  lines[0] = std::make_unique<LineSides>(points, triangles, 0);
  std::unique_ptr<SurfaceGeometry> g;
  VoxelSides r;
  for_each_centre_next_to_boundary(
      grid, foreground,
      [&](std::size_t i, std::size_t j, std::size_t k, bool in) {
        ++r.checked;
        const Vec3 p = grid.world(double(i), double(j), double(k));
        int side = LineSides::kGrazing;
        for (int a = 0; a < 3 && side == LineSides::kGrazing; ++a) {
          if (!lines[a]) lines[a] = std::make_unique<LineSides>(points, triangles, a);
          side = lines[a]->side(p);
        }
        if (side == LineSides::kGrazing) {
          if (!g) g = std::make_unique<SurfaceGeometry>(points, triangles, component, components);
          side = g->side(p);
        }
        if (side == 0) ++r.on_surface;
        else if (in && side > 0) ++r.foreground_outside;
        else if (!in && side < 0) ++r.background_inside;
      },
      box);
  return r;
}

} // namespace imgmesh
