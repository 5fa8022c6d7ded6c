// Images through lib/image as img2wc, img2poly and wc2implicit read them: the
// first byte picks the format (by file name, or standard input with its
// spooling and format sniffing), the rest is the file.
#include "fuzz.hpp"
#include "image/io.hpp"

#include <iostream>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size < 1) return 0;
  static const char* const names[] = {"in.nrrd", "in.mha", "in.nii", "in.nii.gz", "in.png", "stdin.bin"};
  const unsigned pick = data[0] % 6;
  const std::string file = fuzz::write_file(names[pick], data + 1, size - 1);
  std::string path = file;
  auto rewind_stdin = [&] {
    if (pick != 5) return;
    if (!std::freopen(file.c_str(), "rb", stdin)) std::abort();
    std::cin.clear();
    path = "-";
  };
  rewind_stdin();
  fuzz::refuse_or_pass([&] { imgmesh::read_image_info(path); });
  rewind_stdin();
  fuzz::refuse_or_pass([&] { imgmesh::read_foreground(path, {}); });
  rewind_stdin();
  imgmesh::Selection sel;
  sel.has_threshold = true;
  sel.threshold = 0.5;
  fuzz::refuse_or_pass([&] { imgmesh::read_labels(path, sel); });
  rewind_stdin();
  fuzz::refuse_or_pass([&] { imgmesh::read_labels(path); });
  rewind_stdin();
  fuzz::refuse_or_pass([&] { imgmesh::read_float(path); });
  rewind_stdin();
  imgmesh::Selection one;  // img2wc --label: the voxels streamed (voxel_stream.hpp)
  one.labels = {1};
  fuzz::refuse_or_pass([&] { imgmesh::read_foreground_runs(path, one); });
  return 0;
}
