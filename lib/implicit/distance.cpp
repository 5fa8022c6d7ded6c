// Exact Euclidean distance from voxel centres to the voxel-face boundary
// bdCA(X), in linear time.
//
// Why this is exact. Let p be a foreground centre. bdCA(X) is the boundary of
// the union of closed foreground voxel boxes, and p lies in its interior, so
// dist(p, bdCA(X)) = dist(p, union of closed background boxes B_b) (voxels
// outside the grid are background boxes too). The nearest point of the box
// B_b (centre b, half-sides delta_i / 2) to p is the per-axis clamp, so with
// m_i = p_i - b_i (integers, index units)
//
//   dist(p, B_b)^2 = sum_i F_i(m_i),  F_i(0) = 0,  F_i(m) = ((|m| - 1/2) delta_i)^2.
//
// The same holds for a background p and foreground boxes. So
// D(p) = min_b sum_i F_i(p_i - b_i) is a separable min-plus convolution and
// can be done one axis at a time: G_1 = (0 on the opposite class, inf on the
// own class), G_{a+1}(y) = min_{y'} G_a(y') + F_a(y - y'), each pass exact.
// One pass in one line: split off y' = y (F = 0), and for y' != y note that
// F_a(y - y') = min_{s = +-1/2} ((y - y' - s) delta)^2 (the min picks the
// half-shift towards y since |y - y'| >= 1), while for y' = y the parabolas
// give G(y) + delta^2/4 >= G(y), so including them changes nothing:
//
//   G_new(y) = min(G(y), min_c [H(c) + ((y - c) delta)^2]),
//   c = j - 1/2 (j = 0..n), H(c) = min(G(j - 1), G(j)),
//
// the lower envelope of n + 1 parabolas at half-integer sites, done in O(n)
// by Felzenszwalb and Huttenlocher's algorithm. Out-of-grid neighbours G(-1),
// G(n) are 0 for foreground targets (the outside is background) and inf for
// background targets. Both classes share one buffer: a voxel is a site of
// value 0 for the other class and carries its own running value for its own.
#include "implicit/implicit_file.hpp"
#include "implicit/parallel.hpp"
#include "util/error.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

