// The implicit function file (wc2implicit's output) as implicit-eval and
// implicit2mesh read it, then f and its gradient at a few points inside and
// outside its domain.
#include "fuzz.hpp"
#include "implicit/implicit_file.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string path = fuzz::write_file("f.nrrd", data, size);
  fuzz::refuse_or_pass([&] {
    const imgmesh::PartitionOfUnity f = imgmesh::read_implicit(path);
    imgmesh::Vec3 grad{0, 0, 0};
    volatile double sink = 0;
    for (double t : {-1e9, -1.0, 0.0, 0.37, 1.5, 7.25, 1e9}) {
      const imgmesh::Vec3 p{t, t * 0.5, -t};
      sink = sink + f.value(p) + f.value_gradient(p, grad);
    }
  });
  return 0;
}
