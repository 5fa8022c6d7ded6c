// Chapter 5's repair, linear in time and memory: the working image is one
// byte per voxel (the padded output itself), the queue R holds only points
// whose blocks became critical during the repair, and the points of the
// input's critical configurations come from the scan, in scan order, as they
// are reached (a point is re-checked when taken, so the order only changes
// which of equally good choices is made, never correctness).
#include "wellcomposed/well_composed.hpp"

#include "util/error.hpp"
#include "wellcomposed/critical_configuration.hpp"
#include "wellcomposed/label_grid.hpp"

#include <algorithm>
#include <array>
#include <string>
#include <cstring>
#include <iterator>
#include <random>
#include <vector>

namespace imgmesh {
namespace {

using wellcomposed_detail::candidate_sets;
using wellcomposed_detail::CandidateSets;
using wellcomposed_detail::kC1x;
using wellcomposed_detail::kC1y;
using wellcomposed_detail::kC1z;
using wellcomposed_detail::kC2;
using wellcomposed_detail::check_size;
using wellcomposed_detail::Padding;
using wellcomposed_detail::border_padding;

// Local copies of the block tables, so that lookups inline (and popcount
// needs no CPU extension).
struct LocalTables {
  std::uint8_t flags[256], ones[256];
  LocalTables() {
    for (unsigned c = 0; c < 256; ++c) {
      flags[c] = wellcomposed_detail::critical_configurations(std::uint8_t(c));
      ones[c] = std::uint8_t(__builtin_popcount(c));
    }
  }
};
const LocalTables kTables;  // built at start-up (critical_configuration.cpp's build on first use)
inline std::uint8_t critical_configurations(std::uint8_t code) { return kTables.flags[code]; }
inline int popcount(unsigned v) { return kTables.ones[v & 0xffu]; }

void add_counts(CriticalCounts& c, std::uint8_t flags) {
  c.c1 += popcount(flags & (kC1x | kC1y | kC1z));
  c.c2 += (flags & kC2) ? 1 : 0;
}


// Four rows of 8 bytes, all equal to 0 or all to 1: no block among them is
// critical (the common case, checked with four 64-bit loads).
bool uniform_rows(const std::uint8_t* a, const std::uint8_t* b, const std::uint8_t* c, const std::uint8_t* d) {
  std::uint64_t w[4];
  std::memcpy(&w[0], a, 8);
  std::memcpy(&w[1], b, 8);
  std::memcpy(&w[2], c, 8);
  std::memcpy(&w[3], d, 8);
  return w[0] == w[1] && w[0] == w[2] && w[0] == w[3] && (w[0] == 0 || w[0] == 0x0101010101010101ull);
}

// A byte image (0/1) whose border layers are background, so every block N(p)
// with p in [0, n-2]^3 lies inside and no critical configuration can involve
// the border or anything outside (the outside being background too).
struct WorkGrid {
  std::uint8_t* v;
  std::size_t n[3];
  std::size_t sy, sz;
  std::size_t off[8];  // offset of block bit k from r

  WorkGrid(std::uint8_t* data, std::size_t nx, std::size_t ny, std::size_t nz)
      : v(data), n{nx, ny, nz}, sy(nx), sz(nx * ny) {
    for (int k = 0; k < 8; ++k) off[k] = (k & 1) + ((k >> 1) & 1) * sy + ((k >> 2) & 1) * sz;
  }
  // The 2x2 rows of 8 voxels from i on are all 0 or all 1.
  bool uniform8(std::size_t i) const { return uniform_rows(v + i, v + i + sy, v + i + sz, v + i + sz + sy); }
  std::uint8_t code(std::size_t i) const {
    const std::uint8_t* p = v + i;
    return std::uint8_t(p[0] | p[1] << 1 | p[sy] << 2 | p[sy + 1] << 3 | p[sz] << 4 |
                        p[sz + 1] << 5 | p[sz + sy] << 6 | p[sz + sy + 1] << 7);
  }
};

// Rules (1)-(3) of section 5.2.4 with the queue R of Figure 5.2.
class Repair {
public:
  Repair(WorkGrid g, std::uint64_t seed, bool greedy)
      : g_(g), rng_(seed), greedy_(greedy), active_(g.n[1] * g.n[2], kGatedRow | kFinalRow) {}

