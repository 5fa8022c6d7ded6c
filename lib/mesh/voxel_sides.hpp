// Which side of a closed surface each voxel centre next to the voxel
// boundary bdCA(X) lies on (issue 38): a foreground centre should be inside
// the surface, a background one outside. Sides by exact ray tests along
// the lines of centres (LineSides; SurfaceGeometry::side, CGAL's
// Side_of_triangle_mesh, where a line grazes an edge or a vertex), inside
// meaning enclosed by an odd number of the surface's components. Reported
// by meshinfo --image and by the surface mesher's own certificate (which
// fails on a wrong centre unless --no-voxel-sides).
#pragma once
#include "image/grid.hpp"
#include "util/json.hpp"

#include <array>
#include <cstddef>
#include <functional>
#include <vector>

namespace imgmesh {

struct VoxelSides {
  std::size_t checked = 0;             // voxel centres with a face on bdCA(X)
  std::size_t foreground_outside = 0;  // of those, foreground centres outside the surface
  std::size_t background_inside = 0;   // background centres inside it
  std::size_t on_surface = 0;          // centres on a triangle (counted wrong: on no side)
  std::size_t wrong() const { return foreground_outside + background_inside + on_surface; }
  Json to_json() const;
};

// The surface in img's world coordinates: closed, 2-manifold, consistently
// oriented (the certificate's first checks; Error otherwise). component:
// per triangle, its component (0 .. components - 1).
VoxelSides voxel_sides(const std::vector<Vec3>& points, const std::vector<std::array<int, 3>>& triangles,
                       const std::vector<int>& component, std::size_t components, const BinaryImage& img);
// The voxel centres voxel_sides checks on img (those next to bdCA(X)), how
// many: for a caller that knows they are all on their side.
std::size_t centres_next_to_boundary(const BinaryImage& img);
// The same on a grid whose foreground is given per voxel (in the grid;
// beyond it, background): the mesher's, from the signs of f's samples.
// box, when given: inclusive corners outside which every voxel is
// background (a crop placed in its scan): only the box and the voxels
// around it are looked at, so a small label costs its box, not the scan.
using Foreground = std::function<bool(std::size_t, std::size_t, std::size_t)>;
VoxelSides voxel_sides(const std::vector<Vec3>& points, const std::vector<std::array<int, 3>>& triangles,
                       const std::vector<int>& component, std::size_t components, const Geometry& grid,
                       const Foreground& foreground, const std::array<Index3, 2>* box = nullptr);

} // namespace imgmesh
