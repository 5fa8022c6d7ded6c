#include "conforming/label_function.hpp"

#include "implicit/crop.hpp"
#include "implicit/implicit_file.hpp"
#include "util/error.hpp"
#include "wellcomposed/well_composed.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <string>
#include <type_traits>

namespace imgmesh {

struct LabelFunction::Function {
  PartitionOfUnity f;
  double sign = 1;  // -1: the background's, -f of the union
  Vec3 lo{0, 0, 0}, hi{0, 0, 0};  // its crop's box, in X's continuous indices (outside: f > 0, not read)
};

namespace {

// The label's (or, label < 0, the union's) indicator made a function as
// seg2mesh makes a label's: its box plus the crop margin, f clamped and
// placed in X's grid.
template <class T>
PartitionOfUnity indicator_function(const Image<T>& x, std::int32_t label, const VoxelBox& box, double max_distance,
                                    unsigned threads) {
  WellComposedCrop wc = well_composed_crop(
      x, box,
      [&](std::size_t y, std::size_t z, std::size_t x0, std::size_t n, std::uint8_t* row) {
        const T* v = &x(x0, y, z);
        for (std::size_t i = 0; i < n; ++i) row[i] = label < 0 ? v[i] != 0 : std::int32_t(v[i]) == label;
      },
      WellComposedOptions{});
  if (wc.result.changed != 0)
    throw Error(label < 0 ? std::string("the labels' union is not well-composed (repair it: img2wc --labels all)")
                          : "label " + std::to_string(label) +
                                " is not well-composed (repair the map: img2wc --labels all)");
  wc.frame.foreground = foreground_box(wc.result.image);
  // Blocks: every label's f is placed in the whole scan, where dense
  // samples would cost the scan's floats a label (650 MB for the 100
  // organs of a 128x128x100 body map), blocks the label's box.
  return implicit_in_scan(wc.result.image, wc.frame, PartitionOfUnity::clamp_for(wc.result.image, max_distance), threads,
                          nullptr, SampleGrid::kBandBytes, SampleGrid::Storage::blocks);
}

// Along one axis, each voxel's value replaced by op over the window
// [i + lo, i + hi] (beyond the grid: `outside`).
template <class T, class Op>
void window(const Geometry& g, int axis, int lo, int hi, T outside, std::vector<T>& v, Op op) {
  const std::size_t n = g.size[axis];
  const std::size_t stride = axis == 0 ? 1 : axis == 1 ? g.size[0] : g.size[0] * g.size[1];
  std::vector<T> line(n);
  const std::size_t lines = g.count() / n;
  for (std::size_t l = 0; l < lines; ++l) {
    const std::size_t base = axis == 0 ? l * g.size[0]
                             : axis == 1 ? (l % g.size[0]) + (l / g.size[0]) * g.size[0] * g.size[1]
                                         : l;
    for (std::size_t i = 0; i < n; ++i) line[i] = v[base + i * stride];
    for (std::size_t i = 0; i < n; ++i) {
      T r = line[i];
      for (std::ptrdiff_t k = std::ptrdiff_t(i) + lo; k <= std::ptrdiff_t(i) + hi; ++k)
        r = op(r, k >= 0 && std::size_t(k) < n ? line[std::size_t(k)] : outside);
      v[base + i * stride] = r;
    }
  }
}

// The candidates' words (below) of a block of 4x4x4 cubes, from its lower
// cube (i0, j0, k0), x fastest: per cube the OR over the voxels within
// [-2, 3] of it per axis (beyond the grid: label 0's bit) of their label's
// bit, k % 64 for label index k (W holds every label up to 64). The
// block's 9x9x9 voxels, narrowed one axis at a time; a block at a time,
// not the scan's words (8 bytes a voxel past 32 labels: 256 MB on
// body.mha).
template <class W, class T>
void block_candidates(const Image<T>& x, const std::vector<std::int32_t>& labels, std::size_t i0, std::size_t j0,
                      std::size_t k0, W out[64]) {
  constexpr int kN = 9;  // voxels per axis: 4 cubes and the window's 5 more
  W a[kN][kN][kN], b[kN][kN][4], c[kN][4][4];
  std::int32_t last = 0;
  W bit = 1;
  for (int z = 0; z < kN; ++z)
    for (int y = 0; y < kN; ++y)
      for (int i = 0; i < kN; ++i) {
        const std::ptrdiff_t vx = std::ptrdiff_t(i0) + i - 2, vy = std::ptrdiff_t(j0) + y - 2, vz = std::ptrdiff_t(k0) + z - 2;
        const std::int32_t v = std::int32_t(x.at(vx, vy, vz));
        if (v != last) {
          last = v;
          bit = W(W(1) << (std::size_t(std::lower_bound(labels.begin(), labels.end(), v) - labels.begin()) % 64));
        }
        a[z][y][i] = v == 0 ? W(1) : bit;
      }
  auto or6 = [](auto get) {  // the window [-2, 3] along an axis
    W r = 0;
    for (int d = 0; d < 6; ++d) r = W(r | get(d));
    return r;
  };
  for (int z = 0; z < kN; ++z)
    for (int y = 0; y < kN; ++y)
      for (int i = 0; i < 4; ++i) b[z][y][i] = or6([&](int d) { return a[z][y][i + d]; });
  for (int z = 0; z < kN; ++z)
    for (int j = 0; j < 4; ++j)
      for (int i = 0; i < 4; ++i) c[z][j][i] = or6([&](int d) { return b[z][j + d][i]; });
  for (int k = 0; k < 4; ++k)
    for (int j = 0; j < 4; ++j)
      for (int i = 0; i < 4; ++i) out[(k * 4 + j) * 4 + i] = or6([&](int d) { return c[k + d][j][i]; });
}

} // namespace

LabelFunction::~LabelFunction() = default;
LabelFunction::LabelFunction(LabelFunction&&) noexcept = default;

LabelFunction::LabelFunction(const LabelImage& x, double max_distance, unsigned threads) : grid_(x.geometry()) {
  build(x, max_distance, threads);
}

LabelFunction::LabelFunction(const NarrowLabelImage& x, double max_distance, unsigned threads) : grid_(x.geometry()) {
  x.visit([&](const auto& im) { build(im, max_distance, threads); });
}

template <class T> void LabelFunction::build(const Image<T>& x, double max_distance, unsigned threads) {
  if (x.dimension != 3) throw Error("the labelling function needs a 3D label image");
  min_spacing_ = std::min({x.spacing[0], x.spacing[1], x.spacing[2]});
  // The bounds of f_L where label_at reads none of L's voxels (header).
  const double overshoot = 0.0166 * (x.spacing[0] + x.spacing[1] + x.spacing[2]);
  near_bound_ = std::max(0.0, 0.5 * min_spacing_ - overshoot);
  far_bound_ = std::max(0.0, 1.5 * min_spacing_ - overshoot);
  // Each label's box, and the union's.
  std::vector<std::int32_t> present;
  std::vector<std::size_t> counts;
  std::vector<VoxelBox> boxes;
  VoxelBox all;
  for (std::size_t z = 0; z < x.size[2]; ++z)
    for (std::size_t y = 0; y < x.size[1]; ++y)
      for (std::size_t i = 0; i < x.size[0]; ++i) {
        const std::int32_t v = std::int32_t(x(i, y, z));
        if (v == 0) continue;
        auto it = std::lower_bound(present.begin(), present.end(), v);
        const std::size_t k = std::size_t(it - present.begin());
        if (it == present.end() || *it != v) {
          present.insert(it, v);
          counts.insert(counts.begin() + std::ptrdiff_t(k), 0);
          boxes.insert(boxes.begin() + std::ptrdiff_t(k), VoxelBox());
        }
        ++counts[k];
        boxes[k].add(std::ptrdiff_t(i), std::ptrdiff_t(y), std::ptrdiff_t(z));
        all.add(std::ptrdiff_t(i), std::ptrdiff_t(y), std::ptrdiff_t(z));
      }
  if (present.empty()) throw Error("the label image has no label (every voxel is 0)");
  labels_.push_back(0);
  labels_.insert(labels_.end(), present.begin(), present.end());
  // Ranks: 0 lowest, then from the most voxels to the fewest (ties: the
  // larger label higher), as the partition repair ranks them by default.
  {
    std::vector<std::size_t> order(present.size());
    for (std::size_t k = 0; k < order.size(); ++k) order[k] = k;
    std::stable_sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) { return counts[a] > counts[b]; });
    rank_.assign(labels_.size(), 0);
    for (std::size_t r = 0; r < order.size(); ++r) rank_[order[r] + 1] = unsigned(r + 1);
    by_rank_.resize(labels_.size());
    for (std::size_t k = 0; k < labels_.size(); ++k) by_rank_[labels_.size() - 1 - rank_[k]] = k;
    pos_.resize(labels_.size());
    for (std::size_t r = 0; r < by_rank_.size(); ++r) pos_[by_rank_[r]] = r;
  }
  const auto margin = crop_margin(x.geometry());
  auto make = [&](std::int32_t label, const VoxelBox& box, double sign) {
    auto fn = std::make_unique<Function>(Function{indicator_function(x, label, box, max_distance, threads), sign, {}, {}});
    for (int i = 0; i < 3; ++i) {
      fn->lo[i] = double(box.lo[i]) - double(margin[i]);
      fn->hi[i] = double(box.hi[i]) + double(margin[i]);
    }
    f_.push_back(std::move(fn));
  };
  make(-1, all, -1);
  for (std::size_t k = 0; k < present.size(); ++k) make(present[k], boxes[k], 1);
  // Per voxel its label's place by rank, and whether the cube at it is
  // pure (min == max over the 4x4x4 voxels around: window [-1, 2] per
  // axis, 0 beyond the grid).
  if (labels_.size() <= 0x7fff && x.size[0] > 1 && x.size[1] > 1 && x.size[2] > 1) {
    std::vector<T> lo(x.data), hi(x.data);
    for (int axis = 0; axis < 3; ++axis) {
      window(x, axis, -1, 2, T(0), lo, [](T a, T b) { return std::min(a, b); });
      window(x, axis, -1, 2, T(0), hi, [](T a, T b) { return std::max(a, b); });
    }
    const bool narrow = labels_.size() <= 0x7f;
    code_pure_ = narrow ? 0x80 : 0x8000;
    code_place_ = code_pure_ - 1;
    auto fill = [&](auto& codes) {
      codes.resize(x.count());
      std::int32_t last = 0;
      unsigned place = unsigned(pos_[0]);
      for (std::size_t v = 0; v < x.count(); ++v) {
        if (std::int32_t(x.data[v]) != last) {
          last = std::int32_t(x.data[v]);
          place = unsigned(pos_[std::size_t(std::lower_bound(labels_.begin(), labels_.end(), last) - labels_.begin())]);
        }
        codes[v] = static_cast<std::remove_reference_t<decltype(codes[v])>>(place | (lo[v] == hi[v] ? code_pure_ : 0));
      }
    };
    if (narrow) fill(codes8_);
    else fill(codes16_);
  }
  // Candidates: a label whose voxels all lie beyond the 6x6x6 voxels around
  // a cube (window [-2, 3]) has g >= 1.5 voxels at every sample f reads in
  // it, so f >= 1.3 voxels there (extension by d <= delta / 5, slope at
  // most a voxel a voxel), where the label of the voxel holding the point
  // has f under that: only the labels near a cube compete in it. Bit k % 64
  // stands for label index k (a superset past 64 labels).
  cand_bytes_ = labels_.size() <= 8 ? 1 : labels_.size() <= 16 ? 2 : labels_.size() <= 32 ? 4 : 8;
  for (int a = 0; a < 3; ++a) cand_blocks_[std::size_t(a)] = (x.size[a] + 3) / 4;
  cand_block_.assign(cand_blocks_[0] * cand_blocks_[1] * cand_blocks_[2], 0);
  std::uint32_t slots = 0;
  for (std::size_t k = 0; k < x.size[2]; ++k)
    for (std::size_t j = 0; j < x.size[1]; ++j)
      for (std::size_t i = 0; i < x.size[0]; ++i) {
        std::uint32_t& slot = cand_block_[cand_block_of(i, j, k)];
        if (slot == 0 && !(coded() && (code(x.index(i, j, k)) & code_pure_))) slot = ++slots;
      }
  auto keep = [&](auto word) {
    using W = decltype(word);
    cand_.assign(std::size_t(slots) * 64 * sizeof(W), 0);
    W words[64];
    for (std::size_t bk = 0; bk < cand_blocks_[2]; ++bk)
      for (std::size_t bj = 0; bj < cand_blocks_[1]; ++bj)
        for (std::size_t bi = 0; bi < cand_blocks_[0]; ++bi) {
          const std::uint32_t slot = cand_block_[(bk * cand_blocks_[1] + bj) * cand_blocks_[0] + bi];
          if (slot == 0) continue;
          block_candidates(x, labels_, 4 * bi, 4 * bj, 4 * bk, words);
          for (std::size_t k = 4 * bk; k < std::min(4 * bk + 4, x.size[2]); ++k)  // the grid's voxels of the block
            for (std::size_t j = 4 * bj; j < std::min(4 * bj + 4, x.size[1]); ++j)
              for (std::size_t i = 4 * bi; i < std::min(4 * bi + 4, x.size[0]); ++i)
                std::memcpy(cand_.data() + cand_word_of(slot, i, j, k) * sizeof(W), &words[(k % 4 * 4 + j % 4) * 4 + i % 4],
                            sizeof(W));
        }
  };
  switch (cand_bytes_) {
  case 1: keep(std::uint8_t()); break;
  case 2: keep(std::uint16_t()); break;
  case 4: keep(std::uint32_t()); break;
  default: keep(std::uint64_t());
  }
  bit_labels_.resize(64);
  for (std::size_t k = 0; k < labels_.size(); ++k) bit_labels_[k % 64].push_back(k);
}