  // Figures 5.1 and 5.2: scan D; every point whose N_x, N_y, N_z or N is
  // critical is eliminated, then R (points made critical by rule (3)) is
  // drained before the scan goes on.
  //
  // Greedy mode first makes a few passes that apply only choices removing
  // at least `gate` configurations per inserted point (so that the points
  // that serve several configurations at once are taken before their
  // configurations are repaired one by one), then the thesis's full pass.
  // Later passes visit only rows near critical blocks or changes.
  void run() {
    if (g_.n[0] < 2 || g_.n[1] < 2 || g_.n[2] < 2) return;
    if (greedy_)
      for (int gate : kGates) pass(gate);
    pass(0);
    if (greedy_) prune();
  }

  std::size_t changed = 0, created = 0;
  Index3 touched_lo{0, 0, 0}, touched_hi{-1, -1, -1};

private:
  static constexpr int kG = 27;  // blocks N(p), p in [r-1, r+1]^3: all that G(r) holds
  static constexpr int kPoint = 6;  // gains are in 1/6 configuration per point (|S| <= 3)

  // Passes with decreasing gates: 3, 2, then 1.5 configurations per point.
  static constexpr int kGates[] = {3 * kPoint, 2 * kPoint, 3 * kPoint / 2};

  // Row flags: kGatedRow = visit in the gated passes, kFinalRow = in the
  // last pass. A row keeps a flag only while it may hold a critical block
  // that pass would take.
  static constexpr std::uint8_t kGatedRow = 1, kFinalRow = 2;
  enum Outcome { kDone, kLeft, kHopeless };  // kHopeless: below every gate

  void pass(int gate) {
    const std::uint8_t want = gate > 0 ? kGatedRow : kFinalRow;
    for (std::size_t z = 0; z + 1 < g_.n[2]; ++z)
      for (std::size_t y = 0; y + 1 < g_.n[1]; ++y) {
        std::uint8_t& act = active_[y + g_.n[1] * z];
        if (!(act & want)) continue;
        act = gate > 0 ? 0 : std::uint8_t(act & ~kFinalRow);
        const std::size_t row = g_.sy * y + g_.sz * z;
        for (std::size_t x = 0; x + 1 < g_.n[0]; ++x) {
          const std::size_t r = row + x;
          if (x + 8 <= g_.n[0] && g_.uniform8(r)) {
            x += 6;  // blocks x .. x+6 lie in one colour
            continue;
          }
          if (!critical_configurations(g_.code(r))) continue;
          const Outcome o = eliminate(r, gate);
          if (o != kDone) {  // left for a later pass
            act |= o == kLeft ? kGatedRow | kFinalRow : kFinalRow;
            continue;
          }
          while (head_ < queue_.size()) eliminate(queue_[head_++], gate);
          queue_.clear();
          head_ = 0;
        }
      }
  }

