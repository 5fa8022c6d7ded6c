#include "image/sample_grid.hpp"
#include "util/error.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>
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
template <class T> void prefer_huge_pages(std::vector<T>& pool) {
#if defined(__linux__) && defined(MADV_HUGEPAGE)
  const std::size_t bytes = pool.capacity() * sizeof(T);
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
  set_box(lo, box_size);
  if (dense_chosen(storage)) {
    stream_dense(box_size, next_slice, given);
    return;
  }
  stream_blocks(box_size, next_slice);
  after_blocks(storage);
}

SampleGrid::SampleGrid(const Geometry& grid, const Index3& lo, const std::array<std::size_t, 3>& box_size, float clamp,
                       Storage storage, const BandReader& next_band, std::size_t band_bytes)
    : Geometry(grid), clamp_(clamp) {
  set_box(lo, box_size);
  if (dense_chosen(storage)) {
    band_dense(box_size, next_band, band_bytes);
    return;
  }
  band_blocks(box_size, next_band, band_bytes);
  after_blocks(storage);
}

void SampleGrid::set_box(const Index3& lo, const std::array<std::size_t, 3>& box_size) {
  if (!(clamp_ > 0)) throw Error("internal: the samples' clamp must be positive");
  bool whole = true;
  for (int i = 0; i < 3; ++i) {
    if (lo[i] < 0 || box_size[i] == 0 || std::size_t(lo[i]) + box_size[i] > size[i])
      throw Error("internal: the samples' box is not inside the grid");
    whole = whole && lo[i] == 0 && box_size[i] == size[i];
    box_lo_[i] = lo[i];
    box_hi_[i] = lo[i] + std::ptrdiff_t(box_size[i]) - 1;
    first_block_[i] = (long(box_lo_[i]) >> kShift) - 1;
    nb_[i] = (long(box_hi_[i]) >> kShift) - first_block_[i] + 2;
  }
  if (!whole && !std::isfinite(clamp_)) throw Error("internal: the samples outside the box need a finite clamp");
  s1_ = long(size[0]);
  s2_ = long(size[0]) * long(size[1]);
  if (std::size_t(nb_[0] * nb_[1] * nb_[2]) > (std::size_t(1) << 31)) throw Error("grid too large");
}

// Unclamped samples all go in blocks: dense is smaller.
bool SampleGrid::dense_chosen(Storage storage) const {
  const std::size_t dense_bytes = count() * sizeof(float);
  return storage == Storage::dense ||
         (storage == Storage::automatic && (dense_bytes < kBlocksWorth || !std::isfinite(clamp_)));
}

void SampleGrid::after_blocks(Storage storage) {
  const std::size_t dense_bytes = count() * sizeof(float);
  const std::size_t block_bytes = (pool_.size() + table_.size()) * sizeof(float);
  if (storage == Storage::automatic && (dense_bytes < block_bytes || dense_bytes - block_bytes < kBlocksWorth))
    blocks_to_dense();
  else
    code_pool();
}