// A block not kept holds only pure cubes, where label() does not ask: all
// labels there (a superset) all the same.
std::uint64_t LabelFunction::candidates(std::size_t i, std::size_t j, std::size_t k) const {
  const std::uint32_t slot = cand_block_[cand_block_of(i, j, k)];
  if (slot == 0) return ~std::uint64_t(0);
  const std::uint8_t* p = cand_.data() + cand_word_of(slot, i, j, k) * cand_bytes_;
  switch (cand_bytes_) {
  case 1: return p[0];
  case 2: { std::uint16_t w; std::memcpy(&w, p, 2); return w; }
  case 4: { std::uint32_t w; std::memcpy(&w, p, 4); return w; }
  default: { std::uint64_t w; std::memcpy(&w, p, 8); return w; }
  }
}

std::size_t LabelFunction::index_of(std::int32_t label) const {
  const auto it = std::lower_bound(labels_.begin(), labels_.end(), label);
  if (it == labels_.end() || *it != label) throw Error("internal: no such label in the labelling function");
  return std::size_t(it - labels_.begin());
}

double LabelFunction::value(std::int32_t label, const Vec3& p) const {
  const Function& fn = *f_[index_of(label)];
  return fn.sign * fn.f.value(p);
}

std::int32_t LabelFunction::label(const Vec3& p) const { return label_at(p, grid_.continuous_index(p)); }

