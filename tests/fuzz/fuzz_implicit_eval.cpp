// implicit-eval's point lines ("x y z" a line) on a small f (one voxel's
// implicit function); the first byte sets --gradient and --allow-outside.
#include "fuzz.hpp"
#include "implicit/evaluate.hpp"
#include "implicit/implicit_file.hpp"

#include <sstream>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size < 1) return 0;
  static const imgmesh::PartitionOfUnity f = [] {
    imgmesh::Geometry g;
    g.size = {3, 3, 3};
    g.spacing = {1, 0.5, 2};
    imgmesh::BinaryImage wc(g, 0);
    wc(1, 1, 1) = 1;
    return imgmesh::implicit_from_well_composed(wc);
  }();
  std::istringstream in(std::string(reinterpret_cast<const char*>(data + 1), size - 1));
  std::ostringstream out;
  fuzz::refuse_or_pass([&] { imgmesh::evaluate_points(f, in, out, data[0] & 1, data[0] & 2, "points.txt"); });
  return 0;
}
