// The samples of g at the voxel centres of a 3D grid. With a clamp T the
// grid holds g' = max(-T, min(g, T)); without one (T infinite) g' = g. Why
// f' (chapter 6's f built on g') serves the meshers as well as f:
// PartitionOfUnity::clamp_for.
//
// Storage: a dense array, or blocks of 4 x 4 x 4 (x fastest inside a block)
// where a block whose samples all clamp is not stored but reads from one
// shared block of -T or +T (all its samples have one sign: two neighbouring
// samples of opposite signs lie within a voxel of the boundary, so under T).
// Blocks cost each evaluation of f about 7% more instructions (bunny,
// callgrind), so by default they are used only where they save at least
// kBlocksWorth bytes. The blocks' samples are then held as 16-bit codes
// into a palette of their distinct values when there are at most kCodes of
// them, as there are in a distance map (sums of squared multiples of the
// spacing: 272 values on a CT's liver): the same floats in half the
// memory, which the meshers hold through their peak. Plain data, no ITK.
//
// The samples may come streamed, a z-slice at a time (the implicit function
// file as it is read: never the dense grid when blocks are used), and may
// cover only a box of the grid (a crop placed in the scan it was cut from):
// every sample outside that box then reads +T.
#pragma once
#include "image/grid.hpp"
#include "util/zeroed.hpp"

#include <algorithm>
#include <cstdint>
#include <functional>
#include <limits>
#include <vector>

namespace imgmesh {

class SampleGrid : public Geometry {
public:
  static constexpr int kShift = 2;
  static constexpr long kB = 1L << kShift, kMask = kB - 1;  // block side
  static constexpr long kBlockSamples = kB * kB * kB;
  static constexpr std::size_t kBlocksWorth = std::size_t(32) << 20;
  static constexpr std::size_t kCodes = std::size_t(1) << 16;
  enum class Storage { automatic, dense, blocks };

  // Fills `slice` with the next z-slice of the samples given (x fastest, then y).
  using SliceReader = std::function<void(float* slice)>;

  SampleGrid() = default;
  // From the dense samples (3D, or an empty grid; freed once held). clamp > 0.
  explicit SampleGrid(FloatImage g, float clamp = std::numeric_limits<float>::infinity(),
                      Storage storage = Storage::automatic);
  // Streamed: the samples of the box of `box_size` voxels from index `lo` of
  // `grid`, its z-slices in order from next_slice (box_size[0] box_size[1]
  // samples each), clamped as they come; every sample of the grid outside
  // the box reads +clamp (the caller knows that g >= clamp there; clamp
  // finite unless the box is the whole grid). clamp > 0.
  SampleGrid(const Geometry& grid, const Index3& lo, const std::array<std::size_t, 3>& box_size, float clamp,
             Storage storage, const SliceReader& next_slice);

  // Fills `band` with the box's samples of x in [x0, x1) (box indices), x
  // fastest, then y, then z.
  using BandReader = std::function<void(std::size_t x0, std::size_t x1, float* band)>;
  // The same samples a band of x at a time (x0 from 0 up, bands of whole
  // blocks but at the box's sides, about kBandBytes each): what a producer
  // that cannot give z-slices (a distance transform, whose last pass runs
  // along z) gives without the dense box. The same grid as from slices,
  // its blocks in the same order. band_bytes: the bands' size (tests: many
  // bands on a small grid).
  static constexpr std::size_t kBandBytes = std::size_t(8) << 20;
  SampleGrid(const Geometry& grid, const Index3& lo, const std::array<std::size_t, 3>& box_size, float clamp,
             Storage storage, const BandReader& next_band, std::size_t band_bytes = kBandBytes);

