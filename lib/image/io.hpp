// Image I/O through ITK (NRRD .nrrd/.nhdr, MetaImage .mha/.mhd, NIfTI
// .nii/.nii.gz, PNG for 2D), the only place ITK is included. "-" reads stdin
// (spooled to a temporary file, format sniffed from the content) and writes
// NRRD to stdout. Writers go through AtomicOutput: no partial files.
#pragma once
#include "image/foreground_runs.hpp"
#include "image/grid.hpp"
#include "image/slicer_segmentation.hpp"

#include <map>
#include <string>
#include <vector>

namespace imgmesh {

// Which voxels are foreground (doc/design.md "Data contracts"): nonzero by default, the union of
// `labels` if any, or value >= threshold.
struct Selection {
  std::vector<long long> labels;
  bool has_threshold = false;
  double threshold = 0;
};

// What a file holds, without reading the voxels.
struct ImageInfo {
  Geometry geometry;
  std::string component;  // "uint8", "int16", "float", ... (ITK's name)
  bool integer = true;    // integer component type
  int components = 1;     // pixel components (1 for scalar images)
};

// Read the header. Throws Error (unreadable, 1D, 4D, vector pixels...).
ImageInfo read_image_info(const std::string& path);

// Read a scalar 2D/3D image and select its foreground (0/1). Throws Error on
// a label absent from the image, --label on a non-integer image, an empty
// foreground, NaNs, or any unreadable input. fields: its NRRD key/value
// fields ("key:=value"; none in other formats).
BinaryImage read_foreground(const std::string& path, const Selection& sel,
                            std::map<std::string, std::string>* fields = nullptr);
// The same voxels, geometry and errors for a selection of labels, held as
// runs (img2wc --label: the scan's values are read once and not kept). A
// file of a plain layout (voxel_stream.hpp: NRRD, NIfTI-1, MetaImage, raw
// or compressed) is streamed without ITK's reader, its header still read
// by ITK; any other file goes through read_foreground (streamed() false).
ForegroundRuns read_foreground_runs(const std::string& path, const Selection& sel);

// Read an integer label image (2D or 3D) and, when `names` is given, the
// names its file gives its labels (3D Slicer's segment names, empty when
// none). Throws Error on non-integer values. Every reader refuses a 3D
// Slicer segmentation of several layers (overlapping segments) or of a
// fractional labelmap (slicer_segmentation.hpp).
LabelImage read_labels(const std::string& path, LabelNames* names = nullptr);
// A label image held in the narrowest of uint8, uint16 and int32 that its
// values fit: one of u8, u16, i32 holds the voxels (bytes: 1, 2 or 4).
// seg2mesh holds its input throughout: a CT's labels take 1 or 2 bytes a
// voxel, not 4.
struct NarrowLabelImage {
  Image<std::uint8_t> u8;
  Image<std::uint16_t> u16;
  LabelImage i32;
  int bytes = 4;
  const Geometry& geometry() const { return bytes == 1 ? u8.geometry() : bytes == 2 ? u16.geometry() : i32.geometry(); }
  // f(the image that holds the voxels); f returns the same type for each.
  template <class F> auto visit(F&& f) const { return bytes == 1 ? f(u8) : bytes == 2 ? f(u16) : f(i32); }
  template <class F> auto visit(F&& f) { return bytes == 1 ? f(u8) : bytes == 2 ? f(u16) : f(i32); }
  // The label at a possibly outside index (outside: 0).
  std::int32_t at(std::ptrdiff_t x, std::ptrdiff_t y, std::ptrdiff_t z) const {
    return bytes == 1 ? u8.at(x, y, z) : bytes == 2 ? u16.at(x, y, z) : i32.at(x, y, z);
  }
};
// read_labels' values (and its errors), so held.
NarrowLabelImage read_labels_narrow(const std::string& path, LabelNames* names = nullptr);

// The same with a selection: a threshold gives the 0/1 foreground (as
// read_foreground); labels keep those labels and make every other value 0
// (Error when one does not occur); neither keeps every value. `info`, when
// given, gets the file's header (its component type: what a label image
// written back keeps; unsigned_char with a threshold).
LabelImage read_labels(const std::string& path, const Selection& sel, ImageInfo* info = nullptr);

// Read a float image and its NRRD key/value fields ("key:=value").
FloatImage read_float(const std::string& path, std::map<std::string, std::string>* fields = nullptr);

// Write; the format comes from the extension ("-": NRRD on stdout).
// 2D images (dimension == 2) are written as 2D images.
void write_image(const std::string& path, const BinaryImage& img, const std::map<std::string, std::string>& fields = {});
void write_image(const std::string& path, const FloatImage& img,
                 const std::map<std::string, std::string>& fields = {});
// A label image in the component type `component` (ImageInfo::component of
// the file it came from; its values must fit it).
void write_image(const std::string& path, const LabelImage& img, const std::string& component,
                 const std::map<std::string, std::string>& fields = {});

} // namespace imgmesh