std::int32_t LabelFunction::label_at(const Vec3& p, const Vec3& q, const Known* known, Seen* seen,
                                     double* margin) const {
  if (margin) *margin = 0;
  if (!inside(q)) return 0;
  std::size_t c[3];
  for (int i = 0; i < 3; ++i) c[i] = std::min(std::size_t(q[i]), grid_.size[i] - (grid_.size[i] > 1 ? 2 : 1));
  // The voxels every f reads at p: per axis the cube's two and, within a
  // quarter voxel of a plane (where two cells may blend: d <= delta / 5),
  // the one beyond it. A label none of them carries has f > 0 at p, by the
  // pure cubes' argument (header) at p alone; all of one label, lambda is
  // that label, without evaluating an f (most samples of a segment near an
  // interface). near: the places by rank (% 64) of the labels they carry.
  std::uint64_t near = ~std::uint64_t(0);
  if (coded()) {
    std::size_t lo[3], hi[3];
    for (int i = 0; i < 3; ++i) {
      const double r = q[i] - double(c[i]);
      lo[i] = r < 0.25 && c[i] > 0 ? c[i] - 1 : c[i];
      hi[i] = r > 0.75 && c[i] + 2 < grid_.size[i] ? c[i] + 2 : c[i] + 1;
    }
    const unsigned first = code(grid_.index(lo[0], lo[1], lo[2])) & code_place_;
    bool one = true;
    near = 0;
    for (std::size_t z = lo[2]; z <= hi[2]; ++z)
      for (std::size_t y = lo[1]; y <= hi[1]; ++y)
        for (std::size_t i = lo[0]; i <= hi[0]; ++i) {
          const unsigned place = code(grid_.index(i, y, z)) & code_place_;
          one = one && place == first;
          near |= std::uint64_t(1) << (place % 64);
        }
    if (one) return labels_[by_rank_[first]];
  }
  // First those labels in decreasing rank: the first negative one is lambda
  // (the rank rule). When none is (a gap, every f >= 0), argmin over all
  // the cube's candidates (ties: the lower label); without `near`, all of
  // them in decreasing rank.
  const std::uint64_t cand = candidates(c[0], c[1], c[2]);
  auto in_crop = [&](std::size_t k) {
    const Function& fn = *f_[k];
    return fn.sign < 0 || (q[0] >= fn.lo[0] && q[0] <= fn.hi[0] && q[1] >= fn.lo[1] && q[1] <= fn.hi[1] &&
                           q[2] >= fn.lo[2] && q[2] <= fn.hi[2]);  // beyond: f_L >= its clamp > 0
  };
  std::size_t best = 0;
  double fbest = std::numeric_limits<double>::infinity();
  double read = 0;  // the f evaluate read last
  auto evaluate = [&](std::size_t k) {
    const Function& fn = *f_[k];
    double v;
    if (known && known->k[0] == k && !std::isnan(known->v[0])) v = known->v[0];
    else if (known && known->k[1] == k && !std::isnan(known->v[1])) v = known->v[1];
    else v = fn.sign * fn.f.value(p);
    if (seen && seen->n < 4) seen->k[seen->n] = k, seen->v[seen->n++] = v;
    if (v < fbest || (v == fbest && k < best)) fbest = v, best = k;
    read = v;
    return v < 0;
  };
  if (~near != 0) {
    if (labels_.size() <= 64) {
      // The least f of the labels ranked above, read (all >= 0).
      double above = std::numeric_limits<double>::infinity();
      for (std::uint64_t m = near; m; m &= m - 1) {
        const std::size_t k = by_rank_[std::size_t(__builtin_ctzll(m))];
        if (!(cand >> (k % 64) & 1) || !in_crop(k)) continue;
        if (!evaluate(k)) {
          above = std::min(above, read);
          continue;
        }
        if (margin) {
          // lambda stays k while f_k < 0 and every label ranked above
          // has f >= 0 (the rank rule); those not read: a candidate here
          // that no voxel read carries, f >= near_bound_; the others
          // (not candidates, beyond their crop) f >= far_bound_.
          double mk = std::min({-read, above, far_bound_});
          for (std::uint64_t c = cand; c; c &= c - 1) {
            const std::size_t j = std::size_t(__builtin_ctzll(c));
            if (j < labels_.size() && rank_[j] > rank_[k] && !(near >> (pos_[j] % 64) & 1) && in_crop(j))
              mk = std::min(mk, near_bound_);
          }
          *margin = std::max(0.0, mk);
        }
        return labels_[k];
      }
    } else {
      std::vector<std::size_t> ks;
      for (std::uint64_t m = near; m; m &= m - 1)
        for (std::size_t r = std::size_t(__builtin_ctzll(m)); r < by_rank_.size(); r += 64)
          if (cand >> (by_rank_[r] % 64) & 1) ks.push_back(by_rank_[r]);
      std::sort(ks.begin(), ks.end(), [&](std::size_t a, std::size_t b) { return pos_[a] < pos_[b]; });
      for (const std::size_t k : ks)
        if (in_crop(k) && evaluate(k)) return labels_[k];
    }
  }
  std::size_t rest[64], n = 0;
  std::vector<std::size_t> more;  // past 64 candidates (maps of more than 64 labels)
  for (std::uint64_t m = cand; m; m &= m - 1)
    for (const std::size_t k : bit_labels_[std::size_t(__builtin_ctzll(m))]) {
      if ((near >> (pos_[k] % 64) & 1) && ~near != 0) continue;  // evaluated above
      if (!in_crop(k)) continue;
      if (n < 64) rest[n++] = k;
      else more.push_back(k);
    }
  std::size_t* first = rest;
  std::size_t* last = rest + n;
  if (!more.empty()) {
    more.insert(more.begin(), rest, rest + n);
    first = more.data(), last = more.data() + more.size();
  }
  std::sort(first, last, [&](std::size_t a, std::size_t b) { return rank_[a] > rank_[b]; });
  for (const std::size_t* it = first; it != last; ++it)
    if (evaluate(*it)) return labels_[*it];
  return labels_[best];
}