  float operator()(std::size_t x, std::size_t y, std::size_t z) const {
    if (dense()) return dense_[std::size_t(long(x) + s1_ * long(y) + s2_ * long(z))];
    return sample(slot(table_index(long(x) >> kShift, long(y) >> kShift, long(z) >> kShift)) +
                  std::size_t(local(long(x), long(y), long(z))));
  }
  bool dense() const { return !dense_.empty(); }
  // Blocks of codes into palette() (else blocks of floats).
  bool coded() const { return !codes_.empty(); }
  // Dense storage: the samples, x fastest.
  const float* dense_data() const { return dense_.data(); }
  // Blocks: the table holds the blocks the box meets and a layer of +T
  // blocks around them (not the grid's: 4 bytes a block of the scan, per
  // label, were most of seg2mesh --conforming's labelling function), nb(a)
  // along axis a. Grid block b along axis a is table block table_block(a,
  // b); one beyond the layer reads as the layer (+T, as every block
  // outside the box).
  long nb(int axis) const { return nb_[axis]; }
  long table_block(int axis, long b) const { return std::clamp(b - first_block_[axis], 0L, nb_[axis] - 1); }
  // The table's number of grid block (bx, by, bz).
  long table_index(long bx, long by, long bz) const {
    return table_block(0, bx) + nb_[0] * (table_block(1, by) + nb_[1] * table_block(2, bz));
  }
  // Blocks of floats: table block number bx + nb(0) (by + nb(1) bz)'s first
  // sample; sample (x, y, z) of the grid is at local(x, y, z) in its block.
  const float* block_at(long b) const { return pool_.data() + slot(b); }
  // Blocks of codes: the same, its sample the palette's value at the code.
  const std::uint16_t* code_block_at(long b) const { return codes_.data() + slot(b); }
  const float* palette() const { return palette_.data(); }
  // Grid block (bx, by, bz) holds only +clamp (1) or only -clamp (-1): the
  // shared constant blocks; 0 where it holds samples of its own, or dense.
  int constant_block(long bx, long by, long bz) const {
    if (dense()) return 0;
    const std::uint32_t t = table_[std::size_t(table_index(bx, by, bz))];
    return t == 0 ? 1 : t == 1 ? -1 : 0;
  }
  static long local(long x, long y, long z) { return (x & kMask) + kB * ((y & kMask) + kB * (z & kMask)); }
  // The samples at the 8 corners of the cube with lowest corner (x, y, z),
  // corner m at (x + (m & 1), y + (m >> 1 & 1), z + (m >> 2 & 1)).
  void cube(long x, long y, long z, double c[8]) const {
    if (dense()) {
      const float* b = dense_.data() + x + s1_ * y + s2_ * z;
      for (int m = 0; m < 8; ++m) c[m] = b[(m & 1) + s1_ * ((m >> 1) & 1) + s2_ * ((m >> 2) & 1)];
      return;
    }
    if ((x & kMask) < kMask && (y & kMask) < kMask && (z & kMask) < kMask) {
      const std::size_t b = slot(table_index(x >> kShift, y >> kShift, z >> kShift)) +
                            std::size_t(local(x, y, z));
      for (int m = 0; m < 8; ++m) c[m] = sample(b + std::size_t((m & 1) + kB * ((m >> 1) & 1) + kB * kB * ((m >> 2) & 1)));
      return;
    }
    // Across blocks: per axis the two samples' block offsets and local parts.
    const long o[3][2] = {{table_block(0, x >> kShift), table_block(0, (x + 1) >> kShift)},
                          {nb_[0] * table_block(1, y >> kShift), nb_[0] * table_block(1, (y + 1) >> kShift)},
                          {nb_[0] * nb_[1] * table_block(2, z >> kShift), nb_[0] * nb_[1] * table_block(2, (z + 1) >> kShift)}};
    const long l[3][2] = {{x & kMask, (x + 1) & kMask},
                          {kB * (y & kMask), kB * ((y + 1) & kMask)},
                          {kB * kB * (z & kMask), kB * kB * ((z + 1) & kMask)}};
    for (int m = 0; m < 8; ++m) {
      const int a = m & 1, b = (m >> 1) & 1, d = (m >> 2) & 1;
      c[m] = sample(slot(o[0][a] + o[1][b] + o[2][d]) + std::size_t(l[0][a] + l[1][b] + l[2][d]));
    }
  }

  const Geometry& geometry() const { return *this; }
  float clamp() const { return clamp_; }
  // The box whose samples were given, inclusive corners: every sample
  // outside it reads +clamp (loops over the grid may stop at it).
  const Index3& box_lo() const { return box_lo_; }
  const Index3& box_hi() const { return box_hi_; }
  // Blocks: how many the box meets, how many stored (dense: 0 and 0).
  std::size_t blocks() const {
    return table_.empty() ? 0 : std::size_t((nb_[0] - 2) * (nb_[1] - 2) * (nb_[2] - 2));
  }
  std::size_t stored_blocks() const {
    const std::size_t n = coded() ? codes_.size() : pool_.size();
    return n == 0 ? 0 : n / kBlockSamples - 2;
  }
  // Every sample finite (with T infinite: g's own samples).
  bool finite() const;
  // The samples as a dense image (g', for writing and tests).
  FloatImage to_image() const;

private:
  std::vector<float> dense_;
  long s1_ = 0, s2_ = 0;  // dense strides along y and z
  // Blocks 0 and 1: the constant +T and -T blocks; then the stored ones.
  // The table's zeros (+T: every block outside the box) cost no memset.
  std::vector<float> pool_;
  // Coded blocks: pool_'s samples as codes into palette_ (pool_ then empty).
  std::vector<std::uint16_t> codes_;
  std::vector<float> palette_;
  ZeroedVector<std::uint32_t> table_;
  long nb_[3] = {0, 0, 0};           // the table's blocks along each axis
  long first_block_[3] = {0, 0, 0};  // the grid block of its first (a +T block before the box's)
  float clamp_ = std::numeric_limits<float>::infinity();
  Index3 box_lo_{0, 0, 0}, box_hi_{-1, -1, -1};

  // given: the dense samples of the whole grid, taken (not copied) when dense.
  SampleGrid(const Geometry& grid, const Index3& lo, const std::array<std::size_t, 3>& box_size, float clamp,
             Storage storage, const SliceReader& next_slice, std::vector<float>* given);
  void stream_dense(const std::array<std::size_t, 3>& box_size, const SliceReader& next_slice, std::vector<float>* given);
  // The box checked and held, the block counts set.
  void set_box(const Index3& lo, const std::array<std::size_t, 3>& box_size);
  bool dense_chosen(Storage storage) const;
  void stream_blocks(const std::array<std::size_t, 3>& box_size, const SliceReader& next_slice);
  void band_dense(const std::array<std::size_t, 3>& box_size, const BandReader& next_band, std::size_t band_bytes);
  void band_blocks(const std::array<std::size_t, 3>& box_size, const BandReader& next_band, std::size_t band_bytes);
  // Blocks: the table, the two constant blocks, room for every block the box meets.
  void start_blocks();
  // The blocks meeting the sub-box [c0, c1] of the box (grid indices; whole
  // blocks but at the box's sides), its samples in chunk (x fastest).
  void add_blocks(const long c0[3], const long c1[3], const float* chunk);
  // The stored blocks put in the order of their numbers.
  void sort_pool();
  // The pool as codes when its samples take at most kCodes values.
  void code_pool();
  // Blocks: the first sample of block b in pool_ or codes_, and sample i there.
  std::size_t slot(long b) const { return std::size_t(table_[std::size_t(b)]) * kBlockSamples; }
  float sample(std::size_t i) const { return coded() ? palette_[codes_[i]] : pool_[i]; }
  void after_blocks(Storage storage);
  void blocks_to_dense();
};

} // namespace imgmesh
