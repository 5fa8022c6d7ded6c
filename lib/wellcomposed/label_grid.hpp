// The dense label grid behind the multi-label count and repair: label
// values mapped to indices 0..K (0 = the background 0), one byte a voxel for
// K <= 255, two above. Internal to the wellcomposed module (and its tests).
//
// A block N(r) is read as eight indices v[k] (bit k as in
// critical_configuration.hpp); the configurations of label L in it are
// those of the binary code "which v[k] are L" (the indicator's block).
#pragma once
#include "image/grid.hpp"
#include "wellcomposed/critical_configuration.hpp"
#include "wellcomposed/well_composed.hpp"

#include <array>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <vector>

namespace imgmesh::wellcomposed_detail {

// The values of an image, values[0] = 0 (present or not), then the others
// increasing; index_of() maps a value to its index.
struct LabelValues {
  std::vector<std::int32_t> values;
  std::vector<std::size_t> voxels;  // per index, in the image
  std::int32_t lo = 0;
  std::vector<std::uint16_t> table;  // value - lo -> index, when the range is small
  std::size_t index_of(std::int32_t v) const;
};
// Throws Error above 65535 labels besides 0.
LabelValues label_values(const LabelImage& img);

// The indicator code of label l in a block: bit k set when v[k] == l.
template <class T> inline unsigned mask_of(const T v[8], T l) {
  unsigned m = 0;
  for (int k = 0; k < 8; ++k) m |= unsigned(v[k] == l) << k;
  return m;
}

// Eight rows' worth of blocks (4 rows of 8 values from their pointers) hold
// one label only: none of those 7 blocks is critical.
template <class T> inline bool uniform_rows(const T* a, const T* b, const T* c, const T* d) {
  const T x = a[0];
  unsigned diff = 0;
  for (int k = 0; k < 8; ++k) diff |= unsigned(a[k] ^ x) | unsigned(b[k] ^ x) | unsigned(c[k] ^ x) | unsigned(d[k] ^ x);
  return diff == 0;
}
// One byte a voxel: four 64-bit loads.
template <> inline bool uniform_rows<std::uint8_t>(const std::uint8_t* a, const std::uint8_t* b, const std::uint8_t* c,
                                                  const std::uint8_t* d) {
  std::uint64_t w[4];
  std::memcpy(&w[0], a, 8);
  std::memcpy(&w[1], b, 8);
  std::memcpy(&w[2], c, 8);
  std::memcpy(&w[3], d, 8);
  return w[0] == w[1] && w[0] == w[2] && w[0] == w[3] && w[0] == std::uint64_t(a[0]) * 0x0101010101010101ull;
}

// Per label index, C1/C2 of its indicator on an nx x ny x nz dense grid
// (outside = index 0). counts.size() must be the number of labels.
template <class T>
void count_dense(const T* v, std::size_t nx, std::size_t ny, std::size_t nz, std::vector<CriticalCounts>& counts);

// One voxel more on each side where a nonzero voxel touches the border
// (2D: x, y): the grid growth of both repairs.
struct Padding {
  std::array<std::size_t, 3> before{0, 0, 0}, after{0, 0, 0};
  bool any() const {
    for (int a = 0; a < 3; ++a)
      if (before[a] || after[a]) return true;
    return false;
  }
};
template <class T> Padding border_padding(const Image<T>& in) {
  Padding p;
  const std::size_t nx = in.size[0], ny = in.size[1], nz = in.size[2];
  const int axes = in.dimension == 2 ? 2 : 3;
  for (std::size_t z = 0; z < nz; ++z)
    for (std::size_t y = 0; y < ny; ++y) {
      const T* row = &in.data[in.index(0, y, z)];
      const bool edge_row = y == 0 || y + 1 == ny || (axes == 3 && (z == 0 || z + 1 == nz));
      if (edge_row) {
        bool anyfg = false;
        for (std::size_t x = 0; x < nx && !anyfg; ++x) anyfg = row[x] != 0;
        if (anyfg) {
          if (y == 0) p.before[1] = 1;
          if (y + 1 == ny) p.after[1] = 1;
          if (axes == 3 && z == 0) p.before[2] = 1;
          if (axes == 3 && z + 1 == nz) p.after[2] = 1;
        }
      }
      if (row[0]) p.before[0] = 1;
      if (row[nx - 1]) p.after[0] = 1;
    }
  return p;
}

} // namespace imgmesh::wellcomposed_detail
