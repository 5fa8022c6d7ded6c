// Evaluating f = sum_k phi_k f_k (thesis 6.3; the construction, the
// weights and the guarantees: partition_of_unity.cpp's header): the
// weight's smooth step, the stencil of cells a point's weights reach, and
// their contraction, a point or many at a time.
#include "implicit/partition_of_unity.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <type_traits>

namespace imgmesh {

double pu_h(double t, double* dh) {
  if (dh) *dh = 0;
  if (t < 0 || t >= 1) return 0;
  if (t == 0) return 1;
  const double e = std::exp(-1.0 / t);
  const double h = std::exp(2 * e / (t - 1));
  if (dh) *dh = h * 2 * e * (1 / (t * t * (t - 1)) - 1 / ((t - 1) * (t - 1)));
  return h;
}

// eta = h(u) / (h(u) + h(1 - u)) = 1 / (1 + exp(B - A)) with A = log h(u),
// B = log h(1 - u): three exponentials instead of four, no overflow.
double pu_eta(double u, double* deta) {
  if (deta) *deta = 0;
  if (!(u > 0)) return 1;
  if (u >= 1) return 0;
  const double iu = 1 / u, iv = 1 / (1 - u);
  const double ea = std::exp(-iu), eb = std::exp(-iv);
  const double A = -2 * ea * iv, B = -2 * eb * iu;  // 1/(u-1) = -iv, 1/((1-u)-1) = -iu
  const double eta = 1 / (1 + std::exp(B - A));
  if (deta) {
    // d/dt log h(t) = 2 e^{-1/t} (1/(t^2 (t-1)) - 1/(t-1)^2), at t = u and t = 1 - u.
    const double la = ea == 0 ? 0 : 2 * ea * (-iu * iu * iv - iv * iv);
    const double lb = eb == 0 ? 0 : 2 * eb * (-iv * iv * iu - iu * iu);
    *deta = eta * (1 - eta) * (la + lb);
  }
  return eta;
}

bool PartitionOfUnity::in_domain(const Vec3& p) const {
  const Vec3 q = g_.continuous_index(p);
  for (int i = 0; i < 3; ++i)
    if (!(q[i] >= -1e-9 && q[i] <= double(cells_[i]) + 1e-9)) return false;
  return true;
}

template <bool Gradient> void PartitionOfUnity::locate(const Vec3& p, Stencil& s) const {
  const double u0 = p[0] - g_.origin[0], u1 = p[1] - g_.origin[1], u2 = p[2] - g_.origin[2];
  const double q[3] = {to_index_[0] * u0 + to_index_[1] * u1 + to_index_[2] * u2,
                       to_index_[3] * u0 + to_index_[4] * u1 + to_index_[5] * u2,
                       to_index_[6] * u0 + to_index_[7] * u1 + to_index_[8] * u2};
  if (std::isnan(q[0]) || std::isnan(q[1]) || std::isnan(q[2])) {
    s.n[0] = s.n[1] = s.n[2] = 0;
    return;
  }
  long first[3];
  for (int i = 0; i < 3; ++i) {
    const double qi = std::min(std::max(q[i], 0.0), double(cells_[i]));  // outside: nearest domain point
    const long k0 = std::min(long(qi), cells_[i] - 1);
    const double r = qi - double(k0);
    const double xlo = r * delta_[i], xhi = (1 - r) * delta_[i];
    // The grid plane within d, if any (two cells blend there): plane k0 or k0 + 1.
    long plane = -1;
    double x = 0;  // offset above the plane, physical units, in (-d, d)
    if (xlo < d_[i] && k0 > 0) {
      plane = k0;
      x = xlo;
    } else if (xhi < d_[i] && k0 + 1 < cells_[i]) {
      plane = k0 + 1;
      x = -xhi;
    }
    double* c = s.c[i];
    double* dc = s.dc[i];
    const double id = inv_delta_[i];
    if (plane < 0) {
      // Only cell k0: phi = 1 on this axis, f_k linear in r.
      s.n[i] = 2;
      first[i] = k0;
      c[0] = 1 - r;
      c[1] = r;
      if (Gradient) {
        dc[0] = -id;
        dc[1] = id;
      }
    } else {
      // Cells plane - 1 and plane with weights 1 - eta, eta, where the upper
      // one has u = (|t| - alpha_1) / beta = (d - x) / (2 d); l = qi - plane
      // is the point's unit coordinate in the upper cell (1 + l in the lower).
      double de = 0;
      const double eta = pu_eta((d_[i] - x) * inv_2d_[i], Gradient ? &de : nullptr);
      const double l = qi - double(plane);
      s.n[i] = 3;
      first[i] = plane - 1;
      c[0] = -(1 - eta) * l;
      c[1] = 1 + (1 - 2 * eta) * l;
      c[2] = eta * l;
      if (Gradient) {
        const double deta = -de * inv_2d_[i];  // d eta / dt
        dc[0] = deta * l - (1 - eta) * id;
        dc[1] = (1 - 2 * eta) * id - 2 * deta * l;
        dc[2] = deta * l + eta * id;
      }
    }
  }
  if (g_.dense()) {  // row[0] only: rows at strides from it
    s.row[0] = g_.dense_data() + first[0] + first[1] * stride_[1] + first[2] * stride_[2];
    return;
  }
  if (g_.coded()) block_rows<std::uint16_t>(first, s);
  else block_rows<float>(first, s);
}

// Blocks: the rows of samples: per axis y, z each sample's block offset and local
// part, then one table lookup a row; a row that straddles two blocks
// along x is copied.
template <class T> void PartitionOfUnity::block_rows(const long first[3], Stencil& s) const {
  constexpr long kB = SampleGrid::kB, kMask = SampleGrid::kMask;
  constexpr int kShift = SampleGrid::kShift;
  const auto block_at = [this](long b) {
    if constexpr (std::is_same_v<T, float>) return g_.block_at(b);
    else return g_.code_block_at(b);
  };
  // Block numbers are the table's (SampleGrid::table_block).
  const long x0 = first[0], lx = x0 & kMask, bx = g_.table_block(0, x0 >> kShift);
  const long nb0 = g_.nb(0), nb01 = g_.nb(0) * g_.nb(1);
  const long ly = first[1] & kMask, lz = first[2] & kMask;
  if (lx + s.n[0] <= kB && ly + s.n[1] <= kB && lz + s.n[2] <= kB) {  // one block
    const T* base = block_at(bx + nb0 * g_.table_block(1, first[1] >> kShift) + nb01 * g_.table_block(2, first[2] >> kShift)) +
                    lx + kB * ly + kB * kB * lz;
    for (int l = 0; l < s.n[2]; ++l)
      for (int j = 0; j < s.n[1]; ++j) s.row[l * 3 + j] = base + kB * j + kB * kB * l;
    return;
  }
  long yo[3], yl[3], zo[3], zl[3];
  for (int j = 0; j < s.n[1]; ++j) {
    const long y = first[1] + j;
    yo[j] = nb0 * g_.table_block(1, y >> kShift);
    yl[j] = kB * (y & kMask);
  }
  for (int l = 0; l < s.n[2]; ++l) {
    const long z = first[2] + l;
    zo[l] = nb01 * g_.table_block(2, z >> kShift);
    zl[l] = kB * kB * (z & kMask);
  }
  if (lx + s.n[0] <= kB) {
    for (int l = 0; l < s.n[2]; ++l)
      for (int j = 0; j < s.n[1]; ++j) s.row[l * 3 + j] = block_at(bx + yo[j] + zo[l]) + lx + yl[j] + zl[l];
    return;
  }
  const long bx1 = g_.table_block(0, (x0 >> kShift) + 1);
  for (int l = 0; l < s.n[2]; ++l)
    for (int j = 0; j < s.n[1]; ++j) {
      const T* lo = block_at(bx + yo[j] + zo[l]) + yl[j] + zl[l];
      const T* hi = block_at(bx1 + yo[j] + zo[l]) + yl[j] + zl[l];
      T* r;
      if constexpr (std::is_same_v<T, float>) r = s.buf.floats[l * 3 + j];
      else r = s.buf.codes[l * 3 + j];
      for (int i = 0; i < s.n[0]; ++i) r[i] = lx + i < kB ? lo[lx + i] : hi[lx + i - kB];
      s.row[l * 3 + j] = r;
    }
}

// Start loading the rows of samples the stencil uses.
void PartitionOfUnity::prefetch(const Stencil& s) const {
  const std::size_t size = g_.coded() ? sizeof(std::uint16_t) : sizeof(float);
  for (int l = 0; l < s.n[2]; ++l)
    for (int j = 0; j < s.n[1]; ++j) {
      const char* row = g_.dense() ? static_cast<const char*>(s.row[0]) + (j * stride_[1] + l * stride_[2]) * long(sizeof(float))
                                   : static_cast<const char*>(s.row[l * 3 + j]);
      __builtin_prefetch(row);
      __builtin_prefetch(row + std::size_t(s.n[0] - 1) * size);
    }
}

namespace {

// A row of coded samples: its values the palette's at its codes.
struct CodedRow {
  const std::uint16_t* codes;
  const float* palette;
  float operator[](int i) const { return palette[codes[i]]; }
};

// f = sum_{i,j,l} g c[0][i] c[1][j] c[2][l] over N0 x N1 x N2 samples,
// contracted axis by axis; each gradient component (grid axes) swaps one
// axis's c for dc. Fixed sizes: fully unrolled. rows(j, l): a row's
// samples, a float pointer or a CodedRow.
template <bool Gradient, int N0, int N1, int N2, class Rows>
double contract(Rows rows, const double (*c)[3], const double (*dc)[3], double* gs) {
  double f = 0;
  if (Gradient) gs[0] = gs[1] = gs[2] = 0;
  for (int l = 0; l < N2; ++l) {
    double fy = 0, fyx = 0, fyy = 0;
    for (int j = 0; j < N1; ++j) {
      const auto row = rows(j, l);
      double fx = 0, fxx = 0;
      for (int i = 0; i < N0; ++i) {
        fx += c[0][i] * double(row[i]);
        if (Gradient) fxx += dc[0][i] * double(row[i]);
      }
      fy += c[1][j] * fx;
      if (Gradient) {
        fyx += c[1][j] * fxx;
        fyy += dc[1][j] * fx;
      }
    }
    f += c[2][l] * fy;
    if (Gradient) {
      gs[0] += c[2][l] * fyx;
      gs[1] += c[2][l] * fyy;
      gs[2] += dc[2][l] * fy;
    }
  }
  return f;
}

} // namespace

template <bool Gradient> double PartitionOfUnity::combine(const Stencil& s, Vec3* gradient) const {
  if (s.n[0] == 0) {
    const double nan = std::numeric_limits<double>::quiet_NaN();
    if (Gradient) *gradient = {nan, nan, nan};
    return nan;
  }
  double f, gs[3];
  auto shape = [&](auto rows) {
    switch ((s.n[0] - 2) | (s.n[1] - 2) << 1 | (s.n[2] - 2) << 2) {
      case 0: return contract<Gradient, 2, 2, 2>(rows, s.c, s.dc, gs);
      case 1: return contract<Gradient, 3, 2, 2>(rows, s.c, s.dc, gs);
      case 2: return contract<Gradient, 2, 3, 2>(rows, s.c, s.dc, gs);
      case 3: return contract<Gradient, 3, 3, 2>(rows, s.c, s.dc, gs);
      case 4: return contract<Gradient, 2, 2, 3>(rows, s.c, s.dc, gs);
      case 5: return contract<Gradient, 3, 2, 3>(rows, s.c, s.dc, gs);
      case 6: return contract<Gradient, 2, 3, 3>(rows, s.c, s.dc, gs);
      default: return contract<Gradient, 3, 3, 3>(rows, s.c, s.dc, gs);
    }
  };
  if (g_.dense()) {
    const float* base = static_cast<const float*>(s.row[0]);
    const long s1 = stride_[1], s2 = stride_[2];
    f = shape([=](int j, int l) { return base + j * s1 + l * s2; });
  } else if (g_.coded()) {
    const float* palette = g_.palette();
    f = shape([&](int j, int l) { return CodedRow{static_cast<const std::uint16_t*>(s.row[l * 3 + j]), palette}; });
  } else {
    f = shape([&](int j, int l) { return static_cast<const float*>(s.row[l * 3 + j]); });
  }
  if (Gradient) {
    // Grid-axis derivatives to world: p = origin + D s, so df/dp = D df/ds.
    const auto& D = g_.direction;
    for (int j = 0; j < 3; ++j) (*gradient)[j] = D[j * 3] * gs[0] + D[j * 3 + 1] * gs[1] + D[j * 3 + 2] * gs[2];
  }
  return f;
}

// Software pipeline: point i is located (its weights computed) and its
// samples prefetched kAhead points before it is combined, so the cache
// misses of several points overlap instead of stalling one after another.
template <bool Gradient>
void PartitionOfUnity::evaluate_many(const Vec3* points, std::size_t n, double* f, Vec3* gradients) const {
  constexpr std::size_t kAhead = 8;
  Stencil ring[kAhead];
  for (std::size_t i = 0; i < n + kAhead; ++i) {
    Stencil& s = ring[i % kAhead];
    if (i >= kAhead) {
      const std::size_t j = i - kAhead;
      f[j] = combine<Gradient>(s, Gradient ? &gradients[j] : nullptr);
    }
    if (i < n) {
      locate<Gradient>(points[i], s);
      prefetch(s);
    }
  }
}

double PartitionOfUnity::value(const Vec3& p) const {
  Stencil s;
  locate<false>(p, s);
  return combine<false>(s, nullptr);
}

double PartitionOfUnity::value_gradient(const Vec3& p, Vec3& gradient) const {
  Stencil s;
  locate<true>(p, s);
  return combine<true>(s, &gradient);
}

void PartitionOfUnity::values(const Vec3* points, std::size_t n, double* f, Vec3* gradients) const {
  if (gradients) evaluate_many<true>(points, n, f, gradients);
  else evaluate_many<false>(points, n, f, nullptr);
}

} // namespace imgmesh
