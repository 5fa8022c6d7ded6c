#include "image/foreground_runs.hpp"

#include "image/voxel_stream.hpp"

#include <algorithm>
#include <iterator>
#include <limits>

namespace imgmesh {

ForegroundRuns::ForegroundRuns(const BinaryImage& image) : geometry_(image.geometry()) {
  const std::size_t nx = image.size[0];
  for (std::size_t z = 0; z < image.size[2]; ++z)
    for (std::size_t y = 0; y < image.size[1]; ++y) {
      const std::uint8_t* v = &image.data[image.index(0, y, z)];
      for (std::size_t x = 0; x < nx;) {
        if (!v[x]) {
          ++x;
          continue;
        }
        const std::size_t x0 = x;
        while (x < nx && v[x]) ++x;
        add(y, z, x0, x);
      }
    }
}

void ForegroundRuns::add(std::size_t y, std::size_t z, std::size_t x0, std::size_t x1) {
  if (rows_.empty() || rows_.back().y != y || rows_.back().z != z)
    rows_.push_back({std::uint32_t(y), std::uint32_t(z), runs_.size()});
  runs_.push_back({std::uint32_t(x0), std::uint32_t(x1)});
  const Index3 a{std::ptrdiff_t(x0), std::ptrdiff_t(y), std::ptrdiff_t(z)}, b{std::ptrdiff_t(x1) - 1, a[1], a[2]};
  for (int i = 0; i < 3; ++i) {
    lo_[i] = count_ ? std::min(lo_[i], a[i]) : a[i];
    hi_[i] = count_ ? std::max(hi_[i], b[i]) : b[i];
  }
  count_ += x1 - x0;
}

void ForegroundRuns::row(std::size_t y, std::size_t z, std::size_t x0, std::size_t n, std::uint8_t* out) const {
  std::fill_n(out, n, std::uint8_t(0));
  const auto it = std::lower_bound(rows_.begin(), rows_.end(), std::make_pair(z, y), [](const Row& r, const auto& p) {
    return r.z < p.first || (r.z == p.first && r.y < p.second);
  });
  if (it == rows_.end() || it->z != z || it->y != y) return;
  const std::size_t last = std::next(it) == rows_.end() ? runs_.size() : std::next(it)->first;
  for (std::size_t r = it->first; r < last; ++r) {
    const std::size_t a = std::max<std::size_t>(runs_[r][0], x0), b = std::min<std::size_t>(runs_[r][1], x0 + n);
    if (a < b) std::fill_n(out + (a - x0), b - a, std::uint8_t(1));
  }
}

BinaryImage ForegroundRuns::image() const {
  BinaryImage img(geometry_, 0);
  for (std::size_t k = 0; k < rows_.size(); ++k) {
    const std::size_t last = k + 1 == rows_.size() ? runs_.size() : rows_[k + 1].first;
    for (std::size_t r = rows_[k].first; r < last; ++r)
      std::fill_n(&img.data[img.index(runs_[r][0], rows_[k].y, rows_[k].z)], runs_[r][1] - runs_[r][0], std::uint8_t(1));
  }
  return img;
}

namespace {

template <class T> ForegroundRuns runs_of(const Geometry& scan, VoxelStream& in, LabelMatch& match) {
  ForegroundRuns out(scan, true);
  match.seen.assign(match.labels.size(), 0);
  // The labels a T can be, as T (sorted as the labels are), and which label each is.
  std::vector<T> want;
  std::vector<std::size_t> which;
  for (std::size_t i = 0; i < match.labels.size(); ++i)
    if (match.labels[i] >= std::numeric_limits<T>::min() && match.labels[i] <= std::numeric_limits<T>::max()) {
      want.push_back(T(match.labels[i]));
      which.push_back(i);
    }
  if (want.empty()) return out;  // none can occur
  const T lo = want.front(), hi = want.back();
  const bool one = want.size() == 1;
  auto find = [&](T v) -> std::ptrdiff_t {
    if (one) return v == lo ? 0 : -1;
    const auto it = std::lower_bound(want.begin(), want.end(), v);
    return it != want.end() && *it == v ? it - want.begin() : -1;
  };
  const std::size_t nx = scan.size[0], ny = scan.size[1];
  std::vector<T> slice(nx * ny);
  for (std::size_t z = 0; z < scan.size[2]; ++z) {
    in.read(slice.data(), slice.size());
    for (std::size_t y = 0; y < ny; ++y) {
      const T* v = slice.data() + y * nx;
      // Most rows hold none: a test the compiler vectorizes first.
      std::uint8_t any = 0;
      if (one)
        for (std::size_t x = 0; x < nx; ++x) any |= std::uint8_t(v[x] == lo);
      else
        for (std::size_t x = 0; x < nx; ++x) any |= std::uint8_t((v[x] >= lo) & (v[x] <= hi));
      if (!any) continue;
      for (std::size_t x = 0; x < nx;) {
        std::ptrdiff_t k = find(v[x]);
        if (k < 0) {
          ++x;
          continue;
        }
        const std::size_t x0 = x;
        for (; x < nx && (k = find(v[x])) >= 0; ++x) match.seen[which[std::size_t(k)]] = 1;
        out.add(y, z, x0, x);
      }
    }
  }
  return out;
}

} // namespace

ForegroundRuns label_runs(const Geometry& scan, VoxelStream& in, IntegerType type, LabelMatch& match) {
  switch (type) {
    case IntegerType::u8: return runs_of<std::uint8_t>(scan, in, match);
    case IntegerType::i8: return runs_of<std::int8_t>(scan, in, match);
    case IntegerType::u16: return runs_of<std::uint16_t>(scan, in, match);
    case IntegerType::i16: return runs_of<std::int16_t>(scan, in, match);
    case IntegerType::u32: return runs_of<std::uint32_t>(scan, in, match);
    case IntegerType::i32: break;
  }
  return runs_of<std::int32_t>(scan, in, match);
}

} // namespace imgmesh
