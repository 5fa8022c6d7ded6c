#include "mesh/voxel_sides.hpp"

#include "mesh/embedding.hpp"

#include <algorithm>
#include <memory>

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
template <class Visit>
void for_each_centre_next_to_boundary(const Geometry& grid, const Foreground& foreground, Visit visit,
                                      const std::array<Index3, 2>* box = nullptr) {
  const auto fg = [&](std::ptrdiff_t x, std::ptrdiff_t y, std::ptrdiff_t z) {
    return grid.inside(x, y, z) && foreground(std::size_t(x), std::size_t(y), std::size_t(z));
  };
  std::size_t lo[3] = {0, 0, 0}, end[3] = {grid.size[0], grid.size[1], grid.size[2]};
  if (box)
    for (int a = 0; a < 3; ++a) {
      lo[a] = std::size_t(std::clamp<std::ptrdiff_t>((*box)[0][a] - 1, 0, std::ptrdiff_t(grid.size[a])));
      end[a] = std::size_t(std::clamp<std::ptrdiff_t>((*box)[1][a] + 2, 0, std::ptrdiff_t(grid.size[a])));
    }
  for (std::size_t k = lo[2]; k < end[2]; ++k)
    for (std::size_t j = lo[1]; j < end[1]; ++j)
      for (std::size_t i = lo[0]; i < end[0]; ++i) {
        const std::ptrdiff_t x = std::ptrdiff_t(i), y = std::ptrdiff_t(j), z = std::ptrdiff_t(k);
        const bool in = foreground(i, j, k);
        bool next = false;
        for (int a = 0; a < 3 && !next; ++a)
          for (int s : {-1, 1})
            next = next || fg(x + (a == 0) * s, y + (a == 1) * s, z + (a == 2) * s) != in;
        if (next) visit(i, j, k, in);
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