  // G(r) = [r-1, r+2]^3 as 64 bits (bit x + 4y + 16z; outside the grid: 0),
  // and which of the 27 blocks N(p), p in [r-1, r+1]^3, lie in the grid
  // (the others touch the background border and are never critical).
  std::uint64_t load_grid(std::size_t r, std::uint32_t& valid) const {
    const std::ptrdiff_t c[3] = {std::ptrdiff_t(r % g_.sy), std::ptrdiff_t((r / g_.sy) % g_.n[1]),
                                 std::ptrdiff_t(r / g_.sz)};
    std::uint64_t grid = 0;
    if (c[0] >= 1 && c[1] >= 1 && c[2] >= 1 && std::size_t(c[0]) + 3 <= g_.n[0] &&
        std::size_t(c[1]) + 3 <= g_.n[1] && std::size_t(c[2]) + 3 <= g_.n[2]) {
      // Inside: 16 rows of 4 bytes (0/1), each gathered into 4 bits.
      const std::uint8_t* base = g_.v + r - 1 - g_.sy - g_.sz;
      for (int dz = 0; dz < 4; ++dz)
        for (int dy = 0; dy < 4; ++dy) {
          std::uint32_t w;
          std::memcpy(&w, base + std::size_t(dy) * g_.sy + std::size_t(dz) * g_.sz, 4);
          const std::uint64_t bits = ((std::uint64_t(w & 0x01010101u) * 0x01020408u) >> 24) & 0xfu;
          grid |= bits << (4 * dy + 16 * dz);
        }
      valid = (1u << kG) - 1;
      return grid;
    }
    for (int dz = 0; dz < 4; ++dz)
      for (int dy = 0; dy < 4; ++dy)
        for (int dx = 0; dx < 4; ++dx) {
          const std::ptrdiff_t x = c[0] + dx - 1, y = c[1] + dy - 1, z = c[2] + dz - 1;
          if (x < 0 || y < 0 || z < 0 || std::size_t(x) >= g_.n[0] || std::size_t(y) >= g_.n[1] ||
              std::size_t(z) >= g_.n[2])
            continue;
          if (g_.v[std::size_t(x) + g_.sy * std::size_t(y) + g_.sz * std::size_t(z)])
            grid |= std::uint64_t(1) << (dx + 4 * dy + 16 * dz);
        }
    valid = 0;
    for (int k = 0; k < kG; ++k) {
      const std::ptrdiff_t p[3] = {c[0] + k % 3 - 1, c[1] + (k / 3) % 3 - 1, c[2] + k / 9 - 1};
      bool in = true;
      for (int a = 0; a < 3; ++a) in = in && p[a] >= 0 && std::size_t(p[a]) + 1 < g_.n[a];
      if (in) valid |= 1u << k;
    }
    return grid;
  }
  // Flags of the 27 blocks of a loaded G(r).
  static void flags_of(std::uint64_t grid, std::uint32_t valid, std::uint8_t out[kG]) {
    for (int k = 0; k < kG; ++k) {
      const int p = k % 3 + 4 * ((k / 3) % 3) + 16 * (k / 9);
      const std::uint64_t w = grid >> p;
      const unsigned code = unsigned(w & 3u) | unsigned((w >> 4) & 3u) << 2 | unsigned((w >> 16) & 3u) << 4 |
                            unsigned((w >> 20) & 3u) << 6;
      out[k] = (valid >> k) & 1u ? critical_configurations(std::uint8_t(code)) : 0;
    }
  }
  // A set of block bits of N(r) as bits of G(r) (r itself is bit 21).
  static std::uint64_t in_grid(unsigned mask) {
    std::uint64_t m = 0;
    for (int k = 0; k < 8; ++k)
      if (mask & (1u << k)) m |= std::uint64_t(1) << (21 + (k & 1) + 4 * ((k >> 1) & 1) + 16 * ((k >> 2) & 1));
    return m;
  }
  std::size_t neighbour(std::size_t r, int k) const {
    const int dx = k % 3 - 1, dy = (k / 3) % 3 - 1, dz = k / 9 - 1;
    return std::size_t(std::ptrdiff_t(r) + dx + std::ptrdiff_t(g_.sy) * dy + std::ptrdiff_t(g_.sz) * dz);
  }
  void set(std::size_t r, unsigned mask, std::uint8_t colour) {
    for (int k = 0; k < 8; ++k)
      if (mask & (1u << k)) {
        const std::size_t i = r + g_.off[k];
        g_.v[i] = colour;
        const std::ptrdiff_t c[3] = {std::ptrdiff_t(i % g_.sy), std::ptrdiff_t((i / g_.sy) % g_.n[1]), std::ptrdiff_t(i / g_.sz)};
        for (int a = 0; a < 3; ++a) {
          touched_lo[a] = touched_hi[a] < touched_lo[a] ? c[a] : std::min(touched_lo[a], c[a]);
          touched_hi[a] = std::max(touched_hi[a], c[a]);
        }
      }
  }
  // Rows whose blocks may have changed: those of N(p), p in [r-1, r+1]^3.
  void touch(std::size_t r) {
    const std::size_t y = (r / g_.sy) % g_.n[1], z = r / g_.sz;
    for (std::size_t zz = z ? z - 1 : 0; zz <= z + 1 && zz + 1 < g_.n[2]; ++zz)
      for (std::size_t yy = y ? y - 1 : 0; yy <= y + 1 && yy + 1 < g_.n[1]; ++yy)
        active_[yy + g_.n[1] * zz] = kGatedRow | kFinalRow;
  }

