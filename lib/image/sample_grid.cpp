#include "image/sample_grid.hpp"
#include "util/error.hpp"

#include <algorithm>
#include <cmath>
#include <new>
#include <utility>

#if defined(__linux__)
#include <sys/mman.h>
#endif

namespace imgmesh {

namespace {

// Random evaluations touch the samples all over; with 4 KiB pages nearly
// every one misses the TLB. Let the kernel back a large pool with
// transparent huge pages (a hint; no effect elsewhere). Call before the
// pages are first written.
void prefer_huge_pages(std::vector<float>& pool) {
#if defined(__linux__) && defined(MADV_HUGEPAGE)
  const std::size_t bytes = pool.capacity() * sizeof(float);
  if (bytes < (std::size_t(8) << 20)) return;
  const std::uintptr_t huge = std::uintptr_t(2) << 20;
  const std::uintptr_t begin = (reinterpret_cast<std::uintptr_t>(pool.data()) + huge - 1) & ~(huge - 1);
  const std::uintptr_t end = (reinterpret_cast<std::uintptr_t>(pool.data()) + bytes) & ~(huge - 1);
  if (end > begin) ::madvise(reinterpret_cast<void*>(begin), end - begin, MADV_HUGEPAGE);
#else
  (void)pool;
#endif
}

} // namespace

SampleGrid::SampleGrid(FloatImage g, float clamp, Storage storage)
    : SampleGrid(g.geometry(), {0, 0, 0}, g.size, clamp, storage, [&g, z = std::size_t(0)](float* slice) mutable {
        if (g.data.size() != g.count()) throw Error("internal: sample data does not match the grid size");
        const std::size_t n = g.size[0] * g.size[1];
        std::copy_n(g.data.data() + z++ * n, n, slice);
      }, &g.data) {}

SampleGrid::SampleGrid(const Geometry& grid, const Index3& lo, const std::array<std::size_t, 3>& box_size, float clamp,
                       Storage storage, const SliceReader& next_slice)
    : SampleGrid(grid, lo, box_size, clamp, storage, next_slice, nullptr) {}

SampleGrid::SampleGrid(const Geometry& grid, const Index3& lo, const std::array<std::size_t, 3>& box_size, float clamp,
                       Storage storage, const SliceReader& next_slice, std::vector<float>* given)
    : Geometry(grid), clamp_(clamp) {
  if (!(clamp > 0)) throw Error("internal: the samples' clamp must be positive");
  bool whole = true;
  for (int i = 0; i < 3; ++i) {
    if (lo[i] < 0 || box_size[i] == 0 || std::size_t(lo[i]) + box_size[i] > size[i])
      throw Error("internal: the samples' box is not inside the grid");
    whole = whole && lo[i] == 0 && box_size[i] == size[i];
    box_lo_[i] = lo[i];
    box_hi_[i] = lo[i] + std::ptrdiff_t(box_size[i]) - 1;
    nb_[i] = (long(size[i]) + kB - 1) / kB;
  }
  if (!whole && !std::isfinite(clamp)) throw Error("internal: the samples outside the box need a finite clamp");
  s1_ = long(size[0]);
  s2_ = long(size[0]) * long(size[1]);
  if (std::size_t(nb_[0] * nb_[1] * nb_[2]) > (std::size_t(1) << 31)) throw Error("grid too large");
  // Unclamped samples all go in blocks: dense is smaller.
  const std::size_t dense_bytes = count() * sizeof(float);
  if (storage == Storage::dense ||
      (storage == Storage::automatic && (dense_bytes < kBlocksWorth || !std::isfinite(clamp)))) {
    stream_dense(box_size, next_slice, given);
    return;
  }
  stream_blocks(box_size, next_slice);
  const std::size_t block_bytes = (pool_.size() + table_.size()) * sizeof(float);
  if (storage == Storage::automatic && (dense_bytes < block_bytes || dense_bytes - block_bytes < kBlocksWorth))
    blocks_to_dense();
}

void SampleGrid::stream_dense(const std::array<std::size_t, 3>& box_size, const SliceReader& next_slice,
                              std::vector<float>* given) {
  auto clamped = [this](float v) { return v < -clamp_ ? -clamp_ : v > clamp_ ? clamp_ : v; };  // NaN kept
  if (given) {  // taken, not copied: two dense grids made seg2mesh's peak on a large label
    if (given->size() != count()) throw Error("internal: sample data does not match the grid size");
    dense_ = std::move(*given);
    std::transform(dense_.begin(), dense_.end(), dense_.begin(), clamped);
    return;
  }
  const std::size_t n = box_size[0] * box_size[1];
  dense_.reserve(count());
  prefer_huge_pages(dense_);
  if (box_size == size) {  // straight into place
    dense_.resize(count());
    for (std::size_t z = 0; z < size[2]; ++z) {
      float* slice = dense_.data() + z * n;
      next_slice(slice);
      std::transform(slice, slice + n, slice, clamped);
    }
    return;
  }
  dense_.assign(count(), clamp_);
  std::vector<float> slice(n);
  for (std::size_t z = 0; z < box_size[2]; ++z) {
    next_slice(slice.data());
    for (std::size_t y = 0; y < box_size[1]; ++y)
      std::transform(slice.data() + y * box_size[0], slice.data() + (y + 1) * box_size[0],
                     dense_.data() + index(std::size_t(box_lo_[0]), std::size_t(box_lo_[1]) + y, std::size_t(box_lo_[2]) + z),
                     clamped);
  }
}

// A layer of blocks (kB z-slices) at a time: which blocks clamp whole
// (kept as the sign of their samples), which are stored, appended in order.
void SampleGrid::stream_blocks(const std::array<std::size_t, 3>& box_size, const SliceReader& next_slice) {
  auto clamped = [this](float v) { return v < -clamp_ ? -clamp_ : v > clamp_ ? clamp_ : v; };  // NaN kept
  table_.assign(std::size_t(nb_[0] * nb_[1] * nb_[2]), 1);  // outside the box: +T
  long bl[3], bh[3];
  std::size_t bound = 2;
  for (int i = 0; i < 3; ++i) {
    bl[i] = long(box_lo_[i]) >> kShift;
    bh[i] = long(box_hi_[i]) >> kShift;
    bound *= std::size_t(bh[i] - bl[i] + 1);
  }
  // Room for every block the box meets: only the pages written take memory,
  // so the pool never moves (growing it would hold it twice).
  try {
    pool_.reserve(bound * kBlockSamples);
  } catch (const std::bad_alloc&) {
  }
  prefer_huge_pages(pool_);
  pool_.assign(2 * kBlockSamples, -clamp_);
  std::fill_n(pool_.begin() + kBlockSamples, kBlockSamples, clamp_);
  const std::size_t n = box_size[0] * box_size[1];
  std::vector<float> layer(n * std::size_t(std::min<long>(kB, long(box_size[2]))));
  const long lo[3] = {long(box_lo_[0]), long(box_lo_[1]), long(box_lo_[2])};
  const long hi[3] = {long(box_hi_[0]), long(box_hi_[1]), long(box_hi_[2])};
  for (long bz = bl[2]; bz <= bh[2]; ++bz) {
    const long z0 = std::max(bz * kB, lo[2]), z1 = std::min((bz + 1) * kB - 1, hi[2]);
    for (long z = z0; z <= z1; ++z) next_slice(layer.data() + std::size_t(z - z0) * n);
    auto at = [&](long x, long y, long z) {  // a sample of the layer's blocks
      if (x < lo[0] || x > hi[0] || y < lo[1] || y > hi[1] || z < z0 || z > z1) return clamp_;
      return layer[std::size_t(z - z0) * n + std::size_t(y - lo[1]) * box_size[0] + std::size_t(x - lo[0])];
    };
    const long ze = std::min(long(size[2]), (bz + 1) * kB);
    for (long by = bl[1]; by <= bh[1]; ++by)
      for (long bx = bl[0]; bx <= bh[0]; ++bx) {
        const long ye = std::min(long(size[1]), (by + 1) * kB), xe = std::min(long(size[0]), (bx + 1) * kB);
        bool keep = false, negative = false, positive = false;
        for (long z = bz * kB; z < ze && !keep; ++z)
          for (long y = by * kB; y < ye && !keep; ++y)
            for (long x = bx * kB; x < xe; ++x) {
              const float v = at(x, y, z);
              if (!(std::fabs(v) >= clamp_)) {  // NaN kept: the owner rejects it
                keep = true;
                break;
              }
              (v < 0 ? negative : positive) = true;
            }
        // All clamped: one sign (two neighbouring samples of opposite signs
        // lie within a voxel of S); kept all the same if not.
        keep = keep || (negative && positive);
        std::uint32_t& entry = table_[std::size_t(bx + nb_[0] * (by + nb_[1] * bz))];
        if (!keep) {
          entry = negative ? 0 : 1;
          continue;
        }
        entry = std::uint32_t(pool_.size() / kBlockSamples);
        pool_.resize(pool_.size() + kBlockSamples, 0.0f);
        float* block = pool_.data() + pool_.size() - kBlockSamples;
        for (long z = bz * kB; z < ze; ++z)
          for (long y = by * kB; y < ye; ++y)
            for (long x = bx * kB; x < xe; ++x) block[local(x, y, z)] = clamped(at(x, y, z));
      }
  }
}

void SampleGrid::blocks_to_dense() {
  std::vector<float> d;
  d.reserve(count());
  prefer_huge_pages(d);
  d.resize(count());
  for (std::size_t z = 0; z < size[2]; ++z)
    for (std::size_t y = 0; y < size[1]; ++y)
      for (std::size_t x = 0; x < size[0]; ++x) d[index(x, y, z)] = (*this)(x, y, z);
  std::vector<float>().swap(pool_);
  std::vector<std::uint32_t>().swap(table_);
  dense_ = std::move(d);
}

bool SampleGrid::finite() const {
  for (float v : dense_)
    if (!std::isfinite(v)) return false;
  for (std::size_t i = 2 * kBlockSamples; i < pool_.size(); ++i)  // the stored blocks (T may be infinite)
    if (!std::isfinite(pool_[i])) return false;
  return true;
}

FloatImage SampleGrid::to_image() const {
  FloatImage g(geometry());
  for (std::size_t z = 0; z < size[2]; ++z)
    for (std::size_t y = 0; y < size[1]; ++y)
      for (std::size_t x = 0; x < size[0]; ++x) g(x, y, z) = (*this)(x, y, z);
  return g;
}

} // namespace imgmesh
