// A label image narrowed in memory, as read_labels_narrow reads one: for a
// stage that only reads the labels (seg2mesh --fast's certificate holds the
// repaired partition a byte a voxel, not 4).
#pragma once
#include "image/io.hpp"

#include <algorithm>
#include <cstdint>
#include <type_traits>
#include <utility>

namespace imgmesh {

// `image` in the narrowest type its values fit (i32 itself, moved, when
// none narrower does), its int32 voxels freed.
inline NarrowLabelImage narrow_labels(LabelImage image) {
  std::int32_t lo = 0, hi = 0;
  for (std::int32_t v : image.data) lo = std::min(lo, v), hi = std::max(hi, v);
  NarrowLabelImage out;
  auto fill = [&](auto& narrow) {
    using T = typename std::decay_t<decltype(narrow.data)>::value_type;
    static_cast<Geometry&>(narrow) = image.geometry();
    narrow.data.resize(image.data.size());
    for (std::size_t i = 0; i < image.data.size(); ++i) narrow.data[i] = T(image.data[i]);  // each fits T
  };
  out.bytes = lo >= 0 && hi <= 255 ? 1 : lo >= 0 && hi <= 65535 ? 2 : 4;
  if (out.bytes == 1) fill(out.u8);
  else if (out.bytes == 2) fill(out.u16);
  else out.i32 = std::move(image);
  return out;
}

} // namespace imgmesh
