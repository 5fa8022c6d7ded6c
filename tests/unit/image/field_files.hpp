// Valid image files as the field's tools write them, written here byte by
// byte from each format's specification (never through ITK): MetaImage as
// ITK's and VTK's writers make it (.mha, .mhd with .raw, .zraw or a list of
// slice files), NRRD as teem and 3D Slicer make it (attached or detached,
// raw or gzip, LPS or RAS, any axis order), NIfTI-1 as niftilib and nibabel
// make it (sform, qform, .nii, .nii.gz, either byte order). Each file is
// written from a Volume: the voxels and the world geometry (ITK's LPS) the
// reader must give back.
#pragma once
#include <array>
#include <string>
#include <vector>

namespace imgmesh::test {

// A voxel type, with its name in each format (nifti: NIfTI-1 datatype code).
struct VoxelType {
  const char* itk;  // ImageInfo::component
  int bytes;
  bool is_signed;
  const char* meta;
  const char* nrrd;
  int nifti;
};
extern const std::array<VoxelType, 6> kIntegerTypes;  // 8, 16, 32 bits, unsigned and signed

struct Volume {
  std::array<std::size_t, 3> size{13, 11, 7};  // unequal: a swapped axis shows
  std::array<double, 3> origin{-12.5, 3.25, 7.0};
  std::array<double, 3> spacing{0.6, 0.7, 1.3};
  std::array<double, 9> direction{1, 0, 0, 0, 1, 0, 0, 0, 1};  // LPS, row-major: column c is axis c
  VoxelType type = kIntegerTypes[0];
  std::vector<long long> values;  // x fastest; random, so a flipped or shifted axis shows
};

// A volume of `type` whose values are random over the type's range (every
// byte used; negative ones when signed; unsigned 32-bit ones below 2^31,
// what a label image holds), compressing to more bytes than a header holds.
Volume volume_of(const VoxelType& type);
// Rotation matrices (row-major): an oblique rotation; an axis permutation with a flip.
std::array<double, 9> oblique_rotation();
std::array<double, 9> permuted_axes();

// The voxels' bytes; zlib or gzip streams.
std::string voxel_bytes(const Volume& v, bool big_endian);
std::string deflate_bytes(const std::string& raw, bool gzip);
void write_bytes(const std::string& path, const std::string& bytes);

struct MetaOptions {
  std::string data = "LOCAL";   // LOCAL, a file name, "LIST" (one file a slice) or a %d pattern
  bool compressed = false;
  bool declare_size = true;     // CompressedDataSize, as ITK's writer (not for lists)
  bool big_endian = false;
  bool vtk_style = false;       // the field names VTK's vtkMetaImageWriter uses
  int header_bytes = 0;         // HeaderSize: bytes before the voxels in a raw data file
};
// header: .mha or .mhd; data files beside it.
void write_metaimage(const std::string& header, const Volume& v, const MetaOptions& o);

struct NrrdOptions {
  std::string data_file;        // empty: attached
  bool gzip = false;
  bool big_endian = false;
  bool ras = false;             // space: right-anterior-superior
  std::vector<std::string> fields;  // "key:=value" lines
  int list_axis = 0;            // > 0: a first axis of that many "list" layers, values repeated
};
void write_nrrd(const std::string& header, const Volume& v, const NrrdOptions& o);

struct NiftiOptions {
  bool sform = true, qform = true;
  bool big_endian = false;
  bool gzip = false;            // .nii.gz
  bool nibabel = false;         // as nibabel writes a new image: scl_slope and scl_inter NaN, sform_code 2
  bool time_axis = false;       // dim[0] 4 with one time point, as some converters write 3D data
};
void write_nifti(const std::string& path, const Volume& v, const NiftiOptions& o);

} // namespace imgmesh::test