  // Eliminates the configurations at r unless the chosen set gains less than
  // `gate` (then nothing changes).
  Outcome eliminate(std::size_t r, int gate) {
    const std::uint8_t code = g_.code(r);
    if (!critical_configurations(code)) return kDone;  // already eliminated by an earlier choice
    const CandidateSets& b = candidate_sets(code);
    std::uint8_t before[kG], after[kG];
    std::uint32_t valid;
    const std::uint64_t grid = load_grid(r, valid);
    flags_of(grid, valid, before);
    if (gate > 0) {
      // No set can eliminate more than all the configurations of G(r).
      int all = 0;
      for (int k = 0; k < kG; ++k) all += popcount(before[k]);
      if (all * kPoint < kGates[std::size(kGates) - 1]) return kHopeless;
      if (all * kPoint < gate) return kLeft;
    }
    // Partition B(r) into B1(r) (creates nothing) and B2(r). Greedy: within
    // the part a rule draws from, the draw is among the sets that eliminate
    // the most critical configurations of G(r) per inserted point, then
    // create the fewest: one well-chosen point often removes several.
    int created_by[6] = {}, gain[6] = {};
    int n1 = 0;
    for (int i = 0; i < b.count; ++i) {
      flags_of(grid | in_grid(b.sets[i]), valid, after);
      int removed = 0, made = 0;
      for (int k = 0; k < kG; ++k) {
        removed += popcount(before[k] & ~after[k]);
        made += popcount(after[k] & ~before[k]);
      }
      created_by[i] = made;
      if (made == 0) ++n1;
      gain[i] = removed * kPoint / popcount(b.sets[i]);
    }
    unsigned cand[6] = {};
    int nc = 0;
    long best = 0;
    for (int i = 0; i < b.count; ++i) {
      if (n1 > 0 && created_by[i] != 0) continue;  // rules (1), (2): B1(r) only
      const long score = greedy_ ? long(gain[i]) * 64 - created_by[i] : 0;
      if (nc == 0 || score > best) { best = score; nc = 0; }
      if (score == best) cand[nc++] = unsigned(i);
    }
    if (gate > 0 && gain[cand[0]] < gate) return kLeft;
    // Rule (1) when one candidate is left, else rules (2)/(3): at random.
    const unsigned pick = nc == 1 ? cand[0] : cand[rng_() % unsigned(nc)];
    set(r, b.sets[pick], 1);
    changed += std::size_t(popcount(b.sets[pick]));
    for (int k = 0; k < 8; ++k)
      if (b.sets[pick] & (1u << k)) inserted_.push_back(r + g_.off[k]);
    touch(r);
    if (n1 == 0) {
      // Rule (3): re-examine only G(r); queue every point whose N_x, N_y,
      // N_z or N became critical.
      created += std::size_t(created_by[pick]);
      flags_of(grid | in_grid(b.sets[pick]), valid, after);
      for (int k = 0; k < kG; ++k)
        if (after[k] & ~before[k]) queue_.push_back(neighbour(r, k));
    }
    return kDone;
  }

  WorkGrid g_;
  std::mt19937_64 rng_;
  bool greedy_;
  std::vector<std::uint8_t> active_;  // per row (y, z): may hold a critical block
  std::vector<std::size_t> queue_;    // R
  std::size_t head_ = 0;
  std::vector<std::size_t> inserted_;  // P, in insertion order

