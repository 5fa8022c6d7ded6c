// Triangle's formats as poly2tri, tri2quad and quadsmooth read them, and
// poly2tri's refinement of a small PSLG read (up to 64 vertices, 2,000 in
// the mesh: the work budget; issue 35's SIGFPE was in the refinement). The
// first byte picks .node, .poly or .ele; for .poly and .ele a NUL byte
// splits the input into that file and the .node beside it (no NUL: no .node).
#include "fuzz.hpp"
#include "planar/planar_formats.hpp"
#include "planar/triangle_io.hpp"
#include "planar/triangulate.hpp"

#include <algorithm>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size < 1) return 0;
  const unsigned pick = data[0] % 3;
  const std::uint8_t* begin = data + 1;
  const std::uint8_t* end = data + size;
  if (pick == 0) {
    const std::string path = fuzz::write_file("t.node", begin, std::size_t(end - begin));
    fuzz::refuse_or_pass([&] { imgmesh::read_node(path); });
    return 0;
  }
  const std::uint8_t* nul = std::find(begin, end, std::uint8_t(0));
  const std::string stem = pick == 1 ? "p" : "e";
  const std::string path = fuzz::write_file(stem + (pick == 1 ? ".poly" : ".ele"), begin, std::size_t(nul - begin));
  const std::string node = fuzz::scratch() + "/" + stem + ".node";
  if (nul != end) fuzz::write_file(stem + ".node", nul + 1, std::size_t(end - nul - 1));
  else std::remove(node.c_str());
  if (pick == 1) {
    fuzz::refuse_or_pass([&] { imgmesh::read_poly(path); });
    fuzz::refuse_or_pass([&] {
      const imgmesh::PlanarMesh pslg = imgmesh::read_pslg(path);
      if (pslg.points.size() > 64) return;
      imgmesh::TriangulateOptions opt;
      opt.max_vertices = 2000;
      (void)imgmesh::triangulate_pslg(pslg, opt).failed_guarantee();
    });
  } else {
    fuzz::refuse_or_pass([&] { imgmesh::read_ele(path); });
    fuzz::refuse_or_pass([&] { imgmesh::read_planar_mesh(path); });
  }
  return 0;
}
