// The partition of unity f = sum_k phi_k f_k of thesis 6.3, on box cells.
//
// Cells. C_k = [k, k+1] (index units) on each axis, k_i in [0, n_i - 2]; the
// corners are voxel centres, f_k is the trilinear interpolant of g there
// (6.4, 6.5) written in the cell's own unit coordinates, so box cells
// (delta_0, delta_1, delta_2 different) change nothing in it.
//
// Weights. w_k(p) = prod_i eta_i(t_i), t_i = (p_i - c^k_i) in physical units
// along grid axis i, alpha_1 = delta_i/2 - d_i, alpha_2 = delta_i/2 + d_i,
// beta = 2 d_i (6.6-6.8, errata for eta). Because w_k is a product and the
// cells on one axis are translates, sum_j w_j = prod_i S_i with S_i the sum
// of eta_i over the cells of axis i; two neighbouring cells' etas add up to 1
// on their overlap (u and 1 - u), so S_i = 1 except within d_i of the two
// ends of the domain, where only one cell exists. Hence phi_k = w_k / sum w_j
// (6.9) factors into per-axis weights: (1 - eta, eta) where two cells meet,
// 1 where a single cell covers the point. Per axis at most 2 cells have a
// nonzero weight (d_i <= delta_i / 5 < delta_i / 2), so at most 8 of the 27
// neighbouring cells contribute. As f_k is a tensor product of linear
// factors too, f = sum over the 2 or 3 samples per axis that those cells use
// of g times one coefficient per axis (see Stencil): a 2x2x2 to 3x3x3
// contraction instead of up to 8 trilinear interpolations.
//
// Why the argument of 6.4 holds per axis on anisotropic grids. Replace the
// thesis's balls and tubes by boxes: a point is in the vertex / edge / face /
// centre region of a grid feature when it lies within d_i of the feature's
// grid planes on 3 / 2 / 1 / 0 axes (|p_i - plane| < d_i), and farther on the
// others. (1) Claims 6.4.1-6.4.4: supp(w_k) is c^k +- (delta_i/2 + d_i) on
// axis i; a region of a feature that is not a feature of C_k is, on some axis,
// at distance >= delta_i - 2 d_i >= 0.6 delta_i > 0 outside it, because the
// bound d_i <= delta_i / 5 is per axis. (2) Prop. 6.4.2: the proof of
// Prop. 6.4.1 is per coordinate (d f_k / d x_i is bilinear in the other two
// coordinates, so |d f_k / d x_i| peaks at a vertex of any axis-aligned box,
// cube or not); with M_i = max over the 1.8-delta box C'_k of |d f_k/d x_i|
// and L = sqrt(3) max_i M_i, a vertex box v +- d_i lies in C'_k
// (d_i <= 0.2 delta_i < 0.4 delta_i) and there
// |f_k(q) - f_k(v)| <= sum_i M_i d_i <= 3 max_i M_i g_min / (2 L) = (sqrt(3)/2) g_min < |g(v)|,
// so f_k keeps the sign of g(v) in the vertex box: the role of the radius-2d
// ball. (3) Lemmas 6.4.5-6.4.7 use only that, inside an edge (face) region,
// the weights do not vary along the edge (face) directions (true: those axes
// are "far", eta = 1 for the one cell index there) and that f_k is linear
// along axis-parallel lines: both are per-axis facts. So with
// d_i = min(delta_i / 5, g_min / (2 L_max)) every step goes through.
//
// Which cells bound d. Step (2) needs sum_i M_i d_i < |g(v)| for each vertex
// v of each cell. g is 1-Lipschitz (a signed distance), so each edge
// difference along axis i is at most delta_i and |d f_k / d x_i| is at most
// 1.8^2 = 3.24 on C'_k (a bilinear extrapolation to -0.4 and 1.4 in two
// unit coordinates): with d_i <= delta_i / 5, sum_i M_i d_i <=
// 0.648 (delta_0 + delta_1 + delta_2) (float rounding: 1e-6 more), under
// R = 0.65 (delta_0 + delta_1 + delta_2). A cell whose 8 vertices all have
// |g| >= R therefore holds step (2) whatever its L_k, and only the cells
// "near S" (a vertex with |g| < R) need L_k <= L_max. They all lie within
// weight_margin voxels of the foreground's box (a vertex k voxels beyond
// it along axis i is at least (k - 1/2) delta_i from bdCA(X)), so L_max is
// taken over the cells of that grown box: d is then the same on every crop
// of the grid that holds it (crop.hpp), and, the box holding nearly every
// cell, as the thesis's whole-grid L_max on every image we have seen. A d
// given with f (the file's) is checked against the cells near S alone,
// what step (2) asks.
#include "implicit/partition_of_unity.hpp"
#include "implicit/parallel.hpp"
#include "util/error.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <string>
#include <vector>