// Codes in the order the values first come in the pool (deterministic: the
// pool's order is), found in an open-addressing table of their bits; the
// float pool is let go once coded (the float and coded pools are held
// together only here, long before the meshers' peak).
void SampleGrid::code_pool() {
  constexpr std::size_t kSlots = 2 * kCodes;  // at most half full
  struct Entry {
    std::uint32_t bits;
    std::uint32_t code;  // + 1; 0: empty
  };
  std::vector<Entry> table(kSlots, Entry{0, 0});
  std::vector<float> palette;
  std::vector<std::uint16_t> codes;
  codes.reserve(pool_.size());
  prefer_huge_pages(codes);
  for (const float v : pool_) {
    std::uint32_t bits;
    std::memcpy(&bits, &v, sizeof bits);
    std::size_t i = (bits * 0x9E3779B1u) >> 15;  // 17 bits: kSlots
    while (table[i].code != 0 && table[i].bits != bits) i = (i + 1) & (kSlots - 1);
    if (table[i].code == 0) {
      if (palette.size() == kCodes) return;  // too many values: floats kept
      table[i] = {bits, std::uint32_t(palette.size()) + 1};
      palette.push_back(v);
    }
    codes.push_back(std::uint16_t(table[i].code - 1));
  }
  static_assert(2 * kCodes == std::size_t(1) << 17, "the hash's 17 bits index the table");
  codes_ = std::move(codes);
  palette_ = std::move(palette);
  std::vector<float>().swap(pool_);
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

void SampleGrid::start_blocks() {
  ZeroedVector<std::uint32_t>(std::size_t(nb_[0] * nb_[1] * nb_[2])).swap(table_);  // outside the box: +T
  const std::size_t bound = 2 + blocks();
  // Room for every block the box meets: only the pages written take memory,
  // so the pool never moves (growing it would hold it twice).
  try {
    pool_.reserve(bound * kBlockSamples);
  } catch (const std::bad_alloc&) {
  }
  prefer_huge_pages(pool_);
  pool_.assign(2 * kBlockSamples, clamp_);
  std::fill_n(pool_.begin() + kBlockSamples, kBlockSamples, -clamp_);
}

void SampleGrid::add_blocks(const long c0[3], const long c1[3], const float* chunk) {
  auto clamped = [this](float v) { return v < -clamp_ ? -clamp_ : v > clamp_ ? clamp_ : v; };  // NaN kept
  const long nx = c1[0] - c0[0] + 1, nxy = nx * (c1[1] - c0[1] + 1);
  auto at = [&](long x, long y, long z) {  // a sample of the sub-box's blocks
    if (x < c0[0] || x > c1[0] || y < c0[1] || y > c1[1] || z < c0[2] || z > c1[2]) return clamp_;
    return chunk[std::size_t((z - c0[2]) * nxy + (y - c0[1]) * nx + (x - c0[0]))];
  };
  for (long bz = c0[2] >> kShift; bz <= c1[2] >> kShift; ++bz) {
    const long ze = std::min(long(size[2]), (bz + 1) * kB);
    for (long by = c0[1] >> kShift; by <= c1[1] >> kShift; ++by)
      for (long bx = c0[0] >> kShift; bx <= c1[0] >> kShift; ++bx) {
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
        std::uint32_t& entry = table_[std::size_t(table_index(bx, by, bz))];
        if (!keep) {
          entry = negative ? 1 : 0;
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

// A layer of blocks (kB z-slices) at a time.
void SampleGrid::stream_blocks(const std::array<std::size_t, 3>& box_size, const SliceReader& next_slice) {
  start_blocks();
  const std::size_t n = box_size[0] * box_size[1];
  std::vector<float> layer(n * std::size_t(std::min<long>(kB, long(box_size[2]))));
  const long lo[3] = {long(box_lo_[0]), long(box_lo_[1]), long(box_lo_[2])};
  const long hi[3] = {long(box_hi_[0]), long(box_hi_[1]), long(box_hi_[2])};
  for (long bz = lo[2] >> kShift; bz <= hi[2] >> kShift; ++bz) {
    const long z0 = std::max(bz * kB, lo[2]), z1 = std::min((bz + 1) * kB - 1, hi[2]);
    for (long z = z0; z <= z1; ++z) next_slice(layer.data() + std::size_t(z - z0) * n);
    const long c0[3] = {lo[0], lo[1], z0}, c1[3] = {hi[0], hi[1], z1};
    add_blocks(c0, c1, layer.data());
  }
}

namespace {

// The bands of x of a box (grid indices lo..hi of x, ny nz samples a
// column): [first, last] each, whole blocks but at the box's sides.
template <class F> void for_each_band(long lo, long hi, std::size_t column, std::size_t bytes, F&& f) {
  const long kB = SampleGrid::kB;
  const long width = std::max(kB, long(bytes / (sizeof(float) * std::max<std::size_t>(column, 1))) / kB * kB);
  for (long x0 = lo; x0 <= hi;) {
    const long x1 = std::min(hi, (x0 + width) / kB * kB - 1);
    f(x0, x1);
    x0 = x1 + 1;
  }
}

} // namespace

void SampleGrid::band_dense(const std::array<std::size_t, 3>& box_size, const BandReader& next_band,
                            std::size_t band_bytes) {
  auto clamped = [this](float v) { return v < -clamp_ ? -clamp_ : v > clamp_ ? clamp_ : v; };  // NaN kept
  dense_.reserve(count());
  prefer_huge_pages(dense_);
  dense_.assign(count(), clamp_);
  std::vector<float> band;
  const std::size_t column = box_size[1] * box_size[2];
  for_each_band(long(box_lo_[0]), long(box_hi_[0]), column, band_bytes, [&](long x0, long x1) {
    const std::size_t w = std::size_t(x1 - x0 + 1);
    band.resize(w * column);
    next_band(std::size_t(x0 - box_lo_[0]), std::size_t(x1 + 1 - box_lo_[0]), band.data());
    for (std::size_t z = 0; z < box_size[2]; ++z)
      for (std::size_t y = 0; y < box_size[1]; ++y)
        std::transform(band.data() + (z * box_size[1] + y) * w, band.data() + (z * box_size[1] + y + 1) * w,
                       dense_.data() + index(std::size_t(x0), std::size_t(box_lo_[1]) + y, std::size_t(box_lo_[2]) + z),
                       clamped);
  });
}

void SampleGrid::band_blocks(const std::array<std::size_t, 3>& box_size, const BandReader& next_band,
                             std::size_t band_bytes) {
  start_blocks();
  std::vector<float> band;
  const std::size_t column = box_size[1] * box_size[2];
  for_each_band(long(box_lo_[0]), long(box_hi_[0]), column, band_bytes, [&](long x0, long x1) {
    band.resize(std::size_t(x1 - x0 + 1) * column);
    next_band(std::size_t(x0 - box_lo_[0]), std::size_t(x1 + 1 - box_lo_[0]), band.data());
    const long c0[3] = {x0, long(box_lo_[1]), long(box_lo_[2])}, c1[3] = {x1, long(box_hi_[1]), long(box_hi_[2])};
    add_blocks(c0, c1, band.data());
  });
  sort_pool();
}

// Slot s of the pool goes to to[s]: the blocks in the order of their
// numbers, as slices append them (the same memory, the same locality).
void SampleGrid::sort_pool() {
  std::vector<std::uint32_t> to(pool_.size() / kBlockSamples);
  std::uint32_t next = 2;
  to[0] = 0;
  to[1] = 1;
  for (std::uint32_t& entry : table_)
    if (entry >= 2) {
      to[entry] = next;
      entry = next++;
    }
  for (std::size_t s = 2; s < to.size(); ++s)
    while (to[s] != s) {
      const std::uint32_t t = to[s];
      std::swap_ranges(pool_.begin() + std::ptrdiff_t(s * kBlockSamples), pool_.begin() + std::ptrdiff_t((s + 1) * kBlockSamples),
                       pool_.begin() + std::ptrdiff_t(std::size_t(t) * kBlockSamples));
      to[s] = to[t];
      to[t] = t;
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
  ZeroedVector<std::uint32_t>().swap(table_);
  dense_ = std::move(d);
}

bool SampleGrid::finite() const {
  for (float v : dense_)
    if (!std::isfinite(v)) return false;
  for (std::size_t i = 2 * kBlockSamples; i < pool_.size(); ++i)  // the stored blocks (T may be infinite)
    if (!std::isfinite(pool_[i])) return false;
  for (std::size_t i = 2 * kBlockSamples; i < codes_.size(); ++i)
    if (!std::isfinite(palette_[codes_[i]])) return false;
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
