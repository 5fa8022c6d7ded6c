// What tri2quad runs on the mesh it reads: an OFF triangle mesh, its checks
// in tri2quad_input and the conversion (up to 48 triangles: the work budget).
#include "fuzz.hpp"
#include "planar/planar_formats.hpp"
#include "tri2quad/tri2quad.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size < 1) return 0;
  const std::string path = fuzz::write_file("t.off", data + 1, size - 1);
  fuzz::refuse_or_pass([&] {
    imgmesh::PlanarMesh m = imgmesh::read_planar_mesh(path);
    if (m.elements.size() > 48 || m.points.size() > 96) return;
    const imgmesh::Tri2QuadInput in = imgmesh::tri2quad_input(std::move(m), path);
    imgmesh::Tri2QuadOptions opt;
    opt.allow_outside = data[0] & 1;
    opt.pair_above = data[0] & 2 ? 30 : 0;
    const imgmesh::Tri2QuadResult r = imgmesh::tri2quad(in, opt);
    (void)r.failed_guarantee();
  });
  return 0;
}
