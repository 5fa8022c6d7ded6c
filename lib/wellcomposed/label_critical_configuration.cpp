// Critical configurations of every label of a label image at once: one pass
// over the blocks N(r), r in [0, n-1]^3 (outside = background, as the binary
// counter), each block split by label into the indicators' codes.
#include "util/error.hpp"
#include "wellcomposed/label_grid.hpp"
#include "wellcomposed/well_composed_partition.hpp"

#include <algorithm>
#include <string>
#include <unordered_set>

namespace imgmesh {
namespace wellcomposed_detail {

std::size_t LabelValues::index_of(std::int32_t v) const {
  if (!table.empty()) return table[std::size_t(std::int64_t(v) - lo)];
  if (v == 0) return 0;
  return std::size_t(std::lower_bound(values.begin() + 1, values.end(), v) - values.begin());
}

LabelValues label_values(const LabelImage& img) {
  LabelValues lv;
  if (img.data.empty()) {
    lv.values = {0};
    lv.voxels = {0};
    return lv;
  }
  const auto [mn, mx] = std::minmax_element(img.data.begin(), img.data.end());
  const std::int64_t lo = std::min<std::int64_t>(*mn, 0), hi = std::max<std::int64_t>(*mx, 0);
  constexpr std::int64_t kTable = std::int64_t(1) << 22;  // values spread wider: a sorted search
  std::vector<std::int32_t> others;
  if (hi - lo < kTable) {
    std::vector<char> seen(std::size_t(hi - lo + 1), 0);
    for (std::int32_t v : img.data) seen[std::size_t(std::int64_t(v) - lo)] = 1;
    for (std::size_t i = 0; i < seen.size(); ++i)
      if (seen[i] && std::int64_t(i) + lo != 0) others.push_back(std::int32_t(std::int64_t(i) + lo));
  } else {
    std::unordered_set<std::int32_t> seen;
    std::int32_t last = 0;
    for (std::int32_t v : img.data)
      if (v != last) seen.insert(last = v);
    seen.erase(0);
    others.assign(seen.begin(), seen.end());
    std::sort(others.begin(), others.end());
  }
  if (others.size() > 65535)
    throw Error("more than 65535 labels (" + std::to_string(others.size()) + ") besides 0");
  lv.values.push_back(0);
  lv.values.insert(lv.values.end(), others.begin(), others.end());
  lv.lo = std::int32_t(lo);
  if (hi - lo < kTable) {
    lv.table.assign(std::size_t(hi - lo + 1), 0);
    for (std::size_t i = 0; i < lv.values.size(); ++i) lv.table[std::size_t(std::int64_t(lv.values[i]) - lo)] = std::uint16_t(i);
  }
  lv.voxels.assign(lv.values.size(), 0);
  std::int32_t last = lv.values.size() > 1 ? lv.values[1] : 0;
  std::size_t last_index = lv.index_of(last);
  for (std::int32_t v : img.data) {
    if (v != last) last_index = lv.index_of(last = v);
    ++lv.voxels[last_index];
  }
  return lv;
}

template <class T>
void count_dense(const T* v, std::size_t nx, std::size_t ny, std::size_t nz, std::vector<CriticalCounts>& counts) {
  const std::vector<T> zero(nx + 9, T(0));
  auto row = [&](std::size_t y, std::size_t z) -> const T* { return (y < ny && z < nz) ? v + nx * (y + ny * z) : zero.data(); };
  for (std::size_t z = 0; z < nz; ++z)
    for (std::size_t y = 0; y < ny; ++y) {
      const T* r[4] = {row(y, z), row(y + 1, z), row(y, z + 1), row(y + 1, z + 1)};
      for (std::size_t x = 0; x < nx; ++x) {
        if (x + 8 <= nx && uniform_rows(r[0] + x, r[1] + x, r[2] + x, r[3] + x)) {
          x += 6;  // blocks x .. x+6 hold one label
          continue;
        }
        T b[8];
        for (int k = 0; k < 8; ++k) {
          const std::size_t xx = x + (k & 1);
          b[k] = xx < nx ? r[k >> 1][xx] : T(0);
        }
        unsigned done = 0;
        for (int k = 0; k < 8; ++k) {
          if (done >> k & 1u) continue;
          const unsigned m = mask_of(b, b[k]);
          done |= m;
          if (m == 0xffu) break;
          const std::uint8_t f = critical_configurations(std::uint8_t(m));
          if (!f) continue;
          CriticalCounts& c = counts[b[k]];
          c.c1 += std::size_t(__builtin_popcount(f & (kC1x | kC1y | kC1z)));
          c.c2 += (f & kC2) ? 1 : 0;
        }
      }
    }
}
template void count_dense<std::uint8_t>(const std::uint8_t*, std::size_t, std::size_t, std::size_t,
                                        std::vector<CriticalCounts>&);
template void count_dense<std::uint16_t>(const std::uint16_t*, std::size_t, std::size_t, std::size_t,
                                         std::vector<CriticalCounts>&);

} // namespace wellcomposed_detail

std::size_t LabelCriticalCounts::total() const {
  std::size_t t = 0;
  for (const CriticalCounts& c : counts) t += c.total();
  return t;
}

std::size_t LabelCriticalCounts::labels_with_configurations() const {
  return std::size_t(std::count_if(counts.begin(), counts.end(), [](const CriticalCounts& c) { return c.total() > 0; }));
}

Json LabelCriticalCounts::to_json() const {
  Json j = Json::object();
  std::size_t c1 = 0, c2 = 0;
  Json left = Json::array(), per = Json::object();
  for (std::size_t i = 0; i < labels.size(); ++i) {
    c1 += counts[i].c1;
    c2 += counts[i].c2;
    if (counts[i].total()) {
      left.push_back(labels[i]);
      Json l = Json::object();
      l["c1"] = counts[i].c1;
      l["c2"] = counts[i].c2;
      per[std::to_string(labels[i])] = l;
    }
  }
  j["c1"] = c1;
  j["c2"] = c2;
  j["labels_left"] = left;
  j["per_label"] = per;
  return j;
}

LabelCriticalCounts count_label_critical_configurations(const LabelImage& img) {
  wellcomposed_detail::check_size(img, "count_label_critical_configurations");
  if (img.data.size() != img.count()) throw Error("count_label_critical_configurations: image data size mismatch");
  const wellcomposed_detail::LabelValues lv = wellcomposed_detail::label_values(img);
  LabelCriticalCounts out;
  out.labels = lv.values;
  out.counts.assign(lv.values.size(), {});
  const std::size_t nx = img.size[0], ny = img.size[1], nz = img.dimension == 2 ? 1 : img.size[2];
  auto run = [&](auto tag) {
    using T = decltype(tag);
    std::vector<T> dense(img.data.size());
    std::int32_t last = 0;
    std::size_t index = 0;
    for (std::size_t i = 0; i < dense.size(); ++i) {
      if (img.data[i] != last) index = lv.index_of(last = img.data[i]);
      dense[i] = T(index);
    }
    wellcomposed_detail::count_dense(dense.data(), nx, ny, nz, out.counts);
  };
  if (lv.values.size() <= 256) run(std::uint8_t());
  else run(std::uint16_t());
  return out;
}

PartitionCheck check_well_composed_partition(const LabelImage& img) {
  PartitionCheck c;
  c.dimension = img.dimension;
  c.voxels = img.count();
  c.counts = count_label_critical_configurations(img);
  return c;
}

Json PartitionCheck::to_json() const {
  Json j = Json::object();
  j["dimension"] = dimension;
  j["voxels"] = voxels;
  j["labels"] = counts.labels.size() - 1;
  j["label_values"] = std::vector<std::int32_t>(counts.labels.begin() + 1, counts.labels.end());
  const Json c = counts.to_json();
  for (const char* k : {"c1", "c2", "labels_left", "per_label"}) j[k] = c.at(k);
  j["well_composed"] = counts.total() == 0;
  return j;
}

std::string PartitionCheck::failed_guarantee() const {
  if (!counts.total()) return "";
  return "not a well-composed partition: " + std::to_string(counts.total()) + " critical configurations in " +
         std::to_string(counts.labels_with_configurations()) + " labels";
}

} // namespace imgmesh