namespace imgmesh {
namespace {

using implicit_detail::parallel_for;
using implicit_detail::resolve_threads;

constexpr double kInf = std::numeric_limits<double>::infinity();

struct LineWork {
  std::vector<double> h, z, out;
  std::vector<long> v;
  void reserve(long n) {
    h.resize(n + 1);
    z.resize(n + 2);
    v.resize(n + 1);
    out.resize(n);
  }
};

// One pass on one line for the targets of class `cls` (1 foreground, 0
// background). val: running squared distances; lab: the class of each voxel.
// Positions enter only as differences of sites (integers, exact): the
// breakpoint between parabolas q and j is kept as its offset from c_q, so a
// line gives the same values, to the last bit, wherever it starts (a crop
// of a grid gives the grid's samples).
void pass_line(double* val, const std::uint8_t* lab, long n, double delta2, std::uint8_t cls,
               LineWork& w) {
  bool any_target = false;
  for (long j = 0; j < n; ++j)
    if (lab[j] == cls) { any_target = true; break; }
  if (!any_target) return;
  const double outside = cls ? 0.0 : kInf;
  auto site = [&](long j) -> double {
    if (j < 0 || j >= n) return outside;
    return lab[j] == cls ? val[j] : 0.0;
  };
  // Parabola heights in units of delta^2 at sites c_j = j - 1/2.
  for (long j = 0; j <= n; ++j) w.h[j] = std::min(site(j - 1), site(j)) / delta2;
  // Envelope: parabolas v[0..k]; z[m] (m >= 1): where v[m] takes over from
  // v[m - 1], as an offset from c_{v[m - 1]}; z[k + 1] = inf.
  long k = -1;
  for (long j = 0; j <= n; ++j) {
    if (!(w.h[j] < kInf)) continue;
    if (k < 0) {
      k = 0;
      w.v[0] = j;
      w.z[1] = kInf;
      continue;
    }
    double t;
    for (;;) {
      const long q = w.v[k];
      const double step = double(j - q);
      t = ((w.h[j] - w.h[q]) + step * step) / (2 * step);  // from c_q
      if (k > 0 && double(q - w.v[k - 1]) + t <= w.z[k]) --k;
      else break;
    }
    ++k;
    w.v[k] = j;
    w.z[k] = t;
    w.z[k + 1] = kInf;
  }
  if (k < 0) return;  // no site: everything stays inf
  long e = 0;
  for (long y = 0; y < n; ++y) {
    if (lab[y] != cls) continue;
    while (w.z[e + 1] < double(y - w.v[e]) + 0.5) ++e;
    const double u = double(y - w.v[e]) + 0.5;  // y - c
    const double env = (w.h[w.v[e]] + u * u) * delta2;
    val[y] = std::min(val[y], env);
  }
}

// The first pass, where G is 0 on the opposite class and inf on the own
// class: the envelope reduces to the distance to the nearest opposite voxel
// of the line, (m - 1/2) delta for m voxels away (outside = background).
void first_pass_line(double* val, const std::uint8_t* lab, long n, double delta2) {
  constexpr long kNone = std::numeric_limits<long>::min() / 4;
  long last[2] = {-1, kNone};  // last background (outside at -1) and foreground position
  for (long y = 0; y < n; ++y) {
    const int c = lab[y];
    const long o = last[1 - c];
    val[y] = o == kNone ? kInf : double(y - o);
    last[c] = y;
  }
  long next[2] = {n, -kNone};
  for (long y = n - 1; y >= 0; --y) {
    const int c = lab[y];
    const long o = next[1 - c];
    const double m = std::min(val[y], o == -kNone ? kInf : double(o - y));
    val[y] = m < kInf ? (m - 0.5) * (m - 0.5) * delta2 : kInf;
    next[c] = y;
  }
}

} // namespace

void signed_distance_band(const BinaryImage& wc, std::size_t x0, std::size_t x1, float* band, unsigned threads) {
  if (wc.dimension != 3) throw Error("needs a 3D image");
  if (wc.data.size() != wc.count() || wc.count() == 0) throw Error("empty image");
  if (x0 >= x1 || x1 > wc.size[0]) throw Error("internal: a band of x outside the grid");
  threads = resolve_threads(threads);
  const long n[3] = {long(wc.size[0]), long(wc.size[1]), long(wc.size[2])};
  const long w = long(x1 - x0);
  // Strides of the image (labels) and of the band (values), whose x runs
  // over [x0, x1) only.
  const long stride[3] = {1, n[0], n[0] * n[1]}, bstride[3] = {1, w, w * n[1]};
  const std::uint8_t* lab = wc.data.data();
  float* buf = band;
  constexpr long kBatch = 16;  // neighbouring lines gathered together (cache lines)
  for (int a = 0; a < 3; ++a) {
    // Along x every line is whole (the band's values depend on all of it);
    // along y and z only the band's lines.
    const long len = n[a];
    const double delta2 = wc.spacing[a] * wc.spacing[a];
    // Lines along axis a: indexed by the other two coordinates; for a > 0 the
    // x coordinate is innermost so batches of kBatch lines are contiguous.
    const int b = a == 0 ? 1 : 0, c = a == 2 ? 1 : 2;
    const long nb = a == 0 ? n[1] : w, nc = n[c];
    const long batches_per_row = (nb + kBatch - 1) / kBatch;
    const long jobs = nc * batches_per_row;
    parallel_for(jobs, threads, [&](long j0, long j1, unsigned) {
      LineWork work;
      work.reserve(len);
      std::vector<double> vals(len * kBatch);
      std::vector<std::uint8_t> labs(len * kBatch);
      for (long job = j0; job < j1; ++job) {
        const long ic = job / batches_per_row, ib0 = (job % batches_per_row) * kBatch;
        const long m = std::min(kBatch, nb - ib0);
        // Line q's voxel t: in the image at image0 + q stride[b] + t
        // stride[a], in the band at band0 + q bstride[b] + t bstride[a]
        // (along x, t - x0).
        const std::uint8_t* image0 = lab + ib0 * stride[b] + ic * stride[c] + (a == 0 ? 0 : long(x0));
        float* band0 = buf + ib0 * bstride[b] + ic * bstride[c];
        for (long t = 0; t < len; ++t) {
          const std::uint8_t* in = image0 + t * stride[a];
          for (long q = 0; q < m; ++q) labs[q * len + t] = in[q * stride[b]] != 0;
          if (a == 0) continue;
          const float* from = band0 + t * bstride[a];
          for (long q = 0; q < m; ++q) vals[q * len + t] = from[q * bstride[b]];
        }
        for (long q = 0; q < m; ++q) {
          if (a == 0) {
            first_pass_line(&vals[q * len], &labs[q * len], len, delta2);
          } else {
            pass_line(&vals[q * len], &labs[q * len], len, delta2, 1, work);
            pass_line(&vals[q * len], &labs[q * len], len, delta2, 0, work);
          }
        }
        for (long t = a == 0 ? long(x0) : 0; t < (a == 0 ? long(x1) : len); ++t) {
          float* to = band0 + (a == 0 ? t - long(x0) : t * bstride[a]);
          for (long q = 0; q < m; ++q) to[q * bstride[b]] = float(vals[q * len + t]);
        }
      }
    });
  }
  for (long z = 0; z < n[2]; ++z)
    for (long y = 0; y < n[1]; ++y)
      for (long x = 0; x < w; ++x) {
        float& v = buf[x + w * (y + n[1] * z)];
        const float d2 = v;
        if (!(d2 < std::numeric_limits<float>::infinity())) throw Error("the foreground is empty");
        v = lab[std::size_t(x + long(x0) + n[0] * (y + n[1] * z))] ? -std::sqrt(d2) : std::sqrt(d2);
      }
}

FloatImage signed_distance_to_boundary(const BinaryImage& wc, unsigned threads) {
  if (wc.dimension != 3) throw Error("needs a 3D image");
  if (wc.data.size() != wc.count() || wc.count() == 0) throw Error("empty image");
  FloatImage out(wc.geometry(), std::numeric_limits<float>::infinity());
  signed_distance_band(wc, 0, wc.size[0], out.data.data(), threads);
  return out;
}

} // namespace imgmesh
