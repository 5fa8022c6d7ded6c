// The labelling function of a well-composed label image X (issue 40, route
// 1), from the labels' chapter 6 functions f_L:
//   f_L    for a label L != 0: f of the indicator {X = L} (wc2implicit's
//          construction on the label's box plus the crop margin, clamped as
//          the meshers clamp it: crop.hpp), negative inside;
//   f_0    the background's: -f of the union {X != 0}. Where 0 meets a
//          label L alone, f_U = f_L there and 0|L is f_L^-1(0), implicit2mesh's
//          surface of L; no pocket of 0 opens between two touching labels
//          (f_0 is large there, the union's inside).
//   lambda 0 outside the box of voxel centres (X's outer layer is 0 after
//          img2wc --labels' growth); else, where some f_L < 0, the one of
//          highest rank among those (rank: 0 lowest, then from the most
//          voxels to the fewest, as the partition repair ranks labels: a thin
//          label keeps its own {f_L < 0}); elsewhere (a gap, every f_L >= 0)
//          argmin_L f_L (ties: the lower label).
//
// At a voxel centre f_L has the sign of {X = L} (f = g there, Thm 6.4.1):
// only the voxel's own label is negative, so lambda is the voxel's label.
// The interface between a and b is where lambda changes from a to b.
//
// A cube of the lattice of voxel centres whose 4x4x4 voxels around it (the
// samples f reads there: its corners, and its neighbours' within d <
// delta/5) all carry one label a is "pure": every f_L is a convex
// combination of trilinear interpolants of g_L, extended at most d beyond
// their cells, and g_L is 1-Lipschitz with |g_L| >= delta/2 at the centres,
// so f_a < 0 < f_L (L != a; f_0 through the union likewise) on the whole
// cube: lambda is a there. Segment walks skip pure cubes.
//
// Slope. Per axis m, f (f_L, and f_U) contracts g's samples with weights
// c (partition_of_unity.cpp's Stencil) that sum to 1: (1 - r, r) inside a
// cell, and within d_m <= delta_m / 5 of a plane where two cells blend
// (-(1 - eta) l, 1 + (1 - 2 eta) l, eta l), l = x / delta_m for the offset
// x from the plane, eta = pu_eta(u), u = (d - x) / (2 d). So d f / d x_m
// combines g's differences along m (each at most delta_m: g is
// 1-Lipschitz, clamped or not) with sum |dc| delta_m <= 1 + max_u
// |eta'(u) (1 - 2u)| = 1.6544, times each other axis's sum |c| <= 1 + 2
// (d / delta) max_u (1 - eta)(1 - 2u) <= 1 + 0.4 * 0.0780 = 1.0312 (the
// maxima of pu_eta's, numerically): |d f / d x_m| <= 1.6544 * 1.0312^2 =
// 1.7593 (outside the domain f is its nearest point's: no steeper), and
// |f(p) - f(q)| <= kLipschitz sum_m |p_m - q_m| (physical units along the
// grid's axes). Without reading f_L: where every sample f reads has g_L >=
// s, f_L >= s - 0.0166 (delta_0 + delta_1 + delta_2) (a blend undershoots
// its least sample by (1 - eta) |l| delta_m <= 0.078 * 0.2 delta_m, the
// next axis's rows 1.0312-Lipschitz): s = delta_min / 2 for a label
// carried by none of the voxels label_at reads (near_bound_), s = 1.5
// delta_min for one not among the cube's candidates (far_bound_) (the
// clamp T >= 2 |delta| keeps both), and beyond its crop f_L is T, larger. A walk's sample where lambda
// = a by f_a < 0 thus gives a margin (the least of -f_a and the bounds
// or values of the labels ranked above a) that lambda keeps for margin /
// (kLipschitz sum_m |dq_m| delta_m) of t: the walk reads no f there.
#pragma once
#include "image/grid.hpp"
#include "image/io.hpp"
#include "implicit/partition_of_unity.hpp"

#include <array>
#include <cstdint>
#include <memory>
#include <vector>

namespace imgmesh {

class LabelFunction {
public:
  // The bound on every f_L's slope (header): 1.7593, rounded up.
  static constexpr double kLipschitz = 1.77;

  // X well-composed (every label's indicator and the union's: img2wc
  // --labels' output); max_distance: the mesher's, for the clamp (world
  // units). Throws Error on a 2D image, an image without labels, or a label
  // whose indicator the chapter 5 repair would change.
  LabelFunction(const LabelImage& x, double max_distance, unsigned threads = 1);
  // X held in the narrowest type its labels fit (image/narrow_labels.hpp).
  LabelFunction(const NarrowLabelImage& x, double max_distance, unsigned threads = 1);
  ~LabelFunction();
  LabelFunction(LabelFunction&&) noexcept;

  // lambda at a world point.
  std::int32_t label(const Vec3& p) const;
  // f_L at a world point (a label of labels()).
  double value(std::int32_t label, const Vec3& p) const;

