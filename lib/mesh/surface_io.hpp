// Triangle surface meshes in world coordinates (LPS, as ITK), and their I/O:
// read and write OFF, PLY, OBJ, STL, VTK (.vtp, .vtk) and Gmsh .msh
// (surface_formats.hpp), by extension; "-" is OFF on stdin/stdout. This
// header is plain data; OpenMesh stays inside surface_io.cpp.
#pragma once
#include <array>
#include <map>
#include <string>
#include <vector>

namespace imgmesh {

struct SurfaceMesh {
  std::vector<std::array<double, 3>> points;
  std::vector<std::array<int, 3>> triangles;   // 0-based, counter-clockwise seen from outside
  std::vector<std::array<double, 3>> normals;  // per vertex, empty or points.size()
  std::vector<int> labels;  // per triangle: the segmentation label it bounds, empty when not known
  // Per triangle, the two labels it separates (behind, front), the triangle
  // oriented from behind into front (seg2mesh --fast: each interface once);
  // empty when not known.
  std::vector<std::array<int, 2>> interfaces;
  std::map<int, std::string> label_names;  // a label's name where its image gives one (3D Slicer's segments)
};

struct SurfaceWriteOptions {
  std::string msh_version = "4.1";  // or "2.2"
  // Binary is the default where the format has a binary form (.ply, .stl,
  // .vtp, .vtk); ascii writes their text form. .msh is ASCII unless
  // msh_binary (solvers read ASCII .msh more widely).
  bool ascii = false;
  bool msh_binary = false;
};

// The output extensions write_surface takes, for messages and checks.
extern const char* const kSurfaceExtensions;  // ".off, .ply, .obj, .stl, .vtp, .vtk or .msh"
bool is_surface_output(const std::string& path);  // "-" or one of those
// Whether the format of `path` holds vertex normals / face labels.
bool surface_output_holds_normals(const std::string& path);
bool surface_output_holds_labels(const std::string& path);

// Throws Error on unreadable files, non-triangle faces, bad ids, NaNs.
// Per-face labels and label pairs are read back from PLY (properties label,
// label_behind and label_front), .vtp and .vtk (cell data label and the
// 2-component labels; in any layout VTK's writers use) and .msh (physical
// groups, see write_msh); a PLY with label pairs is read as it is (an
// interface mesh is no manifold: OpenMesh would cut it), any other through
// OpenMesh.
SurfaceMesh read_surface(const std::string& path);
// Atomic; binary PLY/STL/VTK (or ASCII, options.ascii), ASCII OFF/OBJ, msh
// as options say; normals written when
// present (PLY, OBJ, VTK, msh); per-face component ids, labels and label
// pairs in PLY, VTK and msh, with the labels' names where known. Throws UsageError on an unknown extension or msh version.
void write_surface(const std::string& path, const SurfaceMesh& mesh, const SurfaceWriteOptions& options = {});

} // namespace imgmesh
