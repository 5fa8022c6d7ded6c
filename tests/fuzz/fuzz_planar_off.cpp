// Planar OFF as tri2quad, quadsmooth (meshes) and poly2tri (PSLGs) read it,
// from a file and (odd first byte) from standard input.
#include "fuzz.hpp"
#include "planar/planar_formats.hpp"

#include <iostream>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size < 1) return 0;
  const std::string path = fuzz::write_file("m.off", data + 1, size - 1);
  if (data[0] & 1) {
    if (!std::freopen(path.c_str(), "rb", stdin)) std::abort();
    std::cin.clear();
    fuzz::refuse_or_pass([&] { imgmesh::read_planar_mesh("-"); });
    return 0;
  }
  fuzz::refuse_or_pass([&] { imgmesh::read_planar_mesh(path); });
  fuzz::refuse_or_pass([&] { imgmesh::read_pslg(path); });
  return 0;
}
