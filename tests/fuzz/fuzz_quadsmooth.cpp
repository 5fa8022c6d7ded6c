// What quadsmooth runs on the mesh it reads: an OFF quad (or mixed) mesh, the
// input checks of smooth_quad_mesh and two passes (up to 48 elements).
#include "fuzz.hpp"
#include "planar/planar_formats.hpp"
#include "quadsmooth/smooth.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size < 1) return 0;
  const std::string path = fuzz::write_file("q.off", data + 1, size - 1);
  fuzz::refuse_or_pass([&] {
    imgmesh::PlanarMesh m = imgmesh::read_planar_mesh(path);
    if (m.elements.size() > 48 || m.points.size() > 96) return;
    imgmesh::SmoothOptions opt;
    opt.iterations = 2;
    opt.cleanup = data[0] & 1;
    opt.slide_boundary = data[0] & 2;
    imgmesh::smooth_quad_mesh(m, opt);
  });
  return 0;
}
