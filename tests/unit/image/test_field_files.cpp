// Valid files as the field's tools write them (field_files.hpp) are read,
// never refused, to the voxels and the world geometry they were written
// from: every MetaImage, NRRD and NIfTI variant of issue 35.
#include "field_files.hpp"
#include "image/io.hpp"
#include "util/error.hpp"

#include "scratch_dir.hpp"

#include <catch2/catch.hpp>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>

using namespace imgmesh;
using namespace imgmesh::test;

namespace {
std::string in_scratch(const std::string& name) { return scratch_dir() + "/" + name; }

// The file reads to v's voxels, type and geometry (tol: NIfTI holds floats).
void reads_as(const std::string& path, const Volume& v, double tol = 1e-9) {
  INFO(path);
  ImageInfo info;
  LabelImage img;
  try {
    info = read_image_info(path);
    img = read_labels(path);
  } catch (const Error& e) {
    FAIL_CHECK("refused: " << e.what());
    return;
  }
  CHECK(info.component == v.type.itk);
  REQUIRE(img.dimension == 3);
  REQUIRE(img.size == v.size);
  for (int i = 0; i < 3; ++i) {
    CHECK(img.origin[i] == Approx(v.origin[i]).margin(tol));
    CHECK(img.spacing[i] == Approx(v.spacing[i]).margin(tol));
  }
  for (int i = 0; i < 9; ++i) CHECK(img.direction[i] == Approx(v.direction[i]).margin(tol));
  const std::vector<long long> got(img.data.begin(), img.data.end());
  CHECK(got == v.values);
}

Volume rotated(const VoxelType& t) {
  Volume v = volume_of(t);
  v.direction = oblique_rotation();
  return v;
}
} // namespace

TEST_CASE("MetaImage as ITK and VTK write it: .mha, .mhd with .raw, .zraw or slice files, every integer type") {
  const Volume v = rotated(kIntegerTypes[3]);
  SECTION(".mhd + .raw, .mhd + .zraw (ITK's writer, VTK's frog), .mha compressed") {
    write_metaimage(in_scratch("raw.mhd"), v, {"raw.raw"});
    reads_as(in_scratch("raw.mhd"), v);
    MetaOptions skip{"skip.raw"};
    skip.header_bytes = 100;
    write_metaimage(in_scratch("skip.mhd"), v, skip);
    reads_as(in_scratch("skip.mhd"), v);
    write_metaimage(in_scratch("itk.mhd"), v, {"itk.zraw", true});
    reads_as(in_scratch("itk.mhd"), v);
    MetaOptions vtk{"frog.zraw", true};
    vtk.vtk_style = true;
    write_metaimage(in_scratch("frog.mhd"), v, vtk);
    reads_as(in_scratch("frog.mhd"), v);
    write_metaimage(in_scratch("nosize.mhd"), v, {"nosize.zraw", true, false});
    reads_as(in_scratch("nosize.mhd"), v);
    write_metaimage(in_scratch("local.mha"), v, {"LOCAL", true});
    reads_as(in_scratch("local.mha"), v);
  }
  SECTION("a list of slice files and a %d pattern, raw and compressed") {
    for (bool compressed : {false, true}) {
      write_metaimage(in_scratch("list.mhd"), v, {"LIST", compressed});
      reads_as(in_scratch("list.mhd"), v);
      write_metaimage(in_scratch("pattern.mhd"), v, {"slice%03d.dat", compressed});
      reads_as(in_scratch("pattern.mhd"), v);
    }
  }
  SECTION("8, 16 and 32 bits, signed and unsigned, both byte orders") {
    for (const VoxelType& t : kIntegerTypes)
      for (bool big : {false, true}) {
        MetaOptions o{"LOCAL"};
        o.big_endian = big;
        o.vtk_style = big;
        write_metaimage(in_scratch("t.mha"), rotated(t), o);
        reads_as(in_scratch("t.mha"), rotated(t));
        o.data = "t.zraw";
        o.compressed = true;
        write_metaimage(in_scratch("t.mhd"), rotated(t), o);
        reads_as(in_scratch("t.mhd"), rotated(t));
      }
  }
}

TEST_CASE("NRRD as teem and 3D Slicer write it: detached .nhdr + .raw.gz, axes permuted, RAS, every integer type") {
  SECTION(".nhdr + .raw.gz and .nhdr + .raw") {
    const Volume v = rotated(kIntegerTypes[2]);
    NrrdOptions gz{"d.raw.gz", true};
    write_nrrd(in_scratch("d.nhdr"), v, gz);
    reads_as(in_scratch("d.nhdr"), v);
    write_nrrd(in_scratch("r.nhdr"), v, {"r.raw"});
    reads_as(in_scratch("r.nhdr"), v);
  }
  SECTION("axes permuted and flipped by the space directions; a RAS space") {
    Volume v = volume_of(kIntegerTypes[0]);
    v.direction = permuted_axes();
    write_nrrd(in_scratch("p.nrrd"), v, {});
    reads_as(in_scratch("p.nrrd"), v);
    NrrdOptions ras;
    ras.ras = true;
    write_nrrd(in_scratch("ras.nrrd"), rotated(kIntegerTypes[0]), ras);
    reads_as(in_scratch("ras.nrrd"), rotated(kIntegerTypes[0]));
  }
  SECTION("8, 16 and 32 bits, signed and unsigned, both byte orders, raw and gzip") {
    for (const VoxelType& t : kIntegerTypes)
      for (bool big : {false, true}) {
        NrrdOptions o;
        o.big_endian = big;
        o.gzip = big;
        write_nrrd(in_scratch("t.nrrd"), rotated(t), o);
        reads_as(in_scratch("t.nrrd"), rotated(t));
      }
  }
}

