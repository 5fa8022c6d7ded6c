// Triangle surface meshes in world coordinates, and their I/O through
// OpenMesh (OFF, PLY, OBJ, STL by extension; "-" is OFF on stdin/stdout).
// This header is plain data; OpenMesh stays inside surface_io.cpp.
#pragma once
#include <array>
#include <string>
#include <vector>

namespace imgmesh {

struct SurfaceMesh {
  std::vector<std::array<double, 3>> points;
  std::vector<std::array<int, 3>> triangles;   // 0-based, counter-clockwise seen from outside
  std::vector<std::array<double, 3>> normals;  // per vertex, empty or points.size()
};

// Throws Error on unreadable files, non-triangle faces, bad ids, NaNs.
SurfaceMesh read_surface(const std::string& path);
// Atomic; binary PLY/STL, ASCII OFF/OBJ; normals written when present (PLY/OBJ).
void write_surface(const std::string& path, const SurfaceMesh& mesh);

} // namespace imgmesh
