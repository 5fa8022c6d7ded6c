// A foreground cut to its box plus a margin (img2wc --label, seg2mesh): the
// cost of a label is that of its box, not of the scan, and the meshes are
// those of the scan's whole grid.
//
// The margin (crop_margin) is background enough that nothing downstream sees
// the cut: the repair of chapter 5 changes the same voxels (it only ever
// acts next to the foreground); g, the distance to bdCA(X), is the same at
// every voxel centre of the crop (distance.cpp computes it the same to the
// last bit wherever a line starts); d depends only on the cells of the
// foreground's box grown by a few voxels (PartitionOfUnity::weight_constant),
// all inside; and
// every sample of the scan beyond the crop has g >= T, the clamp of the
// meshers' samples (PartitionOfUnity::clamp_for), so that the meshers, with
// the crop placed back in the scan's grid (ScanFrame), hold the very samples
// the scan's whole grid gives them and compute in the scan's frame: the
// same mesh, bit for bit.
#pragma once
#include "image/grid.hpp"
#include "implicit/partition_of_unity.hpp"
#include "wellcomposed/well_composed.hpp"

#include <array>
#include <cstdint>
#include <functional>
#include <map>
#include <string>

namespace imgmesh {

// A box of voxels, inclusive corners; empty when lo > hi on an axis.
struct VoxelBox {
  Index3 lo{0, 0, 0}, hi{-1, -1, -1};
  bool empty() const { return hi[0] < lo[0] || hi[1] < lo[1] || hi[2] < lo[2]; }
  void add(std::ptrdiff_t x, std::ptrdiff_t y, std::ptrdiff_t z);
  std::array<std::size_t, 3> size() const;
};

// The foreground's (nonzero voxels') box.
VoxelBox foreground_box(const BinaryImage& image);

// Where a crop lies in the grid of the scan it was cut from: that grid as
// img2wc --full-grid writes it (the scan grown by one background voxel
// where the foreground touches its border). Travels in NRRD key/value
// fields (imgmesh_scan_size, imgmesh_scan_index, imgmesh_scan_origin, the
// origin to the last bit, and imgmesh_foreground_box) from img2wc through
// wc2implicit to the meshers.
struct ScanFrame {
  std::array<std::size_t, 3> size{0, 0, 0};
  Index3 index{0, 0, 0};  // the crop's voxel (0, 0, 0) in the scan's grid
  Vec3 origin{0, 0, 0};
  VoxelBox foreground;    // the foreground's box in the crop (imgmesh_foreground_box)
  bool present() const { return size[0] != 0; }
  // The scan's grid: crop's spacing and direction, this size and origin.
  Geometry scan(const Geometry& crop) const;
  std::map<std::string, std::string> keys() const;
  // From a file's key/value fields; none of them: not present. Throws Error
  // naming path when they are malformed or do not place `crop` inside the
  // scan where its own origin says (1e-6 of a voxel).
  static ScanFrame from_keys(const std::map<std::string, std::string>& keys, const Geometry& crop,
                             const std::string& path);
  // After wc2implicit grew the crop by before/after voxels (its foreground
  // touching those sides): the scan's grid grows the same where the crop's
  // side is the scan's, as wc2implicit grows the whole grid (the origin
  // moved by the same arithmetic); false when a grown side lies inside the
  // scan (the frame then no longer holds).
  bool grow(const std::array<std::size_t, 3>& before, const std::array<std::size_t, 3>& after,
            const Geometry& crop_before);
};

// The meshers' --max-distance that the project's files serve exactly, in
// units of the smallest voxel spacing (the meshers' defaults are 0.3 and
// 0.4): the crops of img2wc and seg2mesh keep background out to its clamp,
// and wc2implicit clamps g's samples to it.
inline constexpr double kCoveredMaxDistance = 0.5;
// That clamp, PartitionOfUnity::clamp_for at kCoveredMaxDistance: a narrow
// band around S, as level-set tools keep one (OpenVDB's background value).
// A mesher with a larger --max-distance meshes f on samples clamped here:
// the same S and the same signs, only its |f| <= 2 E test answers on them.
float covered_clamp(const Geometry& grid);

// Per axis, the background voxels a crop keeps beyond the foreground's box
// for samples clamped at T: every voxel centre beyond is at least T from
// bdCA(X) (m + 1/2 voxels from the foreground's voxels), and the cells that
// L_max is taken over lie inside (PartitionOfUnity::weight_margin).
std::array<std::size_t, 3> crop_margin(const Vec3& spacing, double clamp);
// The margin of img2wc's and seg2mesh's crops: crop_margin at covered_clamp.
std::array<std::size_t, 3> crop_margin(const Geometry& grid);

// Fills out[0 .. n) with the foreground (0/1) of the scan's row (y, z), x
// from x0 (all inside the scan).
using ForegroundRows =
    std::function<void(std::size_t y, std::size_t z, std::size_t x0, std::size_t n, std::uint8_t* out)>;

struct WellComposedCrop {
  WellComposedResult result;  // image: the crop; padded_*: where the scan's grid grew
  ScanFrame frame;
};

// make_well_composed on the scan's foreground (box: its box, not empty; a
// 3D scan), done on the box plus the margin (and room for the repair, grown
// until it holds all the repair set): the same voxels as on the whole grid.
// The result's image is the foreground's box after the repair plus
// crop_margin(scan), within the scan's grid.
WellComposedCrop well_composed_crop(const Geometry& scan, const VoxelBox& box, const ForegroundRows& rows,
                                    const WellComposedOptions& options);

// Whether function_in_scan places a crop of this grid (after wc2implicit's
// growth) in its frame's scan at clamp T (see there).
bool placed_in_scan(const Geometry& crop, const ScanFrame& frame, float clamp);

// f on g's samples clamped at T (infinite: not clamped), placed back in the
// scan's grid when the frame is present, the scan has at most 2^31 voxels
// and the frame's foreground box keeps crop_margin(spacing, T) from every
// side of the crop inside the scan (the scan's samples then, only the
// crop's stored: *placed = true); else on the crop's own grid. The samples come a z-slice of the crop at a time (see
// PartitionOfUnity::streamed; d as there); Error when a negative one lies
// outside the frame's foreground box.
PartitionOfUnity function_in_scan(const Geometry& crop, const ScanFrame& frame, Vec3 d, float clamp,
                                  const SampleGrid::SliceReader& next_slice, bool* placed = nullptr);

} // namespace imgmesh
