// Surface meshes as meshinfo reads them (OFF, .vtp and .vtk by our own
// readers, PLY/OBJ/STL through OpenMesh), then meshinfo's report on what it
// read (up to 200 faces): the first byte picks OFF, PLY, OBJ, STL, OFF on
// standard input, .vtp or .vtk.
#include "fuzz.hpp"
#include "mesh/surface_io.hpp"
#include "meshinfo/meshinfo.hpp"

#include <iostream>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size < 1) return 0;
  static const char* const names[] = {"s.off", "s.ply", "s.obj", "s.stl", "stdin.off", "s.vtp", "s.vtk"};
  const unsigned pick = data[0] % 7;
  const std::string path = fuzz::write_file(names[pick], data + 1, size - 1);
  if (pick == 4) {
    if (!std::freopen(path.c_str(), "rb", stdin)) std::abort();
    std::cin.clear();
    fuzz::refuse_or_pass([&] { imgmesh::read_surface("-"); });
    return 0;
  }
  fuzz::refuse_or_pass([&] { imgmesh::read_surface(path); });
  fuzz::refuse_or_pass([&] {
    const imgmesh::PolyMesh m = imgmesh::read_poly_mesh(path);
    if (m.faces.size() <= 200) imgmesh::mesh_report(m);
  });
  return 0;
}