bool LabelFunction::inside(const Vec3& q) const {
  for (int i = 0; i < 3; ++i)
    if (!(q[i] >= 0 && q[i] <= double(grid_.size[i] - 1))) return false;
  return true;
}

bool LabelFunction::pure_cube(const Vec3& q, std::int32_t& label) const {
  if (!coded()) return false;
  std::size_t c[3];
  for (int i = 0; i < 3; ++i) {
    if (!(q[i] >= 0 && q[i] < double(grid_.size[i] - 1))) return false;
    c[i] = std::size_t(q[i]);
  }
  const unsigned u = code(grid_.index(c[0], c[1], c[2]));
  if (!(u & code_pure_)) return false;
  label = labels_[by_rank_[u & code_place_]];
  return true;
}

// A change's place along a segment: within this many voxels (the mesh's
// vertices need no more; 1e-6 took a third more of f's evaluations).
constexpr double kChangeTolerance = 1e-4;

double LabelFunction::bisect(const Vec3& a, const Vec3& d, double t0, double t1, std::int32_t before,
                             std::int32_t after, const Seen& s0, const Seen& s1) const {
  const double len = std::sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]) / min_spacing_;  // voxels
  auto at = [&](double t) { return Vec3{a[0] + t * d[0], a[1] + t * d[1], a[2] + t * d[2]}; };
  // Between `before` and `after` alone lambda is the higher ranked one (hi)
  // where f_hi < max(0, f_lo) (negative, or the argmin in a gap), so it
  // changes where h = f_hi - max(0, f_lo) (its sign turned to make before
  // negative) does: regula falsi (Illinois) on h, f_lo read only where
  // f_hi >= 0, then lambda checked on both sides of the root, with the f
  // already read there; else (a third label between) bisection on lambda.
  const std::size_t kb = index_of(before), ka = index_of(after);
  const bool before_high = rank_[kb] > rank_[ka];
  const std::size_t fh_index = before_high ? kb : ka, fl_index = before_high ? ka : kb;
  const Function& fh = *f_[fh_index];
  const Function& fl = *f_[fl_index];
  Known klo{{fh_index, fl_index}, {NAN, NAN}}, khi = klo;
  // At t0 and t1 (the walk's samples) the f values the walk read there.
  auto h = [&](double t, Known& k, const Seen& s) {
    const Vec3 p = at(t);
    double vh, vl;
    if (!s.find(fh_index, vh)) vh = fh.sign * fh.f.value(p);
    k.v[0] = vh, k.v[1] = NAN;
    double r = vh;
    if (vh >= 0) {
      if (!s.find(fl_index, vl)) vl = fl.sign * fl.f.value(p);
      k.v[1] = vl;
      r = vh - std::max(0.0, vl);
      // On the root itself lambda's ties decide (0 is not negative; equal
      // in a gap: the lower label), as label() will.
      if (r == 0) r = vl < 0 || (vh == vl && fl_index < fh_index) ? 1e-300 : -1e-300;
    }
    return before_high ? r : -r;
  };
  double lo = t0, hi = t1;
  double hlo = h(lo, klo, s0), hhi = h(hi, khi, s1);
  if (hlo < 0 && hhi > 0) {
    Known kt = klo;
    int side = 0;
    for (int it = 0; it < 60 && (hi - lo) * len > kChangeTolerance; ++it) {
      double t = (lo * hhi - hi * hlo) / (hhi - hlo);
      if (!(t > lo && t < hi)) t = 0.5 * (lo + hi);
      const double ht = h(t, kt, Seen());
      if (ht < 0) {
        lo = t, hlo = ht, klo = kt;
        if (side == -1) hhi *= 0.5;
        side = -1;
      } else {
        hi = t, hhi = ht, khi = kt;
        if (side == 1) hlo *= 0.5;
        side = 1;
      }
    }
    const Vec3 plo = at(lo), phi = at(hi);
    if (label_at(plo, grid_.continuous_index(plo), &klo) == before &&
        label_at(phi, grid_.continuous_index(phi), &khi) == after)
      return 0.5 * (lo + hi);
  }
  while ((t1 - t0) * len > kChangeTolerance) {
    const double t = 0.5 * (t0 + t1);
    if (label(at(t)) == before) t0 = t;
    else t1 = t;
    if (!(t0 < t) && !(t < t1)) break;
  }
  return 0.5 * (t0 + t1);
}

