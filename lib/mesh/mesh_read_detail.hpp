// Private to lib/mesh: the readers that read_surface (surface_io.cpp) shares
// with read_tet_mesh (volume_read.cpp), and the one of its own it keeps
// apart (surface_read.cpp): the .msh reader with the file's physical names
// and label pairs, VTK XML PolyData on the .vtu reader's arrays, legacy VTK.
#pragma once
#include "mesh/surface_io.hpp"
#include "mesh/tet_mesh.hpp"

#include <array>
#include <map>
#include <string>

namespace imgmesh::mesh_detail {

struct MshFile {
  TetMesh mesh;  // its tetrahedra and triangles, each with its physical tag (else its entity's)
  std::map<int, std::string> physical_names;      // of the dimension-2 groups, by tag
  std::map<int, std::array<int, 2>> label_pairs;  // $LabelPairs: a group's (behind, front)
};
// .msh 2.2 or 4.1, ASCII or binary; Error naming the file on anything malformed.
MshFile read_msh_file(const std::string& path);

// .vtp: points, triangles (Polys; Error on another polygon), cell data
// "label" and the 2-component "labels" when present.
SurfaceMesh read_vtp(const std::string& path);
// Legacy .vtk POLYDATA (ASCII or BINARY; 4.2's POLYGONS or 5.1's OFFSETS
// and CONNECTIVITY), the same arrays.
SurfaceMesh read_vtk_legacy(const std::string& path);
// A .msh's triangles, their physical groups read back as write_msh writes
// them: label pairs ($LabelPairs, else groups named "a|b" of two
// integers), else labels (the group's tag) unless the groups are
// components ("component C").
SurfaceMesh read_msh_surface(const std::string& path);
// The same from a file read (read_msh_file); path names it in errors.
SurfaceMesh msh_surface(MshFile file, const std::string& path);

} // namespace imgmesh::mesh_detail
