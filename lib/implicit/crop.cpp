#include "implicit/crop.hpp"

#include "util/error.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <sstream>

namespace imgmesh {

void VoxelBox::add(std::ptrdiff_t x, std::ptrdiff_t y, std::ptrdiff_t z) {
  const std::ptrdiff_t c[3] = {x, y, z};
  const bool was_empty = empty();
  for (int a = 0; a < 3; ++a) {
    lo[a] = was_empty ? c[a] : std::min(lo[a], c[a]);
    hi[a] = was_empty ? c[a] : std::max(hi[a], c[a]);
  }
}

std::array<std::size_t, 3> VoxelBox::size() const {
  if (empty()) return {0, 0, 0};
  return {std::size_t(hi[0] - lo[0] + 1), std::size_t(hi[1] - lo[1] + 1), std::size_t(hi[2] - lo[2] + 1)};
}

VoxelBox foreground_box(const BinaryImage& image) {
  VoxelBox box;
  for (std::size_t z = 0; z < image.size[2]; ++z)
    for (std::size_t y = 0; y < image.size[1]; ++y) {
      const std::uint8_t* row = &image.data[image.index(0, y, z)];
      const std::uint8_t* end = row + image.size[0];
      const std::uint8_t* first = std::find_if(row, end, [](std::uint8_t v) { return v != 0; });
      if (first == end) continue;
      const std::uint8_t* last = end - 1;
      while (*last == 0) --last;
      box.add(first - row, std::ptrdiff_t(y), std::ptrdiff_t(z));
      box.add(last - row, std::ptrdiff_t(y), std::ptrdiff_t(z));
    }
  return box;
}

// ---- ScanFrame ----

Geometry ScanFrame::scan(const Geometry& crop) const {
  Geometry g = crop;
  g.size = size;
  g.origin = origin;
  return g;
}

std::map<std::string, std::string> ScanFrame::keys() const {
  char buf[160];
  std::map<std::string, std::string> k;
  std::snprintf(buf, sizeof buf, "%zu %zu %zu", size[0], size[1], size[2]);
  k["imgmesh_scan_size"] = buf;
  std::snprintf(buf, sizeof buf, "%td %td %td", index[0], index[1], index[2]);
  k["imgmesh_scan_index"] = buf;
  std::snprintf(buf, sizeof buf, "%.17g %.17g %.17g", origin[0], origin[1], origin[2]);
  k["imgmesh_scan_origin"] = buf;
  std::snprintf(buf, sizeof buf, "%td %td %td %td %td %td", foreground.lo[0], foreground.lo[1], foreground.lo[2],
                foreground.hi[0], foreground.hi[1], foreground.hi[2]);
  k["imgmesh_foreground_box"] = buf;
  return k;
}

namespace {

const char* const kFrameKeys[] = {"imgmesh_scan_size", "imgmesh_scan_index", "imgmesh_scan_origin",
                                  "imgmesh_foreground_box"};

// n numbers of a key, or an Error naming it.
template <class T> std::vector<T> numbers(const std::map<std::string, std::string>& keys, const char* key,
                                          std::size_t n, const std::string& path) {
  std::istringstream in(keys.at(key));
  std::vector<T> v(n);
  std::string extra;
  for (T& x : v)
    if (!(in >> x)) throw Error(std::string("bad ") + key + " field '" + keys.at(key) + "'", path);
  if (in >> extra) throw Error(std::string("bad ") + key + " field '" + keys.at(key) + "'", path);
  return v;
}

} // namespace

ScanFrame ScanFrame::from_keys(const std::map<std::string, std::string>& keys, const Geometry& crop,
                               const std::string& path) {
  std::size_t found = 0;
  for (const char* k : kFrameKeys) found += keys.count(k);
  if (found == 0) return {};
  if (found != std::size(kFrameKeys))
    throw Error("the crop's scan frame is incomplete (imgmesh_scan_size, imgmesh_scan_index, imgmesh_scan_origin "
                "and imgmesh_foreground_box go together)",
                path);
  if (crop.dimension != 3) throw Error("a 2D image with a scan frame (crops are 3D)", path);
  ScanFrame f;
  const auto size = numbers<long long>(keys, "imgmesh_scan_size", 3, path);
  const auto index = numbers<long long>(keys, "imgmesh_scan_index", 3, path);
  const auto origin = numbers<double>(keys, "imgmesh_scan_origin", 3, path);
  const auto box = numbers<long long>(keys, "imgmesh_foreground_box", 6, path);
  std::size_t count = 1;
  for (int a = 0; a < 3; ++a) {
    if (size[a] <= 0 || index[a] < 0 || std::size_t(index[a]) + crop.size[a] > std::size_t(size[a]))
      throw Error("the crop does not lie inside its scan (imgmesh_scan_size, imgmesh_scan_index)", path);
    if (count > (std::size_t(1) << 40) / std::size_t(size[a])) throw Error("the crop's scan is too large", path);
    count *= std::size_t(size[a]);
    if (!std::isfinite(origin[a])) throw Error("bad imgmesh_scan_origin field", path);
    if (box[a] < 0 || box[a] > box[a + 3] || box[a + 3] >= (long long)crop.size[a])
      throw Error("bad imgmesh_foreground_box field (a box inside the crop expected)", path);
    f.size[a] = std::size_t(size[a]);
    f.index[a] = std::ptrdiff_t(index[a]);
    f.origin[a] = origin[a];
    f.foreground.lo[a] = std::ptrdiff_t(box[a]);
    f.foreground.hi[a] = std::ptrdiff_t(box[a + 3]);
  }
  // The crop's own origin is where the scan's grid puts its first voxel.
  const Vec3 at = f.scan(crop).world(double(f.index[0]), double(f.index[1]), double(f.index[2]));
  const double tolerance = 1e-6 * std::min({crop.spacing[0], crop.spacing[1], crop.spacing[2]});
  for (int a = 0; a < 3; ++a)
    if (!(std::fabs(at[a] - crop.origin[a]) <= tolerance))
      throw Error("the crop's origin is not where imgmesh_scan_origin and imgmesh_scan_index place it", path);
  return f;
}

bool ScanFrame::grow(const std::array<std::size_t, 3>& before, const std::array<std::size_t, 3>& after,
                     const Geometry& crop_before) {
  for (int a = 0; a < 3; ++a) {
    if (before[a] && index[a] != 0) return false;
    if (after[a] && std::size_t(index[a]) + crop_before.size[a] != size[a]) return false;
  }
  // imgmesh::pad's arithmetic on the scan's grid.
  origin = scan(crop_before).world(-double(before[0]), -double(before[1]), -double(before[2]));
  for (int a = 0; a < 3; ++a) {
    size[a] += before[a] + after[a];
    foreground.lo[a] += std::ptrdiff_t(before[a]);
    foreground.hi[a] += std::ptrdiff_t(before[a]);
  }
  return true;
}

// ---- margins ----

std::array<std::size_t, 3> crop_margin(const Vec3& spacing, double clamp) {
  std::array<std::size_t, 3> m = PartitionOfUnity::weight_margin(spacing);
  for (int a = 0; a < 3; ++a) {
    double v = std::max(double(m[a]), std::ceil(clamp / spacing[a] - 0.5));
    while ((v + 0.5) * spacing[a] < clamp) ++v;  // rounding
    m[a] = std::size_t(v);
  }
  return m;
}

float covered_clamp(const Geometry& grid) {
  const double e = kCoveredMaxDistance * std::min({grid.spacing[0], grid.spacing[1], grid.spacing[2]});
  return PartitionOfUnity::clamp_for(grid, e);
}

std::array<std::size_t, 3> crop_margin(const Geometry& grid) { return crop_margin(grid.spacing, covered_clamp(grid)); }

// ---- well_composed_crop ----

namespace {

// The box [lo, hi] of the scan (may reach one voxel beyond it), the outside
// background.
BinaryImage cut(const Geometry& scan, const Index3& lo, const Index3& hi, const ForegroundRows& rows) {
  Geometry g = scan;
  for (int a = 0; a < 3; ++a) g.size[a] = std::size_t(hi[a] - lo[a] + 1);
  g.origin = scan.world(double(lo[0]), double(lo[1]), double(lo[2]));
  BinaryImage out(g, 0);
  const std::ptrdiff_t x0 = std::max<std::ptrdiff_t>(lo[0], 0),
                       x1 = std::min<std::ptrdiff_t>(hi[0], std::ptrdiff_t(scan.size[0]) - 1);
  for (std::ptrdiff_t z = std::max<std::ptrdiff_t>(lo[2], 0); z <= std::min<std::ptrdiff_t>(hi[2], std::ptrdiff_t(scan.size[2]) - 1); ++z)
    for (std::ptrdiff_t y = std::max<std::ptrdiff_t>(lo[1], 0); y <= std::min<std::ptrdiff_t>(hi[1], std::ptrdiff_t(scan.size[1]) - 1); ++y)
      if (x0 <= x1)
        rows(std::size_t(y), std::size_t(z), std::size_t(x0), std::size_t(x1 - x0 + 1),
             &out.data[out.index(std::size_t(x0 - lo[0]), std::size_t(y - lo[1]), std::size_t(z - lo[2]))]);
  return out;
}

} // namespace

WellComposedCrop well_composed_crop(const Geometry& scan, const VoxelBox& box, const ForegroundRows& rows,
                                    const WellComposedOptions& options) {
  if (scan.dimension != 3) throw Error("internal: crops are 3D");
  if (box.empty()) throw Error("the foreground is empty (check --label/--threshold)");
  // The scan's grid as the whole-grid repair has it: one background voxel
  // more where the foreground touches the border (make_well_composed).
  std::array<std::size_t, 3> before{}, after{};
  Index3 lim_lo, lim_hi;
  for (int a = 0; a < 3; ++a) {
    before[a] = box.lo[a] == 0;
    after[a] = std::size_t(box.hi[a]) + 1 == scan.size[a];
    lim_lo[a] = -std::ptrdiff_t(before[a]);
    lim_hi[a] = std::ptrdiff_t(scan.size[a]) - 1 + std::ptrdiff_t(after[a]);
  }
  const std::array<std::size_t, 3> m = crop_margin(scan);
  // Room for the repair: it acts on blocks meeting the foreground (as it
  // grows), and sees G(r), 2 voxels around a block: where all it set stays
  // 2 voxels inside the cut's inner sides, it did what it does on the whole
  // grid. Doubled until it does.
  for (std::ptrdiff_t room = 2;; room *= 2) {
    Index3 lo, hi;
    for (int a = 0; a < 3; ++a) {
      lo[a] = std::max(box.lo[a] - std::ptrdiff_t(m[a]) - room, lim_lo[a]);
      hi[a] = std::min(box.hi[a] + std::ptrdiff_t(m[a]) + room, lim_hi[a]);
    }
    WellComposedResult res = make_well_composed(cut(scan, lo, hi, rows), options);
    const VoxelBox fg = foreground_box(res.image);
    VoxelBox reach = fg;  // all that was foreground at some time: the input's, the repair's
    reach.add(box.lo[0] - lo[0], box.lo[1] - lo[1], box.lo[2] - lo[2]);
    reach.add(box.hi[0] - lo[0], box.hi[1] - lo[1], box.hi[2] - lo[2]);
    if (res.touched_lo[0] <= res.touched_hi[0]) {
      reach.add(res.touched_lo[0], res.touched_lo[1], res.touched_lo[2]);
      reach.add(res.touched_hi[0], res.touched_hi[1], res.touched_hi[2]);
    }
    bool holds = !fg.empty();
    Index3 out_lo, out_hi;  // the result in the cut's indices
    for (int a = 0; a < 3 && holds; ++a) {
      const std::ptrdiff_t n = hi[a] - lo[a] + 1;
      if (lo[a] != lim_lo[a]) holds = holds && reach.lo[a] >= 2 && fg.lo[a] >= std::ptrdiff_t(m[a]);
      if (hi[a] != lim_hi[a]) holds = holds && reach.hi[a] <= n - 3 && fg.hi[a] <= n - 1 - std::ptrdiff_t(m[a]);
      out_lo[a] = std::max<std::ptrdiff_t>(fg.lo[a] - std::ptrdiff_t(m[a]), 0);
      out_hi[a] = std::min<std::ptrdiff_t>(fg.hi[a] + std::ptrdiff_t(m[a]), n - 1);
    }
    if (!holds) {
      if (fg.empty()) throw Error("the repair left no foreground");
      continue;
    }
    WellComposedCrop out;
    // The scan's grid as img2wc --full-grid writes it (imgmesh::pad's origin).
    out.frame.origin = scan.world(-double(before[0]), -double(before[1]), -double(before[2]));
    Geometry full = scan;
    full.origin = out.frame.origin;
    Index3 at;  // the result's first voxel in the scan's grid, then in the full grid
    for (int a = 0; a < 3; ++a) {
      full.size[a] = scan.size[a] + before[a] + after[a];
      at[a] = lo[a] + out_lo[a];
      out.frame.index[a] = at[a] + std::ptrdiff_t(before[a]);
      out.frame.foreground.lo[a] = fg.lo[a] - out_lo[a];
      out.frame.foreground.hi[a] = fg.hi[a] - out_lo[a];
    }
    out.frame.size = full.size;
    Geometry g = full;
    for (int a = 0; a < 3; ++a) g.size[a] = std::size_t(out_hi[a] - out_lo[a] + 1);
    g.origin = full.world(double(out.frame.index[0]), double(out.frame.index[1]), double(out.frame.index[2]));
    BinaryImage image(g, 0);
    for (std::size_t z = 0; z < g.size[2]; ++z)
      for (std::size_t y = 0; y < g.size[1]; ++y)
        std::copy_n(&res.image(std::size_t(out_lo[0]), y + std::size_t(out_lo[1]), z + std::size_t(out_lo[2])),
                    g.size[0], &image(0, y, z));
    for (int a = 0; a < 3; ++a) {
      res.touched_lo[a] -= out_lo[a];
      res.touched_hi[a] -= out_lo[a];
    }
    res.image = std::move(image);
    res.padded_before = before;
    res.padded_after = after;
    res.input_voxels = scan.count();
    res.output = count_critical_configurations(res.image);
    out.result = std::move(res);
    return out;
  }
}

// ---- function_in_scan ----

bool placed_in_scan(const Geometry& crop, const ScanFrame& frame, float clamp) {
  // A scan beyond 2^31 voxels would cost the crop more than its box (the
  // block table and the mesher's cube bits cover the scan: 3/16 byte a
  // voxel): the crop alone then.
  bool in_scan = frame.present() && std::isfinite(clamp) &&
                 frame.size[0] * frame.size[1] * frame.size[2] <= (std::size_t(1) << 31);
  if (in_scan) {
    const std::array<std::size_t, 3> m = crop_margin(crop.spacing, clamp);
    for (int a = 0; a < 3; ++a) {
      const bool first = frame.index[a] == 0, last = std::size_t(frame.index[a]) + crop.size[a] == frame.size[a];
      in_scan = in_scan && (first || frame.foreground.lo[a] >= std::ptrdiff_t(m[a])) &&
                (last || std::ptrdiff_t(crop.size[a]) - 1 - frame.foreground.hi[a] >= std::ptrdiff_t(m[a]));
    }
  }
  return in_scan;
}

PartitionOfUnity function_in_scan(const Geometry& crop, const ScanFrame& frame, Vec3 d, float clamp,
                                  const SampleGrid::SliceReader& next_slice, bool* placed) {
  const bool in_scan = placed_in_scan(crop, frame, clamp);
  if (placed) *placed = in_scan;
  // The negative samples must lie in the frame's foreground box: the
  // margins above are measured from it.
  std::size_t z = 0;
  const std::size_t nx = crop.size[0], n = crop.size[0] * crop.size[1];
  auto checked = [&](float* slice) {
    next_slice(slice);
    if (frame.present())
      for (std::size_t i = 0; i < n; ++i)
        if (slice[i] < 0) {
          const std::ptrdiff_t c[3] = {std::ptrdiff_t(i % nx), std::ptrdiff_t(i / nx), std::ptrdiff_t(z)};
          for (int a = 0; a < 3; ++a)
            if (c[a] < frame.foreground.lo[a] || c[a] > frame.foreground.hi[a])
              throw Error("a foreground sample lies outside imgmesh_foreground_box");
        }
    ++z;
  };
  if (in_scan) return PartitionOfUnity::streamed(frame.scan(crop), frame.index, crop, d, clamp, checked);
  return PartitionOfUnity::streamed(crop, {0, 0, 0}, crop, d, clamp, checked);
}

} // namespace imgmesh
