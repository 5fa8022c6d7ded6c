// The smooth implicit function f of thesis chapter 6: a partition of unity
// over the cells C_k between voxel centres, shape functions f_k = trilinear
// interpolants of the signed distance g (negative inside), weights built from
// the C-infinity step eta (6.7, 6.8; see doc/thesis-errata.md). Evaluation in world
// coordinates, O(1), thread safe, no allocation per call.
//
// Anisotropic grids: the cells are boxes delta_0 x delta_1 x delta_2 and the
// weight constant d is per axis (d_i); see partition_of_unity.cpp for why the
// argument of thesis 6.4 still holds axis by axis.
#pragma once
#include "image/grid.hpp"
#include "image/sample_grid.hpp"

#include <array>
#include <cstddef>
#include <cstdint>
#include <limits>

namespace imgmesh {

class PartitionOfUnity {
public:
  // g: signed distance to bdCA(X) at the voxel centres, physical units,
  // negative inside, with the image's world geometry (3D, >= 2 voxels per
  // axis, finite and nonzero values: throws Error otherwise). d: the
  // weight-function constant per axis; computed from g (thesis 6.3.2,
  // Prop. 6.4.1) when all components are <= 0. threads: for the O(|D|)
  // computation of d (0 = all cores). clamp: f is then built on g clamped
  // to [-clamp, clamp] (see clamp_for; d and the checks are g's own); the
  // samples far from S take no memory.
  explicit PartitionOfUnity(FloatImage g, Vec3 d = {0, 0, 0}, unsigned threads = 1,
                            float clamp = std::numeric_limits<float>::infinity(),
                            SampleGrid::Storage storage = SampleGrid::Storage::automatic);
  // The same from g's samples streamed a z-slice at a time (the implicit
  // function file as it is read, never whole): those of `box` placed from
  // index lo in `grid` (box's spacing and direction), every sample of grid
  // outside the box having g >= clamp (a crop's margin: crop_margin); box ==
  // grid and lo = 0 for a whole grid. d is given (the file's); the
  // constructor's checks, on the slices as they come, d's against the cells
  // near S (what the thesis's argument needs: see weight_constant), whose
  // largest L_k l_max() then gives.
  static PartitionOfUnity streamed(const Geometry& grid, const Index3& lo, const Geometry& box, Vec3 d, float clamp,
                                   const SampleGrid::SliceReader& next_slice,
                                   SampleGrid::Storage storage = SampleGrid::Storage::automatic);

  // The same f as PartitionOfUnity(g) then streamed() with its d (the
  // clamped f of a crop that seg2mesh builds), from g's samples a band of x
  // at a time (SampleGrid::BandReader): d computed as the constructor does
  // (weight_constant), the cells of the foreground's box grown by
  // weight_margin measured as the bands come; fg_lo, fg_hi: that box in
  // box's indices (every negative sample inside it; Error if not).
  static PartitionOfUnity from_bands(const Geometry& grid, const Index3& lo, const Geometry& box, const Index3& fg_lo,
                                     const Index3& fg_hi, float clamp, const SampleGrid::BandReader& next_band,
                                     unsigned threads = 1, SampleGrid::Storage storage = SampleGrid::Storage::automatic,
                                     std::size_t band_bytes = SampleGrid::kBandBytes);

  // The clamp T for a mesher that compares |f| with bounds up to 2 e (its
  // --max-distance e): the stencil of a point (its 2-3 samples per axis) has
  // diameter D = 2 |delta|, and T = (D + 2 e)(1 + 1e-6). Where f' (on
  // clamped g) differs from f, a sample v of the stencil has |g(v)| > T, so
  // every sample of it lies within D < |g(v)| of v, on v's side of
  // bdCA(X) (g is the distance to it), with |g| > T - D > 2 e; f and f',
  // convex combinations of those samples (clamped or not), both have v's
  // sign and exceed 2 e in absolute value. Hence f'^-1(0) = f^-1(0), f' has
  // f's sign everywhere, f' = f within T - D of S, and every test |f| <= 2 e
  // gives the same answer on f'. Clamping is 1-Lipschitz: g' keeps g_min,
  // and its L_max is at most g's, so d stays within the thesis's bound.
  static float clamp_for(const Geometry& grid, double e);

