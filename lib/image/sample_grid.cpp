#include "image/sample_grid.hpp"
#include "util/error.hpp"

#include <algorithm>
#include <cmath>
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

SampleGrid::SampleGrid(FloatImage g, float clamp, Storage storage) : Geometry(g.geometry()), clamp_(clamp) {
  if (!(clamp > 0)) throw Error("internal: the samples' clamp must be positive");
  if (g.data.size() != g.count()) throw Error("internal: sample data does not match the grid size");
  for (int i = 0; i < 3; ++i) nb_[i] = (long(size[i]) + kB - 1) / kB;
  s1_ = long(size[0]);
  s2_ = long(size[0]) * long(size[1]);
  const std::size_t nblocks = std::size_t(nb_[0] * nb_[1] * nb_[2]);
  if (nblocks > (std::size_t(1) << 31)) throw Error("grid too large");
  auto clamped = [clamp](float v) { return v < -clamp ? -clamp : v > clamp ? clamp : v; };  // NaN kept
  auto keep_dense = [&] {
    for (float& v : g.data) v = clamped(v);
    dense_.reserve(g.data.size());
    prefer_huge_pages(dense_);
    dense_.assign(g.data.begin(), g.data.end());
  };
  const std::size_t dense_bytes = g.data.size() * sizeof(float);
  if (storage == Storage::dense || (storage == Storage::automatic && dense_bytes < kBlocksWorth)) {
    keep_dense();
    return;
  }
  // Which blocks clamp whole (kept as the sign of their samples), which are stored.
  table_.assign(nblocks, 0);
  std::size_t stored = 0;
  for (long bz = 0; bz < nb_[2]; ++bz)
    for (long by = 0; by < nb_[1]; ++by)
      for (long bx = 0; bx < nb_[0]; ++bx) {
        bool keep = false, negative = false;
        for (long z = bz * kB; z < std::min(long(size[2]), (bz + 1) * kB) && !keep; ++z)
          for (long y = by * kB; y < std::min(long(size[1]), (by + 1) * kB) && !keep; ++y)
            for (long x = bx * kB; x < std::min(long(size[0]), (bx + 1) * kB); ++x) {
              const float v = g(std::size_t(x), std::size_t(y), std::size_t(z));
              if (!(std::fabs(v) >= clamp)) {  // NaN kept: the owner rejects it
                keep = true;
                break;
              }
              negative = v < 0;
            }
        table_[std::size_t(bx + nb_[0] * (by + nb_[1] * bz))] = keep ? std::uint32_t(2 + stored++) : negative ? 0 : 1;
      }
  const std::size_t block_bytes = ((2 + stored) * std::size_t(kBlockSamples) + nblocks) * sizeof(float);
  if (storage == Storage::automatic && (dense_bytes < block_bytes || dense_bytes - block_bytes < kBlocksWorth)) {
    std::vector<std::uint32_t>().swap(table_);
    keep_dense();
    return;
  }
  pool_.reserve((2 + stored) * kBlockSamples);
  prefer_huge_pages(pool_);
  pool_.assign((2 + stored) * kBlockSamples, 0.0f);
  std::fill_n(pool_.begin(), kBlockSamples, -clamp);
  std::fill_n(pool_.begin() + kBlockSamples, kBlockSamples, clamp);
  for (long z = 0; z < long(size[2]); ++z)
    for (long y = 0; y < long(size[1]); ++y)
      for (long x = 0; x < long(size[0]); ++x) {
        const std::uint32_t b = table_[std::size_t((x >> kShift) + nb_[0] * ((y >> kShift) + nb_[1] * (z >> kShift)))];
        if (b < 2) continue;
        const float v = g(std::size_t(x), std::size_t(y), std::size_t(z));
        pool_[std::size_t(b) * kBlockSamples + std::size_t(local(x, y, z))] = clamped(v);
      }
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