TEST_CASE("NIfTI as niftilib and nibabel write it: sform, qform only, rotated, .nii and .nii.gz, every integer type") {
  const double tol = 1e-5;  // the header holds float32
  SECTION("sform only, qform only (an improper rotation: qfac -1), both") {
    const Volume v = rotated(kIntegerTypes[3]);
    write_nifti(in_scratch("s.nii"), v, {true, false});
    reads_as(in_scratch("s.nii"), v, tol);
    Volume flipped = v;
    for (int r = 0; r < 3; ++r) flipped.direction[std::size_t(3 * r + 2)] *= -1;
    write_nifti(in_scratch("q.nii"), flipped, {false, true});
    reads_as(in_scratch("q.nii"), flipped, tol);
    write_nifti(in_scratch("qs.nii.gz"), v, {true, true, false, true});
    reads_as(in_scratch("qs.nii.gz"), v, tol);
  }
  SECTION("as nibabel writes it (scaling NaN, an aligned sform); 3D data with dim[0] 4 and one time point") {
    const Volume v = rotated(kIntegerTypes[3]);
    NiftiOptions nib{true, false};
    nib.nibabel = true;
    write_nifti(in_scratch("nib.nii.gz"), v, nib);
    reads_as(in_scratch("nib.nii.gz"), v, tol);
    NiftiOptions t;
    t.time_axis = true;
    write_nifti(in_scratch("t4.nii"), v, t);
    reads_as(in_scratch("t4.nii"), v, tol);
  }
  SECTION("a .nii.gz beside a .nii of the same name (niftilib would take the .nii's voxels)") {
    const Volume gz = rotated(kIntegerTypes[2]);
    Volume other = gz;
    for (long long& x : other.values) x = 65535 - x;
    write_nifti(in_scratch("both.nii"), other, {});
    write_nifti(in_scratch("both.nii.gz"), gz, {true, true, true, true});
    reads_as(in_scratch("both.nii.gz"), gz, tol);
    reads_as(in_scratch("both.nii"), other, tol);
  }
  SECTION("8, 16 and 32 bits, signed and unsigned, both byte orders, .nii and .nii.gz") {
    for (const VoxelType& t : kIntegerTypes)
      for (bool big : {false, true})
        for (bool gz : {false, true}) {
          const std::string name = in_scratch(gz ? "t.nii.gz" : "t.nii");
          write_nifti(name, rotated(t), {true, true, big, gz});
          reads_as(name, rotated(t), tol);
        }
  }
}

// The data-file check keeps what the header check was for: a header that
// declares more than its data holds is refused before MetaIO allocates it.
TEST_CASE("MetaImage headers that declare more than their data files hold are refused") {
  const Volume v = rotated(kIntegerTypes[3]);
  auto refused = [&](const std::string& header, const std::string& what) {
    INFO(header);
    CHECK_THROWS_WITH(read_labels(in_scratch(header)), Catch::Contains(what));
  };
  auto rewrite = [&](const std::string& header, const std::string& from, const std::string& to) {
    std::ifstream in(in_scratch(header), std::ios::binary);
    std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    const std::size_t at = text.find(from);
    REQUIRE(at != std::string::npos);
    write_bytes(in_scratch(header), text.replace(at, from.size(), to));
  };
  write_metaimage(in_scratch("lie.mhd"), v, {"lie.zraw", true});
  const std::string size = "CompressedDataSize = " + std::to_string(std::filesystem::file_size(in_scratch("lie.zraw")));
  rewrite("lie.mhd", size, size + "1");
  refused("lie.mhd", "CompressedDataSize (");
  rewrite("lie.mhd", size + "1", "CompressedDataSize = -4");
  refused("lie.mhd", "CompressedDataSize is not a size");
  write_metaimage(in_scratch("lie.mha"), v, {"LOCAL", true});
  rewrite("lie.mha", "CompressedDataSize = ", "CompressedDataSize = 1000000000000");
  refused("lie.mha", "is more than the file holds");
  write_metaimage(in_scratch("short.mhd"), v, {"short.raw"});
  std::filesystem::resize_file(in_scratch("short.raw"), 100);
  refused("short.mhd", "'short.raw' holds 100 bytes, the header declares 2002");
}