namespace imgmesh {

namespace {

// L_k of the cell whose lowest sample is c (strides 1, s1, s2; inv: 1 /
// spacing).
double cell_lipschitz(const float* c, long s1, long s2, const double inv[3]) {
  double F[2][2][2];  // F[a][b][c], a: x offset
  for (int a = 0; a < 2; ++a)
    for (int b = 0; b < 2; ++b)
      for (int cz = 0; cz < 2; ++cz) F[a][b][cz] = c[a + b * s1 + cz * s2];
  double m = 0;
  // d u / d x_i is bilinear in the two other unit coordinates: its
  // values at the vertices of C'_k (unit coordinates -0.4 and 1.4)
  // are extrapolations of the four edge differences along axis i.
  for (int axis = 0; axis < 3; ++axis) {
    double e[2][2];
    for (int p = 0; p < 2; ++p)
      for (int q = 0; q < 2; ++q) {
        if (axis == 0) e[p][q] = F[1][p][q] - F[0][p][q];
        else if (axis == 1) e[p][q] = F[p][1][q] - F[p][0][q];
        else e[p][q] = F[p][q][1] - F[p][q][0];
      }
    for (double t : {-0.4, 1.4})
      for (double u : {-0.4, 1.4}) {
        const double lo = (1 - u) * e[0][0] + u * e[0][1], hi = (1 - u) * e[1][0] + u * e[1][1];
        m = std::max(m, std::fabs((1 - t) * lo + t * hi) * inv[axis]);
      }
  }
  return std::sqrt(3.0) * m;
}

// An upper bound of cell_lipschitz from the same samples at a third of its
// cost: each extrapolated derivative above is sum_j w_j e_j over the four
// edge differences along its axis, with sum w_j = 1 and sum |w_j| = 3.24,
// so it lies within 1.62 (max e - min e) of (max e + min e) / 2. Where the
// samples are smooth (most cells away from S and the medial axis) the
// bound is near sqrt(3) and the exact L_k is not needed for a maximum.
double cell_lipschitz_bound(const float* c, long s1, long s2, const double inv[3]) {
  const double F0 = c[0], F1 = c[1], F2 = c[s1], F3 = c[1 + s1], F4 = c[s2], F5 = c[1 + s2], F6 = c[s1 + s2],
               F7 = c[1 + s1 + s2];
  const auto axis = [](double e0, double e1, double e2, double e3, double inv_s) {
    const double lo = std::min(std::min(e0, e1), std::min(e2, e3)), hi = std::max(std::max(e0, e1), std::max(e2, e3));
    return (std::fabs(hi + lo) / 2 + 1.62 * (hi - lo)) * inv_s;
  };
  const double m = std::max(std::max(axis(F1 - F0, F3 - F2, F5 - F4, F7 - F6, inv[0]),
                                     axis(F2 - F0, F3 - F1, F6 - F4, F7 - F5, inv[1])),
                            axis(F4 - F0, F5 - F1, F6 - F2, F7 - F3, inv[2]));
  return std::sqrt(3.0) * m * (1 + 1e-9);  // the margin covers cell_lipschitz's roundings
}

// A vertex of the cell has |g| < r.
bool cell_near(const float* c, long s1, long s2, double r) {
  for (int m = 0; m < 8; ++m)
    if (std::fabs(c[(m & 1) + ((m >> 1) & 1) * s1 + ((m >> 2) & 1) * s2]) < r) return true;
  return false;
}

Vec3 bound_of(const Vec3& spacing, double gm, double lm) {
  Vec3 d;
  for (int i = 0; i < 3; ++i) {
    d[i] = spacing[i] / 5;
    if (lm > 0) d[i] = std::min(d[i], gm / (2 * lm));
  }
  return d;
}

const char* const kBadSamples = "the samples of g must be finite and nonzero (g is a signed distance from voxel centres)";

// g_min and the largest L_k of the cells near S, of g streamed a z-slice at
// a time: the last two slices held, the cells between them measured as each
// slice comes.
class StreamedBound {
public:
  explicit StreamedBound(const Geometry& box)
      : nx_(long(box.size[0])), ny_(long(box.size[1])), n_(std::size_t(nx_ * ny_)), two_(2 * n_),
        near_rows_(2 * std::size_t(ny_)),
        inv_{1 / box.spacing[0], 1 / box.spacing[1], 1 / box.spacing[2]},
        r_(PartitionOfUnity::near_radius(box.spacing)) {}
  void add(const float* slice) {
    // Which rows hold a sample under r: a cell near S has a corner in one.
    std::uint8_t* near_row = near_rows_.data() + (z_ & 1) * std::size_t(ny_);
    for (long y = 0; y < ny_; ++y) {
      bool near = false;
      for (long x = 0; x < nx_; ++x) {
        const float v = slice[x + y * nx_];
        if (!std::isfinite(v) || v == 0) throw Error(kBadSamples);
        g_min = std::min(g_min, double(std::fabs(v)));
        near = near || std::fabs(v) < r_;
      }
      near_row[y] = near;
    }
    float* cur = two_.data() + (z_ & 1) * n_;
    std::copy_n(slice, n_, cur);
    if (z_ > 0) {
      const float* prev = two_.data() + ((z_ - 1) & 1) * n_;
      const std::uint8_t* prev_near = near_rows_.data() + ((z_ - 1) & 1) * std::size_t(ny_);
      const long s2 = long(cur - prev);
      for (long y = 0; y + 1 < ny_; ++y)
        if (near_row[y] || near_row[y + 1] || prev_near[y] || prev_near[y + 1])
          for (long x = 0; x + 1 < nx_; ++x)
            if (cell_near(prev + x + y * nx_, nx_, s2, r_))
              l_near = std::max(l_near, cell_lipschitz(prev + x + y * nx_, nx_, s2, inv_));
    }
    ++z_;
  }
  double g_min = std::numeric_limits<double>::infinity(), l_near = 0;

private:
  long nx_, ny_;
  std::size_t n_;
  std::vector<float> two_;
  std::vector<std::uint8_t> near_rows_;  // per row of the last two slices
  double inv_[3], r_;
  std::size_t z_ = 0;
};

// The same of g a band of x at a time, and the largest L_k of the cells of
// the foreground's box grown by weight_margin (weight_constant's): the
// last column of the band before held for the cells across.
class BandBound {
public:
  BandBound(const Geometry& box, const Index3& fg_lo, const Index3& fg_hi, unsigned threads)
      : ny_(long(box.size[1])), nz_(long(box.size[2])), inv_{1 / box.spacing[0], 1 / box.spacing[1], 1 / box.spacing[2]},
        r_(PartitionOfUnity::near_radius(box.spacing)), fg_lo_(fg_lo), fg_hi_(fg_hi),
        threads_(implicit_detail::resolve_threads(threads)), prev_(std::size_t(ny_ * nz_)) {
    const std::array<std::size_t, 3> m = PartitionOfUnity::weight_margin(box.spacing);
    for (int a = 0; a < 3; ++a) {
      const long n = long(box.size[a]);
      long lo = long(fg_lo[a]), hi = long(fg_hi[a]);
      if (hi < lo) lo = 0, hi = n - 1;  // no foreground: every cell
      c0_[a] = std::max(0L, lo - long(m[a]));
      c1_[a] = std::min(n - 2, hi + long(m[a]) - 1);
    }
  }
  void add(long x0, long x1, const float* band) {
    const long w = x1 - x0;
    for (long z = 0; z < nz_; ++z)
      for (long y = 0; y < ny_; ++y)
        for (long x = 0; x < w; ++x) {
          const float v = band[x + w * (y + ny_ * z)];
          if (!std::isfinite(v) || v == 0) throw Error(kBadSamples);
          g_min = std::min(g_min, double(std::fabs(v)));
          if (v < 0 && (x + x0 < fg_lo_[0] || x + x0 > fg_hi_[0] || y < fg_lo_[1] || y > fg_hi_[1] || z < fg_lo_[2] ||
                        z > fg_hi_[2]))
            throw Error("internal: a foreground sample outside the foreground's box");
        }
    if (x0 > 0) {  // the cells across: the held column and the band's first
      std::vector<float> pair(std::size_t(2 * ny_ * nz_));
      for (std::size_t i = 0; i < prev_.size(); ++i) {
        pair[2 * i] = prev_[i];
        pair[2 * i + 1] = band[std::size_t(w) * i];
      }
      cells(pair.data(), 2, x0 - 1);
    }
    cells(band, w, x0);
    for (std::size_t i = 0; i < prev_.size(); ++i) prev_[i] = band[std::size_t(w) * i + std::size_t(w - 1)];
  }
  double g_min = std::numeric_limits<double>::infinity(), l_all = 0, l_near = 0;

private:
  // The cells whose lowest corner lies in the w columns of v (x from x0).
  void cells(const float* v, long w, long x0) {
    const long s1 = w, s2 = w * ny_;
    std::vector<double> all(threads_, 0.0), near(threads_, 0.0);
    implicit_detail::parallel_for(nz_ - 1, threads_, [&](long z0, long z1, unsigned t) {
      for (long z = z0; z < z1; ++z)
        for (long y = 0; y + 1 < ny_; ++y)
          for (long x = 0; x + 1 < w; ++x) {
            const float* c = v + x + y * s1 + z * s2;
            const bool in_box = x + x0 >= c0_[0] && x + x0 <= c1_[0] && y >= c0_[1] && y <= c1_[1] && z >= c0_[2] &&
                                z <= c1_[2];
            const bool near_s = cell_near(c, s1, s2, r_);
            if (!in_box && !near_s) continue;
            const double ub = cell_lipschitz_bound(c, s1, s2, inv_);
            if (!(in_box && ub > all[t]) && !(near_s && ub > near[t])) continue;
            const double l = cell_lipschitz(c, s1, s2, inv_);
            if (in_box) all[t] = std::max(all[t], l);
            if (near_s) near[t] = std::max(near[t], l);
          }
    });
    l_all = std::max(l_all, *std::max_element(all.begin(), all.end()));
    l_near = std::max(l_near, *std::max_element(near.begin(), near.end()));
  }
  long ny_, nz_;
  double inv_[3], r_;
  Index3 fg_lo_, fg_hi_;
  long c0_[3], c1_[3];
  unsigned threads_;
  std::vector<float> prev_;  // the last band's last column (y, z)
};

} // namespace

double PartitionOfUnity::near_radius(const Vec3& spacing) { return 0.65 * (spacing[0] + spacing[1] + spacing[2]); }

std::array<std::size_t, 3> PartitionOfUnity::weight_margin(const Vec3& spacing) {
  const double r = near_radius(spacing);
  std::array<std::size_t, 3> m;
  for (int i = 0; i < 3; ++i) m[i] = std::size_t(std::floor(r / spacing[i] + 0.5)) + 1;
  return m;
}

Vec3 PartitionOfUnity::weight_constant(const FloatImage& g, double* g_min, double* l_max, unsigned threads) {
  const long n[3] = {long(g.size[0]), long(g.size[1]), long(g.size[2])};
  const long s1 = n[0], s2 = n[0] * n[1];
  const float* v = g.data.data();
  const unsigned nt = implicit_detail::resolve_threads(threads);
  const double inv[3] = {1 / g.spacing[0], 1 / g.spacing[1], 1 / g.spacing[2]};
  // Per slab along z: min |g| and the foreground's (g < 0) box.
  std::vector<double> gmin(nt, std::numeric_limits<double>::infinity()), lmax(nt, 0.0);
  std::vector<std::array<long, 6>> box(nt, {n[0], n[1], n[2], -1, -1, -1});
  implicit_detail::parallel_for(n[2], nt, [&](long z0, long z1, unsigned t) {
    double gm = gmin[t];
    std::array<long, 6>& b = box[t];
    for (long z = z0; z < z1; ++z)
      for (long y = 0; y < n[1]; ++y)
        for (long x = 0; x < n[0]; ++x) {
          const float w = v[x + y * s1 + z * s2];
          gm = std::min(gm, double(std::fabs(w)));
          if (w < 0) {
            const long c[3] = {x, y, z};
            for (int a = 0; a < 3; ++a) b[a] = std::min(b[a], c[a]), b[a + 3] = std::max(b[a + 3], c[a]);
          }
        }
    gmin[t] = gm;
  });
  // The cells of that box grown by weight_margin (all of them when g has
  // no foreground sample: then no cell is near S).
  const std::array<std::size_t, 3> m = weight_margin(g.spacing);
  long c0[3], c1[3];
  for (int a = 0; a < 3; ++a) {
    long lo = n[a], hi = -1;
    for (const auto& b : box) lo = std::min(lo, b[a]), hi = std::max(hi, b[a + 3]);
    if (hi < lo) lo = 0, hi = n[a] - 1;
    c0[a] = std::max(0L, lo - long(m[a]));
    c1[a] = std::min(n[a] - 2, hi + long(m[a]) - 1);
  }
  implicit_detail::parallel_for(std::max(0L, c1[2] - c0[2] + 1), nt, [&](long z0, long z1, unsigned t) {
    double lm = lmax[t];
    for (long z = c0[2] + z0; z < c0[2] + z1; ++z)
      for (long y = c0[1]; y <= c1[1]; ++y)
        for (long x = c0[0]; x <= c1[0]; ++x) {
          const float* c = v + x + y * s1 + z * s2;
          if (cell_lipschitz_bound(c, s1, s2, inv) > lm) lm = std::max(lm, cell_lipschitz(c, s1, s2, inv));
        }
    lmax[t] = lm;
  });
  const double gm = *std::min_element(gmin.begin(), gmin.end());
  const double lm = *std::max_element(lmax.begin(), lmax.end());
  if (g_min) *g_min = gm;
  if (l_max) *l_max = lm;
  return bound_of(g.spacing, gm, lm);
}

void PartitionOfUnity::check_grid(const Geometry& g) {
  if (g.dimension != 3) throw Error("the implicit function needs a 3D image");
  for (int i = 0; i < 3; ++i) {
    if (g.size[i] < 2)
      throw Error("the implicit function needs at least 2 voxels on every axis (axis " + std::to_string(i) +
                  " has " + std::to_string(g.size[i]) + ")");
    if (!(g.spacing[i] > 0) || !std::isfinite(g.spacing[i]))
      throw Error("voxel spacing must be positive and finite");
  }
  if (g.count() > (std::size_t(1) << 40)) throw Error("grid too large");
}

PartitionOfUnity::PartitionOfUnity(FloatImage g, Vec3 d, unsigned threads, float clamp, SampleGrid::Storage storage)
    : d_(d) {
  check_grid(g);
  if (g.data.size() != g.count()) throw Error("internal: sample data does not match the grid size");
  for (float x : g.data)
    if (!std::isfinite(x) || x == 0) throw Error(kBadSamples);
  const Vec3 bound = weight_constant(g, &g_min_, &l_max_, threads);
  if (clamp < clamp_for(g, 0)) throw Error("internal: the samples' clamp is under the stencil's diameter");
  g_ = SampleGrid(std::move(g), clamp, storage);
  finish(bound);
}

PartitionOfUnity PartitionOfUnity::streamed(const Geometry& grid, const Index3& lo, const Geometry& box, Vec3 d,
                                            float clamp, const SampleGrid::SliceReader& next_slice,
                                            SampleGrid::Storage storage) {
  check_grid(box);
  check_grid(grid);
  if (grid.spacing != box.spacing || grid.direction != box.direction)
    throw Error("internal: a box placed in a grid of another spacing or direction");
  if (clamp < clamp_for(box, 0)) throw Error("internal: the samples' clamp is under the stencil's diameter");
  if (!(d[0] > 0 || d[1] > 0 || d[2] > 0)) throw Error("internal: a streamed f takes its d given");
  PartitionOfUnity f;
  f.d_ = d;
  StreamedBound bound(box);
  f.g_ = SampleGrid(grid, lo, box.size, clamp, storage, [&](float* slice) {
    next_slice(slice);
    bound.add(slice);
  });
  f.g_min_ = bound.g_min;
  f.l_max_ = bound.l_near;
  f.finish(bound_of(box.spacing, bound.g_min, bound.l_near));
  return f;
}

PartitionOfUnity PartitionOfUnity::from_bands(const Geometry& grid, const Index3& lo, const Geometry& box,
                                              const Index3& fg_lo, const Index3& fg_hi, float clamp,
                                              const SampleGrid::BandReader& next_band, unsigned threads,
                                              SampleGrid::Storage storage, std::size_t band_bytes) {
  check_grid(box);
  check_grid(grid);
  if (grid.spacing != box.spacing || grid.direction != box.direction)
    throw Error("internal: a box placed in a grid of another spacing or direction");
  if (clamp < clamp_for(box, 0)) throw Error("internal: the samples' clamp is under the stencil's diameter");
  PartitionOfUnity f;
  BandBound bound(box, fg_lo, fg_hi, threads);
  f.g_ = SampleGrid(grid, lo, box.size, clamp, storage, [&](std::size_t x0, std::size_t x1, float* band) {
    next_band(x0, x1, band);
    bound.add(long(x0), long(x1), band);
  }, band_bytes);
  // d as the constructor's (all the cells of the grown box), checked as
  // streamed() checks the file's (the cells near S): f's numbers are the
  // streamed f's.
  f.g_min_ = bound.g_min;
  f.l_max_ = bound.l_near;
  f.d_ = bound_of(box.spacing, bound.g_min, bound.l_all);
  f.finish(bound_of(box.spacing, bound.g_min, bound.l_near));
  return f;
}

void PartitionOfUnity::finish(const Vec3& bound) {
  const bool given = d_[0] > 0 || d_[1] > 0 || d_[2] > 0;
  if (!given) d_ = bound;
  for (int i = 0; i < 3; ++i) {
    if (!(d_[i] > 0) || !std::isfinite(d_[i])) throw Error("the weight constant d must be positive on every axis");
    // A larger d than the thesis's bound voids the topological guarantee.
    if (d_[i] > bound[i] * (1 + 1e-6))
      throw Error("the weight constant d (" + std::to_string(d_[i]) + " on axis " + std::to_string(i) +
                  ") exceeds min(delta/5, g_min/(2 L_max)) = " + std::to_string(bound[i]));
  }
  stride_[0] = 1;
  stride_[1] = long(g_.size[0]);
  stride_[2] = long(g_.size[0]) * long(g_.size[1]);
  for (int i = 0; i < 3; ++i) {
    delta_[i] = g_.spacing[i];
    inv_delta_[i] = 1 / delta_[i];
    inv_2d_[i] = 1 / (2 * d_[i]);
    cells_[i] = long(g_.size[i]) - 1;
  }
  // continuous index = diag(1/spacing) D^T (p - origin) (D orthonormal)
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) to_index_[i * 3 + j] = g_.direction[j * 3 + i] / g_.spacing[i];
}

float PartitionOfUnity::clamp_for(const Geometry& grid, double e) {
  const Vec3& h = grid.spacing;
  const double diameter = 2 * std::sqrt(h[0] * h[0] + h[1] * h[1] + h[2] * h[2]);
  const double t = (diameter + 2 * std::max(e, 0.0)) * (1 + 1e-6);
  return t < double(std::numeric_limits<float>::max()) ? float(t) : std::numeric_limits<float>::infinity();
}

} // namespace imgmesh

