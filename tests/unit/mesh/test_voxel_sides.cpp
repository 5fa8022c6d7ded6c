// voxel_sides over a box outside which every voxel is background (a crop
// placed in its scan): the counts of the whole grid.
#include "mesh/voxel_sides.hpp"

#include <catch2/catch.hpp>

using namespace imgmesh;

TEST_CASE("voxel_sides: given the foreground's box, the counts of the whole grid", "[voxel_sides]") {
  Geometry grid;
  grid.size = {12, 11, 10};
  grid.spacing = {1.0, 0.8, 1.5};
  // The foreground: a 3x3x3 block at 4..6 and a voxel at 7 7 6 (a corner of
  // the box); the surface: a box a little off the voxel boundary, so that
  // some centres lie on the wrong side.
  auto fg = [](std::size_t i, std::size_t j, std::size_t k) {
    return (i >= 4 && i <= 6 && j >= 4 && j <= 6 && k >= 4 && k <= 6) || (i == 7 && j == 7 && k == 6);
  };
  const double lo[3] = {3.6, 3.4 * 0.8, 3.7 * 1.5}, hi[3] = {6.8, 6.3 * 0.8, 6.2 * 1.5};
  std::vector<Vec3> p;
  for (int m = 0; m < 8; ++m) p.push_back({m & 1 ? hi[0] : lo[0], m & 2 ? hi[1] : lo[1], m & 4 ? hi[2] : lo[2]});
  const std::vector<std::array<int, 3>> t = {{0, 2, 3}, {0, 3, 1}, {4, 5, 7}, {4, 7, 6}, {0, 1, 5}, {0, 5, 4},
                                             {2, 6, 7}, {2, 7, 3}, {0, 4, 6}, {0, 6, 2}, {1, 3, 7}, {1, 7, 5}};
  const std::vector<int> component(t.size(), 0);
  const VoxelSides whole = voxel_sides(p, t, component, 1, grid, fg);
  const std::array<Index3, 2> box{Index3{4, 4, 4}, Index3{7, 7, 6}};
  const VoxelSides boxed = voxel_sides(p, t, component, 1, grid, fg, &box);
  REQUIRE(whole.checked > 27);
  CHECK(whole.wrong() > 0);
  CHECK(boxed.checked == whole.checked);
  CHECK(boxed.foreground_outside == whole.foreground_outside);
  CHECK(boxed.background_inside == whole.background_inside);
  CHECK(boxed.on_surface == whole.on_surface);
}
