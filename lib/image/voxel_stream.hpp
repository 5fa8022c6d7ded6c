// The voxel block of an image file of a plain layout, read without ITK:
// NRRD with its data attached (raw or gzip), NIfTI-1 in one file (.nii or
// .nii.gz) and MetaImage with its data LOCAL (raw or zlib). Streamed into
// the caller's buffer: one label of a big scan costs one pass of
// decompression, never a buffer of the whole grid (ITK's readers inflate
// into one, and the NIfTI and MetaImage checks before them inflate the
// data once more). The header (geometry, component type) is still ITK's.
#pragma once

#include <cstddef>
#include <memory>
#include <optional>
#include <string>

namespace imgmesh {

struct VoxelLayout {
  std::size_t offset = 0;  // where the data, or its compressed stream, starts in the file
  std::size_t skip = 0;    // bytes of the inflated stream before the data (.nii.gz: the header)
  bool deflate = false;    // gzip or zlib data
  bool big_endian = false;
  int bytes = 0;           // of a value, by the header's type
  std::size_t values = 0;  // the header's sizes multiplied (and components)
};

// The layout of `file` (by its content) when it is one of the plain ones
// above, else none: ITK reads the file as before (and refuses what is
// wrong with it). Throws nothing.
std::optional<VoxelLayout> plain_voxel_layout(const std::string& file);

// The values of `file` in order (x fastest), `values` of them, in native
// byte order. Throws Error (one line, naming path) when the data is
// truncated or its compressed stream corrupt.
class VoxelStream {
public:
  VoxelStream(const std::string& file, const VoxelLayout& layout, std::size_t values, const std::string& path);
  ~VoxelStream();
  VoxelStream(const VoxelStream&) = delete;
  VoxelStream& operator=(const VoxelStream&) = delete;
  // The next n values into out (n * bytes).
  void read(void* out, std::size_t n);

private:
  struct Source;
  std::unique_ptr<Source> in_;
  VoxelLayout layout_;
  std::string path_;
  std::size_t total_ = 0, done_ = 0;  // bytes declared, given so far
};

} // namespace imgmesh
