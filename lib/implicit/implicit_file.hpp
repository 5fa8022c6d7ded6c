// The implicit function file of doc/design.md and its construction from a
// well-composed image (thesis 6.3): a float NRRD of g at the voxel centres
// (negative inside, physical units, world geometry of the image) with the
// key/value fields imgmesh_kind:=pu-implicit, imgmesh_version:=1 and
// imgmesh_d:=d_0 d_1 d_2. Everything needed to evaluate f travels in it.
#pragma once
#include "image/grid.hpp"
#include "implicit/crop.hpp"
#include "implicit/partition_of_unity.hpp"
#include "util/json.hpp"

#include <array>
#include <cstddef>
#include <functional>
#include <limits>
#include <string>

namespace imgmesh {

// g at the voxel centres: the exact Euclidean distance (physical units, per
// axis spacing) from each centre to the voxel-FACE boundary bdCA(X), negative
// inside. Voxels outside the grid count as background. Linear time (separable
// lower-envelope passes, see distance.cpp). Throws Error on an empty
// foreground or a grid that is not 3D.
FloatImage signed_distance_to_boundary(const BinaryImage& wc, unsigned threads = 1);
// The same values, to the last bit, for the voxels of x in [x0, x1) only,
// into band (x fastest, then y, then z; (x1 - x0) size[1] size[2] floats):
// g a band at a time, never the dense grid (seg2mesh's crops).
void signed_distance_band(const BinaryImage& wc, std::size_t x0, std::size_t x1, float* band, unsigned threads = 1);

// What implicit_from_well_composed did, and what f it made.
struct ImplicitReport {
  std::array<std::size_t, 3> input_size{0, 0, 0}, size{0, 0, 0};  // of wc, of g (padded)
  std::array<std::size_t, 3> padded_before{0, 0, 0}, padded_after{0, 0, 0};
  Vec3 spacing{0, 0, 0}, d{0, 0, 0};
  std::size_t foreground = 0;
  double g_min = 0, l_max = 0;
  unsigned threads = 1;
  double distance_seconds = 0, weights_seconds = 0;
  double construction_seconds = 0, construction_cpu_seconds = 0;  // the whole call
  // wc2implicit's --stats; the guarantees hold by construction (the input
  // was checked; f = g at every centre, |g| >= g_min > 0; PartitionOfUnity
  // refuses a larger d).
  Json to_json() const;
  std::string failed_guarantee() const { return ""; }
};

// The whole construction of chapter 6 on a well-composed image (Error when
// it is not, or not 3D). Where the foreground touches the border of the
// grid, the grid grows by one background voxel on that side (thesis 6.3,
// restriction (2): bdCA(X) must lie inside conv(D) for f^-1(0) to be closed);
// world coordinates of the voxels stay exact.
PartitionOfUnity implicit_from_well_composed(const BinaryImage& wc, ImplicitReport* report = nullptr,
                                             unsigned threads = 1);

// What seg2mesh meshes of a label's crop: implicit_from_well_composed(wc)
// then function_in_scan(it, frame grown as wc2implicit grows the grid,
// clamp), the same f to the last bit, built from g a band of x at a time
// (signed_distance_band): never the dense float grid of the crop. frame:
// the crop's (well_composed_crop's, its foreground box wc's), or none.
// band_bytes: SampleGrid's.
// storage: SampleGrid's (automatic keeps a scan under 32 MB dense: a map's
// many labels each want blocks, the labelling function's).
PartitionOfUnity implicit_in_scan(const BinaryImage& wc, ScanFrame frame, float clamp, unsigned threads = 1,
                                  bool* placed = nullptr, std::size_t band_bytes = SampleGrid::kBandBytes,
                                  SampleGrid::Storage storage = SampleGrid::Storage::automatic);

// The file's fields imgmesh_kind and imgmesh_version; imgmesh_clamp:=T
// (optional) says that its samples are g clamped to [-T, T].
inline constexpr const char* kImplicitKind = "pu-implicit";
inline constexpr const char* kImplicitVersion = "1";

// Written through ITK (implicit_write.cpp, library imgmesh_implicit_write);
// read without it (image/nrrd_float.hpp), so that the meshers load no ITK.
// A crop's file carries its scan frame (crop.hpp). clamp: the samples are
// written clamped to [-clamp, clamp] (wc2implicit: covered_clamp, a narrow
// band that gzip shrinks to almost nothing beyond), with imgmesh_clamp;
// infinite: as f holds them.
void write_implicit(const std::string& path, const PartitionOfUnity& f, const ScanFrame& frame = {},
                    float clamp = std::numeric_limits<float>::infinity());
// Rejects anything that is not a pu-implicit file of a known version with a
// clear Error (wrong kind, missing or bad d, zero or NaN samples, 2D...).
// clamp: given the file's grid, the clamp of g's samples (the meshers:
// PartitionOfUnity::clamp_for); none: f itself. A file clamped at a smaller
// T (imgmesh_clamp) gives f on samples clamped there: f.samples().clamp()
// says which. The samples are read as
// they stream (gzip too), into f's blocks: never the dense grid unless f
// keeps it. A crop's f with a clamp is placed back in its scan's grid when
// its margin allows (function_in_scan): *frame is the file's, *placed says
// whether it was.
PartitionOfUnity read_implicit(const std::string& path, const std::function<float(const Geometry&)>& clamp = {},
                               ScanFrame* frame = nullptr, bool* placed = nullptr);

} // namespace imgmesh
