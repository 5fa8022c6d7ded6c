// A foreground held as the runs of its rows: what img2wc --label keeps of
// a scan read a z-slice at a time, so that a label costs its own voxels'
// rows and one pass over the scan's values, never a grid of the scan.
#pragma once
#include "image/grid.hpp"

#include <cstddef>
#include <cstdint>
#include <vector>

namespace imgmesh {

class ForegroundRuns {
public:
  ForegroundRuns() = default;
  // streamed: read by VoxelStream (not ITK's reader), for the tests.
  ForegroundRuns(const Geometry& scan, bool streamed) : geometry_(scan), streamed_(streamed) {}
  // The runs of a dense foreground (ITK's readers' path).
  explicit ForegroundRuns(const BinaryImage& image);

  const Geometry& geometry() const { return geometry_; }
  // The foreground's box, inclusive corners (lo > hi: empty), and voxels.
  const Index3& lo() const { return lo_; }
  const Index3& hi() const { return hi_; }
  std::size_t count() const { return count_; }
  bool streamed() const { return streamed_; }
  // Fills out[0 .. n) with the foreground (0/1) of row (y, z) from x0.
  void row(std::size_t y, std::size_t z, std::size_t x0, std::size_t n, std::uint8_t* out) const;
  // The dense image (2D scans, which are not cropped).
  BinaryImage image() const;

  // Appends the run [x0, x1) of row (y, z): rows in order (z, then y),
  // runs of a row in order, apart.
  void add(std::size_t y, std::size_t z, std::size_t x0, std::size_t x1);

private:
  struct Row {
    std::uint32_t y, z;
    std::size_t first;  // its first run
  };
  Geometry geometry_;
  Index3 lo_{0, 0, 0}, hi_{-1, -1, -1};
  std::size_t count_ = 0;
  bool streamed_ = false;
  std::vector<Row> rows_;
  std::vector<std::array<std::uint32_t, 2>> runs_;
};

// Which values a stream's voxels are compared with, and which were seen.
struct LabelMatch {
  std::vector<long long> labels;  // sorted, distinct
  std::vector<char> seen;         // per label
};

class VoxelStream;
enum class IntegerType { u8, i8, u16, i16, u32, i32 };

// The runs of the voxels of `scan` whose value (of `type`, read from `in`
// a z-slice at a time) is one of match.labels; marks match.seen.
ForegroundRuns label_runs(const Geometry& scan, VoxelStream& in, IntegerType type, LabelMatch& match);

} // namespace imgmesh
