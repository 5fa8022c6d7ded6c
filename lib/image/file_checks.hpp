// Checks of image files before (or, for NIfTI, after) ITK reads them. Each
// *_error returns what is wrong, or "" when the check has nothing to say;
// the check_* functions throw Error naming `path` (the name the user gave).
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>

namespace imgmesh {

// A NIfTI file (.nii, .nii.gz) holds its whole voxel block: ITK zero-pads.
void check_nifti_complete(const std::string& path, const std::string& file, std::size_t data_bytes);
// The most bytes of voxels `file` can hold (0: not known here).
std::uintmax_t max_data_bytes(const std::string& file, std::uintmax_t file_size);
std::uintmax_t physical_memory();
// data_bytes fit in the file (when known) and in this machine's memory.
void check_declared_size(const std::string& path, const std::string& file, std::uintmax_t data_bytes);
std::string png_header_error(const std::string& file);
// Before MetaIO reads the header.
std::string metaimage_header_error(const std::string& file);
// After MetaIO read the header, before it reads `bytes` of voxels.
std::string metaimage_data_error(const std::string& file, std::uintmax_t bytes);
std::string nifti_header_error(const std::string& file);

}  // namespace imgmesh
