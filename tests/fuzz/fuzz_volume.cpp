// Tetrahedral meshes as meshinfo reads them (Gmsh .msh 2.2/4.1, MEDIT
// .mesh, VTK .vtu, legacy VTK .vtk, Abaqus .inp): the first byte picks the format, the rest is the file;
// then what meshinfo computes on what it read (up to 500 tetrahedra).
#include "fuzz.hpp"
#include "mesh/tet_mesh.hpp"
#include "mesh/volume_io.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size < 1) return 0;
  static const char* const names[] = {"t.msh", "t.mesh", "t.vtu", "t.vtk", "t.inp"};
  const std::string path = fuzz::write_file(names[data[0] % 5], data + 1, size - 1);
  fuzz::refuse_or_pass([&] {
    const imgmesh::TetMesh m = imgmesh::read_tet_mesh(path);
    if (m.tets.size() > 500) return;
    imgmesh::tet_quality(m);
    imgmesh::tet_conformity(m);
    imgmesh::tet_boundary(m);
  });
  return 0;
}