  // A point of P that later insertions made unnecessary goes back to the
  // background when none of the 8 blocks holding it becomes critical (only
  // those blocks see it). P only shrinks, so X stays a subset of X'.
  void prune() {
    for (std::size_t i : inserted_) {
      g_.v[i] = 0;
      bool ok = true;
      // Blocks inside the grid only: in 2D (two layers) a point of the
      // bottom layer has no block below it; that one, outside the grid and
      // background there, mirrors the block above, which is checked.
      const bool bottom = i < g_.sz;
      for (int k = 0; k < 8 && ok; ++k)
        if (!(bottom && (k & 4))) ok = !critical_configurations(g_.code(i - g_.off[k]));
      if (ok) --changed;
      else g_.v[i] = 1;
    }
    inserted_.clear();
  }
};

// Repair in one mode on a padded copy. Remove is the dual: complement, add,
// complement back (the border stays background in the result, since the
// complement's border is foreground and add never touches it).
WellComposedResult repair(const BinaryImage& in, const Padding& pad, RepairMode mode, std::uint64_t seed,
                          bool greedy, bool run = true) {
  WellComposedResult res;
  res.padded_before = pad.before;
  res.padded_after = pad.after;
  res.mode_used = mode;
  // Not a conditional expression: its const prvalue would be copied twice.
  if (pad.any()) res.image = imgmesh::pad(in, pad.before, pad.after, std::uint8_t(0));
  else res.image = in;
  BinaryImage& out = res.image;
  for (auto& v : out.data) v = v ? 1 : 0;
  const bool remove = mode == RepairMode::Remove;
  const std::size_t nx = out.size[0], ny = out.size[1];
  if (out.dimension == 2) {
    // A 2D image is the bottom layer of a two-layer grid whose top layer is
    // background: then only N_z(r) squares can be critical, the 2D analogue.
    std::vector<std::uint8_t> w(2 * nx * ny, 0);
    for (std::size_t i = 0; i < nx * ny; ++i) w[i] = remove ? out.data[i] ^ 1 : out.data[i];
    Repair rep(WorkGrid(w.data(), nx, ny, 2), seed, greedy);
    if (run) rep.run();
    for (std::size_t i = 0; i < nx * ny; ++i) out.data[i] = remove ? w[i] ^ 1 : w[i];
    res.changed = rep.changed;
    res.created = rep.created;
    res.touched_lo = rep.touched_lo;
    res.touched_hi = rep.touched_hi;
    return res;
  }
  if (remove)
    for (auto& v : out.data) v ^= 1;
  Repair rep(WorkGrid(out.data.data(), nx, ny, out.size[2]), seed, greedy);
  if (run) rep.run();
  if (remove)
    for (auto& v : out.data) v ^= 1;
  res.changed = rep.changed;
  res.created = rep.created;
  res.touched_lo = rep.touched_lo;
  res.touched_hi = rep.touched_hi;
  return res;
}

} // namespace

namespace wellcomposed_detail {

void check_size(const Geometry& g, const char* what) {
  if (g.dimension != 2 && g.dimension != 3)
    throw Error(std::string(what) + ": image must be 2D or 3D");
  if (g.dimension == 2 && g.size[2] != 1) throw Error(std::string(what) + ": 2D image with depth > 1");
  for (std::size_t s : g.size)
    if (s == 0 || s > (std::size_t(1) << 20))
      throw Error(std::string(what) + ": image size out of range");
  if (g.size[0] * g.size[1] > (std::size_t(1) << 40) / g.size[2])
    throw Error(std::string(what) + ": image too large");
}

} // namespace wellcomposed_detail

CriticalCounts count_critical_configurations(const BinaryImage& img) {
  check_size(img, "count_critical_configurations");
  if (img.data.size() != img.count()) throw Error("count_critical_configurations: image data size mismatch");
  CriticalCounts c;
  const std::size_t nx = img.size[0], ny = img.size[1], nz = img.size[2];
  // Blocks N(r) for r in [0, n-1]^3 with the outside as background: blocks
  // reaching below 0 have a background face or edge and are never critical.
  const std::vector<std::uint8_t> zero(nx + 1, 0);
  auto row = [&](std::size_t y, std::size_t z) -> const std::uint8_t* {
    return (y < ny && z < nz) ? &img.data[img.index(0, y, z)] : zero.data();
  };
  for (std::size_t z = 0; z < nz; ++z)
    for (std::size_t y = 0; y < ny; ++y) {
      const std::uint8_t* r0 = row(y, z);
      const std::uint8_t* r1 = row(y + 1, z);
      const std::uint8_t* r2 = row(y, z + 1);
      const std::uint8_t* r3 = row(y + 1, z + 1);
      auto column = [&](std::size_t x) {
        return unsigned(r0[x] != 0) | unsigned(r1[x] != 0) << 2 | unsigned(r2[x] != 0) << 4 |
               unsigned(r3[x] != 0) << 6;
      };
      unsigned left = column(0);
      for (std::size_t x = 0; x < nx; ++x) {
        if (x + 8 <= nx && uniform_rows(r0 + x, r1 + x, r2 + x, r3 + x)) {
          x += 6;  // blocks x .. x+6 lie in one colour
          left = column(x + 1);
          continue;
        }
        const unsigned right = x + 1 < nx ? column(x + 1) : 0u;
        const unsigned code = left | right << 1;
        if (code && code != 0xffu) add_counts(c, critical_configurations(std::uint8_t(code)));
        left = right;
      }
    }
  return c;
}

bool is_well_composed(const BinaryImage& img) { return count_critical_configurations(img).total() == 0; }

WellComposedResult make_well_composed(const BinaryImage& in, const WellComposedOptions& opt) {
  check_size(in, "make_well_composed");
  if (in.data.size() != in.count()) throw Error("make_well_composed: image data size mismatch");
  const CriticalCounts counts = count_critical_configurations(in);
  const Padding pad = border_padding(in);
  WellComposedResult res;
  if (opt.mode == RepairMode::Min) {
    WellComposedResult add = repair(in, pad, RepairMode::Add, opt.seed, opt.greedy, opt.repair);
    if (add.changed == 0) {
      res = std::move(add);
    } else {
      WellComposedResult rem = repair(in, pad, RepairMode::Remove, opt.seed, opt.greedy, opt.repair);
      // Both repairs' reach: the choice depends on both (add set voxels).
      Index3 lo = add.touched_lo, hi = add.touched_hi;
      if (rem.touched_lo[0] <= rem.touched_hi[0])
        for (int a = 0; a < 3; ++a) {
          lo[a] = std::min(lo[a], rem.touched_lo[a]);
          hi[a] = std::max(hi[a], rem.touched_hi[a]);
        }
      res = rem.changed < add.changed ? std::move(rem) : std::move(add);
      res.touched_lo = lo;
      res.touched_hi = hi;
    }
  } else {
    res = repair(in, pad, opt.mode, opt.seed, opt.greedy, opt.repair);
  }
  res.input = counts;
  res.options = opt;
  res.input_voxels = in.count();
  res.output = count_critical_configurations(res.image);
  return res;
}

namespace {
const char* mode_name(RepairMode m) {
  return m == RepairMode::Add ? "add" : m == RepairMode::Remove ? "remove" : "min";
}
std::vector<unsigned long long> triple(const std::array<std::size_t, 3>& a) { return {a[0], a[1], a[2]}; }
} // namespace

Json WellComposedResult::to_json() const {
  Json j = Json::object();
  j["dimension"] = image.dimension;
  j["voxels"] = input_voxels;
  j["mode"] = mode_name(options.mode);
  j["mode_used"] = mode_name(mode_used);
  j["seed"] = static_cast<unsigned long long>(options.seed);
  j["rules"] = options.greedy ? "greedy" : "thesis";
  j["c1"] = input.c1;
  j["c2"] = input.c2;
  j["changed"] = changed;
  const std::size_t m = input.total();
  j["ratio"] = m ? double(changed) / double(m) : 0.0;
  j["created"] = created;
  j["output_size"] = triple(image.size);
  j["padded_before"] = triple(padded_before);
  j["padded_after"] = triple(padded_after);
  j["output_c1"] = output.c1;
  j["output_c2"] = output.c2;
  j["well_composed"] = output.total() == 0;
  return j;
}

std::string WellComposedResult::failed_guarantee() const {
  if (output.total() == 0) return "";
  return "output is NOT well-composed (" + std::to_string(output.total()) + " critical configurations left)";
}

WellComposedCheck check_well_composed(const BinaryImage& img) {
  WellComposedCheck c;
  c.dimension = img.dimension;
  c.voxels = img.count();
  c.counts = count_critical_configurations(img);
  return c;
}

Json WellComposedCheck::to_json() const {
  Json j = Json::object();
  j["dimension"] = dimension;
  j["voxels"] = voxels;
  j["c1"] = counts.c1;
  j["c2"] = counts.c2;
  j["well_composed"] = counts.total() == 0;
  return j;
}

} // namespace imgmesh