template <class Found>
void LabelFunction::walk(const Vec3& a, const Vec3& b, double step, const std::int32_t* ends, Found found) const {
  const Vec3 d{b[0] - a[0], b[1] - a[1], b[2] - a[2]};
  const Vec3 qa = grid_.continuous_index(a), qb = grid_.continuous_index(b);
  const Vec3 dq{qb[0] - qa[0], qb[1] - qa[1], qb[2] - qa[2]};
  double len = 0;  // in voxels of the smallest spacing
  for (int i = 0; i < 3; ++i) len += d[i] * d[i];
  len = std::sqrt(len) / min_spacing_;
  if (!(len > 0) || !std::isfinite(len)) return;
  // The part of the segment within a voxel of the box of centres: beyond,
  // lambda is 0 (pure_cube's rule), like the segment's ends there.
  double t0 = 0, t1 = 1;
  for (int i = 0; i < 3; ++i) {
    const double lo = -1, hi = double(grid_.size[i]);
    if (dq[i] == 0) {
      if (qa[i] < lo || qa[i] > hi) t1 = -1;
      continue;
    }
    double s0 = (lo - qa[i]) / dq[i], s1 = (hi - qa[i]) / dq[i];
    if (s0 > s1) std::swap(s0, s1);
    t0 = std::max(t0, s0), t1 = std::min(t1, s1);
  }
  const double dt = step / len;
  // Along the segment |d f_L / dt| <= kLipschitz sum_m |dq_m| delta_m
  // (header): a sample whose label_at gave the margin m proves lambda
  // there until t + m / slope; the samples up to it are that label without
  // label_at (the same samples, so the same changes, only fewer f read).
  double slope = 0;
  for (int i = 0; i < 3; ++i) slope += std::fabs(dq[i]) * grid_.spacing[i];
  slope *= kLipschitz;
  double proven = -1;  // lambda is prev on [the last sample read, proven]
  std::int32_t prev = ends ? ends[0] : label(a);
  double tprev = 0;
  Seen seen_prev, seen;  // the f values read at tprev, and at the sample being visited
  auto visit = [&](double t, std::int32_t l, const Seen& s) {
    bool more = true;
    if (l != prev) {
      more = found(Bracket{tprev, t, prev, l, seen_prev, s});
      prev = l;
    }
    tprev = t;
    seen_prev = s;
    return more;
  };
  if (t0 <= t1) {
    double t = t0;
    while (t < t1) {
      const Vec3 q{qa[0] + t * dq[0], qa[1] + t * dq[1], qa[2] + t * dq[2]};
      std::int32_t l;
      if (pure_cube(q, l)) {
        if (!visit(t, l, Seen())) return;
        // To the cube's exit (or the end): lambda is l all along.
        double exit = t1;
        for (int i = 0; i < 3; ++i) {
          if (dq[i] == 0) continue;
          const double c = std::floor(q[i]);
          const double s = ((dq[i] > 0 ? c + 1 : c) - qa[i]) / dq[i];
          if (s > t) exit = std::min(exit, s);
        }
        if (!visit(std::min(exit, t1), l, Seen())) return;
        t = std::min(exit, t1) + 1e-12;
        continue;
      }
      seen.n = 0;
      if ((t < proven && inside(q)) || (t == 0 && ends)) {  // a's label: the caller's
        l = prev;
      } else {
        double m;
        l = label_at({a[0] + t * d[0], a[1] + t * d[1], a[2] + t * d[2]}, q, nullptr, &seen, &m);
        proven = m > 0 && slope > 0 ? t + m / slope : -1;
      }
      if (!visit(t, l, seen)) return;
      t += dt;
    }
  }
  visit(1, ends ? ends[1] : label(b), Seen());
}

