// Tetrahedral mesh files, chosen by extension: Gmsh .msh (4.1, or 2.2 for
// the solvers that read only that; ASCII or binary), MEDIT .mesh, VTK .vtu
// (XML, appended raw data zlib-compressed as VTK writes, or ASCII) and
// Abaqus .inp. Regions travel as physical groups (tetrahedra: dimension 3,
// tag = region; boundary triangles: dimension 2, same tag, "boundary_R"),
// references, cell data "region" (and "boundary": 1 on triangles), element
// sets REGION_R with the boundary as an element-face surface BOUNDARY_R.
// Writes are atomic. Plain C++.
#pragma once
#include "mesh/surface_io.hpp"
#include "mesh/tet_mesh.hpp"

#include <optional>
#include <string>

namespace imgmesh {

// The extensions write_tet_mesh knows, for messages.
extern const char* const kTetMeshExtensions;
bool is_tet_mesh_path(const std::string& path);

struct TetWriteOptions {
  std::string msh_version = "4.1";  // or "2.2"
  bool ascii = false;       // .vtu in ASCII (else appended raw data, zlib-compressed, as VTK writes)
  bool msh_binary = false;  // .msh in Gmsh's binary form (else ASCII)
  std::string vtu_cell_data = "region";  // .vtu: the regions' cell data array (seg2tet: "label")
};

// Gmsh's name of region 0 when the mesh gives none (writer and reader).
inline constexpr const char* kBackgroundName = "background";

// Region 0 (seg2tet --outside's background) is Gmsh's physical tag max + 1,
// named "background" unless the mesh names it (Gmsh's tag 0 is no group),
// and its tag goes in a $BackgroundRegion section (0: none) whenever region
// 0 is present or another region is named "background", so that names do
// not decide; the other formats write 0. A box face (region 0, pair {0, 0}) is in the
// interface group "box" (Abaqus: surface BOX).
// Throws Error on failure (no file left), UsageError on an unknown extension.
void write_tet_mesh(const std::string& path, const TetMesh& mesh, const TetWriteOptions& options = {});

// .msh (2.2 and 4.1, ASCII or binary), .mesh, .vtu (ASCII, inline binary
// or appended raw or base64 data, zlib-compressed or not, either byte order:
// as VTK and meshio write them), legacy .vtk (UNSTRUCTURED_GRID, ASCII or
// BINARY, 4.2 or 5.1), Abaqus .inp (write_inp's and Gmsh's: a tetrahedron's
// region the R of its element set REGION_R or PhysicalVolumeR, the
// triangles those of surfaces BOUNDARY_R and triangle elements; .vtu's
// regions its cell data "region" or "label"; a .msh's physical volume
// $BackgroundRegion's tag, else its physical volume "background", region 0):
// tetrahedra and triangles with their regions. Throws
// Error naming the file on anything malformed.
TetMesh read_tet_mesh(const std::string& path);

// A .msh or a legacy .vtk of either kind, read once (meshinfo takes both):
// `tets` when it holds tetrahedra (.msh) or is an UNSTRUCTURED_GRID (.vtk),
// as read_tet_mesh reads them, else `surface`, its triangles as
// read_surface reads them (label pairs or labels from a .msh's physical
// groups, a .vtk's cell data). Throws Error as they do.
struct TetsOrSurface {
  std::optional<TetMesh> tets;
  std::optional<SurfaceMesh> surface;
};
TetsOrSurface read_tets_or_surface(const std::string& path);

} // namespace imgmesh