  // f at a world point inside the domain (the box of voxel centres). Outside
  // the domain, f (and its gradient) at the nearest point of the domain.
  double value(const Vec3& p) const;
  // f and its analytic gradient (world coordinates).
  double value_gradient(const Vec3& p, Vec3& gradient) const;
  // f (and grad f when gradients is not null) at n points, the same values
  // as value() / value_gradient(). Faster for many scattered points: the
  // samples of later points are prefetched while earlier ones are combined.
  void values(const Vec3* points, std::size_t n, double* f, Vec3* gradients = nullptr) const;
  // Inside the domain (the box spanned by the voxel centres), up to a
  // relative rounding tolerance of 1e-9 of a voxel.
  bool in_domain(const Vec3& p) const;

  // g's samples (clamped when a clamp was given): what f is built on.
  const SampleGrid& samples() const { return g_; }
  const Vec3& d() const { return d_; }

  // The quantities of thesis 6.3.2 (computed from g even when d was given):
  // g_min = min |g| over D, L_max = max_k L_k with
  // L_k = sqrt(3) * max_i max over the 8 vertices v of the 1.8-delta box C'_k
  // of |d f_k / d x_i (v)| (physical units), over the cells C_k of the
  // foreground's box grown by weight_margin voxels: they hold every cell
  // near S (a vertex v with |g(v)| < R = 0.65 (delta_0 + delta_1 +
  // delta_2)), the only ones that can bound d (partition_of_unity.cpp), so
  // d is the same on a crop of the grid that holds that box (crop_margin).
  double g_min() const { return g_min_; }
  double l_max() const { return l_max_; }
  // The bound d_i = min(delta_i / 5, g_min / (2 L_max)) itself.
  static Vec3 weight_constant(const FloatImage& g, double* g_min = nullptr, double* l_max = nullptr,
                              unsigned threads = 1);
  // R and the margin above.
  static double near_radius(const Vec3& spacing);
  static std::array<std::size_t, 3> weight_margin(const Vec3& spacing);

private:
  // What f needs at a point. Because phi_k factors per axis and f_k is
  // trilinear, f = sum_{i,j,l} g(first + (i, j, l)) c[0][i] c[1][j] c[2][l]
  // over the n[0] x n[1] x n[2] samples (n = 2 in a cell's centre region on
  // that axis, 3 where two cells blend); c[a] are the per-axis coefficients,
  // dc[a] their derivatives along axis a (physical units). row[l * 3 + j]:
  // the n[0] samples (i = 0.., j, l), contiguous in a block, or copied into
  // buf where they straddle two blocks; floats, or codes into the palette
  // when the blocks are coded (dense: row[0] only, a float). n[0] = 0 for a
  // NaN point.
  struct Stencil {
    const void* row[9];
    int n[3];
    double c[3][3], dc[3][3];
    union {
      float floats[9][3];
      std::uint16_t codes[9][3];
    } buf;
  };
  PartitionOfUnity() = default;
  static void check_grid(const Geometry& g);
  // d checked against its bound (or set to it when not given), then the
  // evaluation's constants from g_.
  void finish(const Vec3& bound);
  template <bool Gradient> void locate(const Vec3& p, Stencil& s) const;
  // The rows of a stencil whose samples start at `first`, in blocks of T
  // (float, or std::uint16_t codes).
  template <class T> void block_rows(const long first[3], Stencil& s) const;
  void prefetch(const Stencil& s) const;
  template <bool Gradient> double combine(const Stencil& s, Vec3* gradient) const;
  template <bool Gradient> void evaluate_many(const Vec3* points, std::size_t n, double* f, Vec3* gradients) const;

  SampleGrid g_;
  Vec3 d_{0, 0, 0};
  double g_min_ = 0, l_max_ = 0;
  // Per axis: voxel spacing delta_i, 1/delta_i, 1/(2 d_i), and the number of
  // cells (size_i - 1).
  double delta_[3] = {}, inv_delta_[3] = {}, inv_2d_[3] = {};
  double to_index_[9] = {};  // world offset -> continuous index
  long cells_[3] = {};
  long stride_[3] = {};  // dense storage
};

// The C-infinity step of (6.8): h(t) = exp(2 e^{-1/t} / (t - 1)) on (0, 1),
// h(0) = 1, 0 for t >= 1. dh: its derivative (may be null).
double pu_h(double t, double* dh = nullptr);
// The blend of (6.7) with the errata fix, as a function of
// u = (|t| - alpha_1) / beta: eta = h(u) / (h(u) + h(1 - u)); 1 for u <= 0,
// 0 for u >= 1. deta: d eta / du (may be null).
double pu_eta(double u, double* deta = nullptr);

} // namespace imgmesh