void LabelFunction::brackets(const Vec3& a, const Vec3& b, std::vector<Bracket>& out, double step,
                             std::size_t max_changes, const std::int32_t* ends) const {
  out.clear();
  walk(a, b, step, ends, [&](const Bracket& c) {
    out.push_back(c);
    return max_changes == 0 || out.size() < max_changes;
  });
}

double LabelFunction::place(const Vec3& a, const Vec3& b, const Bracket& c) const {
  const Vec3 d{b[0] - a[0], b[1] - a[1], b[2] - a[2]};
  return bisect(a, d, c.t0, c.t1, c.before, c.after, c.s0, c.s1);
}

void LabelFunction::changes(const Vec3& a, const Vec3& b, std::vector<Change>& out, double step,
                            std::size_t max_changes, const std::int32_t* ends) const {
  out.clear();
  walk(a, b, step, ends, [&](const Bracket& c) {
    out.push_back({place(a, b, c), c.before, c.after});
    return max_changes == 0 || out.size() < max_changes;
  });
}

bool LabelFunction::first_change(const Vec3& a, const Vec3& b, Vec3& x, double step) const {
  std::vector<Change> c;
  changes(a, b, c, step, 1);
  if (c.empty()) return false;
  for (int i = 0; i < 3; ++i) x[i] = a[i] + c[0].t * (b[i] - a[i]);
  return true;
}

} // namespace imgmesh
