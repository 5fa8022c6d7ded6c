// Private to lib/mesh: the readers that read_surface (surface_io.cpp) shares
// with read_tet_mesh (volume_read.cpp), and the one of its own it keeps
// apart (surface_read.cpp): the .msh reader with the file's physical names
// and label pairs, VTK XML (vtk_xml_read.cpp: PolyData on the .vtu reader's
// arrays), legacy VTK; the token stream of the text formats.
#pragma once
#include "mesh/surface_io.hpp"
#include "mesh/tet_mesh.hpp"
#include "mesh/volume_io.hpp"

#include "util/coordinates.hpp"
#include "util/error.hpp"
#include "util/parse.hpp"

#include <array>
#include <cctype>
#include <cmath>
#include <istream>
#include <map>
#include <string>
#include <vector>

namespace imgmesh::mesh_detail {

// Reading: a whitespace token stream, counting lines, with the file's name
// and the line in its errors.
struct Tokens {
  std::istream& in;
  const std::string& path;
  int line = 1;  // of the last token read (or where reading stopped)

  [[noreturn]] void fail(const std::string& what) const {
    throw Error("line " + std::to_string(line) + ": " + what, path);
  }
  // Past the blanks; false at the end.
  bool more() {
    for (int c; (c = in.peek()) != EOF && std::isspace(c); in.get())
      if (c == '\n') ++line;
    return in.peek() != EOF;
  }
  bool read(std::string& s) {
    if (!more()) return false;
    s.clear();
    for (int c; (c = in.peek()) != EOF && !std::isspace(c); in.get()) s.push_back(char(c));
    return true;
  }
  std::string next() {
    std::string s;
    if (!read(s)) fail("unexpected end of file");
    return s;
  }
  void skip_line() {
    for (int c; (c = in.get()) != EOF && c != '\n';) {
    }
    ++line;
  }
  long long integer() {
    const std::string s = next();
    long long v;
    if (!parse_integer(s, v)) fail("expected an integer, found '" + s.substr(0, 40) + "'");
    return v;
  }
  double real() {
    const std::string s = next();
    double v;
    if (!parse_real(s, v) || !std::isfinite(v)) fail("expected a finite number, found '" + s.substr(0, 40) + "'");
    return v;
  }
  double coordinate() {
    const std::string s = next();
    double v;
    if (!parse_coordinate(s, v)) fail(coordinate_error(s));
    return v;
  }
  std::size_t count(const char* what) {
    const long long n = integer();
    if (n < 0 || n > 200000000) fail(std::string("bad ") + what + " count " + std::to_string(n));
    return std::size_t(n);
  }
  void skip_to(const std::string& end) {
    while (next() != end) {
    }
  }
};

// Gmsh's element type 4 (tetrahedron) or 2 (triangle) with its region
// into m; other types left out.
inline void add_element(TetMesh& m, int type, const std::vector<int>& v, int region) {
  if (type == 4) {
    m.tets.push_back({v[0], v[1], v[2], v[3]});
    m.tet_region.push_back(region);
  } else if (type == 2) {
    m.triangles.push_back({v[0], v[1], v[2]});
    m.triangle_region.push_back(region);
  }
}


struct MshFile {
  TetMesh mesh;  // its tetrahedra and triangles, each with its physical tag (else its entity's)
  std::map<int, std::string> physical_names;      // of the dimension-2 groups, by tag
  std::map<int, std::array<int, 2>> label_pairs;  // $LabelPairs: a group's (behind, front)
  // Region 0's tag (volume_io.hpp): $BackgroundRegion's, else the physical
  // volume named "background" (files without the section); 0: none.
  int background = 0;
};
// .msh 2.2 or 4.1, ASCII or binary; Error naming the file on anything malformed.
MshFile read_msh_file(const std::string& path);

// VTK XML (vtk_xml_read.cpp), as vtkXMLWriter writes it in any of its
// layouts. .vtp: points, triangles (Polys; Error on another polygon), cell
// data "label" and the 2-component "labels" when present; .vtu: tetrahedra
// and triangles, cell data "region".
SurfaceMesh read_vtp(const std::string& path);
TetMesh read_vtu(const std::string& path);
// Abaqus .inp (inp_read.cpp): C3D4 tetrahedra, a region per element set
// REGION_R or PhysicalVolumeR, the triangles of surfaces BOUNDARY_R (faces
// of tetrahedra) and 3-node triangle elements.
TetMesh read_inp(const std::string& path);
// Legacy .vtk POLYDATA (ASCII or BINARY; 4.2's POLYGONS or 5.1's OFFSETS
// and CONNECTIVITY), the same arrays.
SurfaceMesh read_vtk_legacy(const std::string& path);
// A legacy .vtk of either kind: POLYDATA as read_vtk_legacy reads it, or
// UNSTRUCTURED_GRID (CELLS in either layout, CELL_TYPES, cell data
// "region") as tetrahedra.
TetsOrSurface read_vtk_legacy_mesh(const std::string& path);
// A .msh's triangles, their physical groups read back as write_msh writes
// them: label pairs ($LabelPairs, else groups named "a|b" of two
// integers), else labels (the group's tag) unless the groups are
// components ("component C").
SurfaceMesh read_msh_surface(const std::string& path);
// The same from a file read (read_msh_file); path names it in errors.
SurfaceMesh msh_surface(MshFile file, const std::string& path);

} // namespace imgmesh::mesh_detail