  // A change of lambda along a segment: t in [0, 1] and the labels before
  // and after it.
  struct Change {
    double t = 0;
    std::int32_t before = 0, after = 0;
  };
  // The changes of lambda along [a, b] (world), in order: lambda sampled at
  // steps of at most `step` voxels (the smallest spacing) inside cubes that
  // are not pure (those within a sample's margin, header, known without
  // reading f), each change then bisected to 1e-4 of a voxel. Changes
  // closer than `step` may be missed: the certificate decides. Stops after
  // `max_changes` (0: no limit). ends, when given: lambda(a) and lambda(b),
  // known to the caller.
  void changes(const Vec3& a, const Vec3& b, std::vector<Change>& out, double step = 0.25,
               std::size_t max_changes = 0, const std::int32_t* ends = nullptr) const;
  // The first change from a towards b, when lambda(a) != lambda(b) or some
  // change was found: its point.
  bool first_change(const Vec3& a, const Vec3& b, Vec3& x, double step = 0.25) const;

private:
  // The f values label_at read at a walk's sample (up to four; n = 0: none
  // read there), for the bisection that starts or ends at it.
  struct Seen {
    std::size_t n = 0;
    std::size_t k[4];
    double v[4];
    bool find(std::size_t label, double& value) const {
      for (std::size_t i = 0; i < n; ++i)
        if (k[i] == label) return value = v[i], true;
      return false;
    }
  };

public:
  // A change of lambda as the walk finds it, not yet placed: lambda is
  // `before` at the sample t0 and `after` at the next one, t1. place()
  // gives its t, the very t changes() gives (bisect's inputs kept), in
  // [t0, t1]: a caller that needs only where the change may be skips the
  // bisection.
  struct Bracket {
    double t0 = 0, t1 = 0;
    std::int32_t before = 0, after = 0;
    Seen s0, s1;  // the f values read at t0 and t1
  };
  // changes(), each change left as its bracket.
  void brackets(const Vec3& a, const Vec3& b, std::vector<Bracket>& out, double step = 0.25,
                std::size_t max_changes = 0, const std::int32_t* ends = nullptr) const;
  double place(const Vec3& a, const Vec3& b, const Bracket& c) const;

private:
  struct Function;
  template <class T> void build(const Image<T>& x, double max_distance, unsigned threads);
  std::size_t index_of(std::int32_t label) const;
  bool pure_cube(const Vec3& q, std::int32_t& label) const;
  // f of up to two labels (indices) at a point, read already (NaN: not).
  struct Known {
    std::size_t k[2];
    double v[2];
  };
  // q: p's continuous index; known: f values at p to use, not read again;
  // seen: where to keep those read.
  // margin: where given, a bound m >= 0 such that lambda is the label
  // returned wherever every f_L differs from its value at p by less than m
  // (0: none known).
  std::int32_t label_at(const Vec3& p, const Vec3& q, const Known* known = nullptr, Seen* seen = nullptr,
                        double* margin = nullptr) const;
  // q (a continuous index) in the box of voxel centres, where lambda is
  // not 0 by that rule alone.
  bool inside(const Vec3& q) const;
  // The walk along [a, b] (changes()'s), each change's bracket given to
  // found(bracket), which says whether to go on.
  template <class Found>
  void walk(const Vec3& a, const Vec3& b, double step, const std::int32_t* ends, Found found) const;
  // s0, s1: the f values read at t0 and t1.
  double bisect(const Vec3& a, const Vec3& d, double t0, double t1, std::int32_t before, std::int32_t after,
                const Seen& s0, const Seen& s1) const;

  Geometry grid_;
  std::vector<std::int32_t> labels_;  // ascending, 0 first
  std::vector<unsigned> rank_;  // per label index: 0 for the background, then fewest voxels highest
  std::vector<std::size_t> by_rank_, pos_;  // label indices from the highest rank down; each one's place there
  std::vector<std::unique_ptr<Function>> f_;  // per label (f_U for 0)
  // Per voxel its code: its label's place in by_rank_ (bits code_place_),
  // and code_pure_ when the cube whose lower corner it is (i < size - 1)
  // is pure (then that cube's voxels are of its label): a byte a voxel up
  // to 127 labels (codes8_), else two (codes16_); past 0x7fff labels
  // neither, and no shortcut.
  std::vector<std::uint8_t> codes8_;
  std::vector<std::uint16_t> codes16_;
  unsigned code_pure_ = 0, code_place_ = 0;  // the two parts' bits
  bool coded() const { return !codes8_.empty() || !codes16_.empty(); }
  unsigned code(std::size_t v) const { return codes8_.empty() ? codes16_[v] : codes8_[v]; }
  // Per cube the labels that can be lambda in it (bits: label index % 64),
  // in words of cand_bytes_ (the fewest that hold every label's bit, up to
  // 8), kept for the blocks of 4x4x4 cubes that hold a cube not pure
  // (label() answers in a pure cube without them): per block its slot + 1
  // in cand_ (0: none kept), and per bit its label indices.
  std::vector<std::uint8_t> cand_;
  std::vector<std::uint32_t> cand_block_;
  std::array<std::size_t, 3> cand_blocks_{0, 0, 0};
  std::size_t cand_bytes_ = 8;
  std::uint64_t candidates(std::size_t i, std::size_t j, std::size_t k) const;
  // Cube (i, j, k)'s block, and its word's index in cand_ (x fastest in a
  // block; slot: the block's entry, 1 or more).
  std::size_t cand_block_of(std::size_t i, std::size_t j, std::size_t k) const {
    return (k / 4 * cand_blocks_[1] + j / 4) * cand_blocks_[0] + i / 4;
  }
  static std::size_t cand_word_of(std::uint32_t slot, std::size_t i, std::size_t j, std::size_t k) {
    return std::size_t(slot - 1) * 64 + (k % 4) * 16 + (j % 4) * 4 + i % 4;
  }
  std::vector<std::vector<std::size_t>> bit_labels_;
  double min_spacing_ = 1;
  double near_bound_ = 0, far_bound_ = 0;
};

} // namespace imgmesh
