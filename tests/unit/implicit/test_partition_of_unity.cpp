// The partition of unity f of thesis 6.3 and the properties of 6.4.
#include "helpers.hpp"
#include "image/io.hpp"
#include "implicit/implicit_file.hpp"
#include "implicit/partition_of_unity.hpp"
#include "util/error.hpp"

#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>
#include <thread>
#include <vector>

using namespace imgmesh;
using namespace imgmesh::test;

namespace {

// A torus (genus 1) of radii R, r around the grid centre, in index units.
BinaryImage torus(std::size_t n, Vec3 sp = {1, 1, 1}) {
  BinaryImage im(grid(n, n, n, sp), 0);
  const double c = (n - 1) / 2.0, R = n / 4.0, r = n / 9.0;
  for (std::size_t z = 0; z < n; ++z)
    for (std::size_t y = 0; y < n; ++y)
      for (std::size_t x = 0; x < n; ++x) {
        const double q = std::hypot(x - c, y - c) - R;
        im(x, y, z) = q * q + (z - c) * (z - c) <= r * r;
      }
  make_well_composed_slow(im);
  return im;
}

Vec3 centre_world(const Geometry& g, long x, long y, long z) { return g.world(double(x), double(y), double(z)); }

// Every voxel centre: f = g (so f has the image's sign).
void check_sign_at_centres(const PartitionOfUnity& f) {
  const SampleGrid& g = f.samples();
  for (long z = 0; z < long(g.size[2]); ++z)
    for (long y = 0; y < long(g.size[1]); ++y)
      for (long x = 0; x < long(g.size[0]); ++x) {
        const double v = f.value(centre_world(g, x, y, z));
        const double s = g(x, y, z);
        if (!((v < 0) == (s < 0)) || std::abs(v - s) > 1e-9 * (1 + std::abs(s))) {
          INFO(x << " " << y << " " << z << " f=" << v << " g=" << s);
          REQUIRE(false);
        }
      }
}

double max_abs_g(const PartitionOfUnity& f) {
  double m = 0;
  for (float v : f.samples().to_image().data) m = std::max(m, double(std::abs(v)));
  return m;
}

} // namespace

TEST_CASE("eta: smooth step from 1 to 0 (errata form)", "[pu]") {
  REQUIRE(pu_eta(0) == 1.0);
  REQUIRE(pu_eta(1) == 0.0);
  REQUIRE(pu_eta(-0.5) == 1.0);
  REQUIRE(pu_eta(1.5) == 0.0);
  REQUIRE(pu_h(0) == 1.0);
  REQUIRE(pu_h(1) == 0.0);
  double prev = 1;
  for (int i = 1; i < 1000; ++i) {
    const double u = i / 1000.0;
    double de = 0;
    const double e = pu_eta(u, &de);
    REQUIRE(e <= prev);
    REQUIRE(e + pu_eta(1 - u) == Approx(1).margin(1e-15));  // neighbouring cells add to 1
    const double h = 1e-6;
    REQUIRE(de == Approx((pu_eta(u + h) - pu_eta(u - h)) / (2 * h)).margin(1e-6));
    prev = e;
  }
  // All derivatives vanish at the ends: eta is flat to high order there.
  for (double t : {1e-3, 1e-2, 3e-2}) {
    double d0 = 0, d1 = 0;
    pu_eta(t, &d0);
    pu_eta(1 - t, &d1);
    REQUIRE(std::abs(d0) < 1e-6);
    REQUIRE(std::abs(d1) < 1e-6);
    REQUIRE(1 - pu_eta(t) < 1e-8);
  }
}

TEST_CASE("f has the sign of the image at every voxel centre", "[pu]") {
  SECTION("torus") { check_sign_at_centres(implicit_from_well_composed(torus(24))); }
  SECTION("random well-composed images, anisotropic, rotated") {
    for (unsigned seed = 1; seed <= 6; ++seed) {
      BinaryImage im = random_wc(14, 12, 13, seed, seed % 2 ? Vec3{1, 1, 1} : Vec3{0.7, 1.0, 1.6});
      if (seed % 3 == 0) rotate(im);
      REQUIRE(count_critical(im) == 0);
      check_sign_at_centres(implicit_from_well_composed(im, nullptr, 2));
    }
  }
  SECTION("real image (bunny, made well-composed)") {
    BinaryImage im = read_foreground(IMGMESH_TEST_DATA "/bunny00-96.nrrd", Selection{});
    make_well_composed_slow(im);
    REQUIRE(count_critical(im) == 0);
    ImplicitReport rep;
    const PartitionOfUnity f = implicit_from_well_composed(im, &rep, 2);
    check_sign_at_centres(f);
    // The sign of g is the image (padded where the foreground touched the border).
    const SampleGrid& g = f.samples();
    for (std::size_t z = 0; z < im.size[2]; ++z)
      for (std::size_t y = 0; y < im.size[1]; ++y)
        for (std::size_t x = 0; x < im.size[0]; ++x)
          REQUIRE((g(x + rep.padded_before[0], y + rep.padded_before[1], z + rep.padded_before[2]) < 0) ==
                  (im(x, y, z) != 0));
  }
}

TEST_CASE("f and grad f are continuous across cell faces, edges, corners and weight transitions", "[pu]") {
  for (unsigned seed = 1; seed <= 3; ++seed) {
    BinaryImage im = random_wc(12, 11, 10, seed, seed == 2 ? Vec3{0.6, 1.0, 1.5} : Vec3{1, 1, 1});
    if (seed == 3) rotate(im);
    const PartitionOfUnity f = implicit_from_well_composed(im);
    const SampleGrid& g = f.samples();
    const double scale = max_abs_g(f);
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> u(0, 1);
    for (int trial = 0; trial < 4000; ++trial) {
      // Snap 1, 2 or 3 coordinates to a grid plane (face, edge, corner), or
      // to a plane +- d_i where the weights stop varying.
      Vec3 q;
      for (int i = 0; i < 3; ++i) q[i] = 1 + u(rng) * (g.size[i] - 3.0);
      const int snapped = 1 + trial % 3;
      const int first = int(rng() % 3);
      const double shift = (trial / 3) % 3 == 0 ? 0.0 : ((trial / 3) % 3 == 1 ? 1.0 : -1.0);
      for (int s = 0; s < snapped; ++s) {
        const int i = (first + s) % 3;
        q[i] = std::round(q[i]) + shift * f.d()[i] / g.spacing[i];
      }
      const double eps = 1e-9;  // index units, on every snapped axis
      Vec3 a = q, b = q;
      for (int s = 0; s < snapped; ++s) {
        const int i = (first + s) % 3;
        a[i] -= eps;
        b[i] += eps;
      }
      Vec3 ga, gb;
      const double fa = f.value_gradient(g.world(a[0], a[1], a[2]), ga);
      const double fb = f.value_gradient(g.world(b[0], b[1], b[2]), gb);
      INFO("seed " << seed << " q " << q[0] << " " << q[1] << " " << q[2]);
      REQUIRE(std::abs(fa - fb) <= 1e-6 * scale);
      for (int i = 0; i < 3; ++i) REQUIRE(std::abs(ga[i] - gb[i]) <= 1e-4 * (1 + std::abs(ga[i])));
    }
  }
}

TEST_CASE("analytic gradient matches central differences", "[pu]") {
  for (unsigned seed = 1; seed <= 3; ++seed) {
    BinaryImage im = random_wc(12, 12, 12, seed + 10, seed == 1 ? Vec3{1, 1, 1} : Vec3{0.6, 1.1, 1.5});
    if (seed == 3) rotate(im);
    const PartitionOfUnity f = implicit_from_well_composed(im);
    const SampleGrid& g = f.samples();
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> u(0, 1);
    for (int trial = 0; trial < 3000; ++trial) {
      Vec3 q;
      for (int i = 0; i < 3; ++i) q[i] = 0.01 + u(rng) * (g.size[i] - 1.02);
      // Half the points inside a weight transition (within d of a plane).
      if (trial % 2) {
        const int i = int(rng() % 3);
        q[i] = std::max(0.01, std::min(g.size[i] - 1.01, std::round(q[i]) + (2 * u(rng) - 1) * f.d()[i] / g.spacing[i]));
      }
      const Vec3 p = g.world(q[0], q[1], q[2]);
      Vec3 grad;
      const double v = f.value_gradient(p, grad);
      REQUIRE(v == Approx(f.value(p)).epsilon(1e-14).margin(1e-14));
      const double h = 1e-6;
      for (int j = 0; j < 3; ++j) {
        Vec3 pp = p, pm = p;
        pp[j] += h;
        pm[j] -= h;
        const double fd = (f.value(pp) - f.value(pm)) / (2 * h);
        INFO("trial " << trial << " axis " << j);
        REQUIRE(grad[j] == Approx(fd).margin(1e-5).epsilon(1e-5));
      }
    }
  }
}

TEST_CASE("Lemmas 6.4.1, 6.4.2, 6.4.5: vertex boxes keep the sign; edge regions are monotone, one zero", "[pu]") {
  for (unsigned seed = 1; seed <= 4; ++seed) {
    BinaryImage im = random_wc(12, 11, 12, seed + 20, seed % 2 ? Vec3{1, 1, 1} : Vec3{1.3, 0.7, 1.0});
    const PartitionOfUnity f = implicit_from_well_composed(im);
    const SampleGrid& g = f.samples();
    const Vec3 d = f.d();
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> u(0, 1);
    int crossing_edges = 0;
    for (int trial = 0; trial < 3000; ++trial) {
      const int e = int(rng() % 3);  // edge axis
      long v1[3];
      for (int i = 0; i < 3; ++i) v1[i] = long(rng() % (g.size[i] - (i == e ? 1 : 0)));
      long v2[3] = {v1[0], v1[1], v1[2]};
      v2[e] += 1;
      const double g1 = g(v1[0], v1[1], v1[2]), g2 = g(v2[0], v2[1], v2[2]);
      // Vertex box of v1 (Lemma 6.4.1 with boxes): sign of g(v1).
      Vec3 q;
      for (int i = 0; i < 3; ++i)
        q[i] = std::max(0.0, std::min(double(g.size[i] - 1), v1[i] + (2 * u(rng) - 1) * 0.999 * d[i] / g.spacing[i]));
      REQUIRE((f.value(g.world(q[0], q[1], q[2])) < 0) == (g1 < 0));
      // A segment parallel to the edge inside its edge region.
      Vec3 base;
      for (int i = 0; i < 3; ++i)
        base[i] = i == e ? 0.0
                         : std::max(0.0, std::min(double(g.size[i] - 1),
                                                  v1[i] + (2 * u(rng) - 1) * 0.999 * d[i] / g.spacing[i]));
      const double t0 = v1[e] + d[e] / g.spacing[e], t1 = v2[e] - d[e] / g.spacing[e];
      const int steps = 200;
      std::vector<double> vals;
      for (int s = 0; s <= steps; ++s) {
        Vec3 p = base;
        p[e] = t0 + (t1 - t0) * s / steps;
        vals.push_back(f.value(g.world(p[0], p[1], p[2])));
      }
      if ((g1 < 0) != (g2 < 0)) {
        ++crossing_edges;
        const double dir = g2 > g1 ? 1 : -1;
        int zeros = 0;
        for (int s = 0; s < steps; ++s) {
          REQUIRE(dir * (vals[s + 1] - vals[s]) > 0);
          zeros += (vals[s] < 0) != (vals[s + 1] < 0);
        }
        REQUIRE((vals.front() < 0) == (g1 < 0));
        REQUIRE((vals.back() < 0) == (g2 < 0));
        REQUIRE(zeros == 1);
      } else {
        for (double v : vals) REQUIRE((v < 0) == (g1 < 0));
      }
    }
    REQUIRE(crossing_edges > 0);
  }
}

TEST_CASE("Lemmas 6.4.1-6.4.4: no zero of f in a region whose feature's corners agree in sign", "[pu]") {
  // Per axis a point is "near" a grid plane when within d_i of it; near on
  // 3/2/1/0 axes = vertex/edge/face/centre region of the feature spanned by
  // the nearest planes (near axes) and the cell (far axes). If all corners of
  // that feature have one sign, f has that sign at the point.
  for (unsigned seed = 1; seed <= 4; ++seed) {
    BinaryImage im = random_wc(13, 12, 11, seed + 40, seed % 2 ? Vec3{1, 1, 1} : Vec3{0.6, 1.4, 0.9});
    if (seed == 4) rotate(im);
    const PartitionOfUnity f = implicit_from_well_composed(im);
    const SampleGrid& g = f.samples();
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> u(0, 1);
    int agreeing = 0;
    for (int trial = 0; trial < 40000; ++trial) {
      double q[3];
      for (int i = 0; i < 3; ++i) q[i] = u(rng) * (g.size[i] - 1);
      // Bias half the points into transition zones.
      if (trial % 2)
        for (int i = 0; i < 3; ++i)
          if (rng() % 2) q[i] = std::max(0.0, std::min(double(g.size[i] - 1), std::round(q[i]) + (2 * u(rng) - 1) * f.d()[i] / g.spacing[i]));
      long lo[3], hi[3];
      for (int i = 0; i < 3; ++i) {
        const double r = std::round(q[i]);
        if (std::abs(q[i] - r) * g.spacing[i] < f.d()[i]) lo[i] = hi[i] = long(r);
        else {
          lo[i] = std::min(long(std::floor(q[i])), long(g.size[i]) - 2);
          hi[i] = lo[i] + 1;
        }
      }
      int neg = 0, total = 0;
      for (long z = lo[2]; z <= hi[2]; ++z)
        for (long y = lo[1]; y <= hi[1]; ++y)
          for (long x = lo[0]; x <= hi[0]; ++x) {
            neg += g(x, y, z) < 0;
            ++total;
          }
      if (neg != 0 && neg != total) continue;
      ++agreeing;
      const double v = f.value(g.world(q[0], q[1], q[2]));
      INFO("seed " << seed << " q " << q[0] << " " << q[1] << " " << q[2]);
      REQUIRE(v != 0);
      REQUIRE((v < 0) == (neg == total));
    }
    REQUIRE(agreeing > 1000);
  }
}

namespace {

// Brute force L_max: sample |d f_k / d x_i| on a dense lattice of the
// 1.8-delta box C'_k (thesis 6.3.2), from the thesis's polynomial form.
// L_max over the cells of the foreground's box grown by the margin m (those
// whose 8 vertices lie in it); with `beyond`, what the cells far from S (no
// vertex with |g| < R) need instead of L_max (6.4.2 at their vertices): max
// over them of sum_i M_i d_i / min |g(v)|, which must be < 1, and their
// largest M_i, at most 1.8^2 (g is 1-Lipschitz); `near_inside`: every cell
// with a vertex under R lies in the grown box; `near_max`: the largest L_k
// of those cells.
double brute_lmax(const FloatImage& g, const std::array<std::size_t, 3>& margin, const Vec3& d = {0, 0, 0},
                  double* beyond = nullptr, double* m_beyond = nullptr, bool* near_inside = nullptr,
                  double* near_max = nullptr) {
  double best = 0;
  const double r = 0.65 * (g.spacing[0] + g.spacing[1] + g.spacing[2]);
  long lo[3] = {1L << 40, 1L << 40, 1L << 40}, hi[3] = {-(1L << 40), -(1L << 40), -(1L << 40)};
  for (long z = 0; z < long(g.size[2]); ++z)
    for (long y = 0; y < long(g.size[1]); ++y)
      for (long x = 0; x < long(g.size[0]); ++x)
        if (g(x, y, z) < 0) {
          const long c[3] = {x, y, z};
          for (int a = 0; a < 3; ++a) lo[a] = std::min(lo[a], c[a] - long(margin[a])), hi[a] = std::max(hi[a], c[a] + long(margin[a]));
        }
  if (near_inside) *near_inside = true;
  for (std::size_t z = 0; z + 1 < g.size[2]; ++z)
    for (std::size_t y = 0; y + 1 < g.size[1]; ++y)
      for (std::size_t x = 0; x + 1 < g.size[0]; ++x) {
        const long k[3] = {long(x), long(y), long(z)};
        bool in_box = true;
        for (int a = 0; a < 3; ++a) in_box = in_box && k[a] >= lo[a] && k[a] + 1 <= hi[a];
        auto F = [&](int m, int n, int l) { return double(g(x + m, y + n, z + l)); };
        double least = HUGE_VAL;
        for (int k = 0; k < 8; ++k) least = std::min(least, std::abs(F(k & 1, (k >> 1) & 1, k >> 2)));
        // u = a + b z + c y + d yz + e x + f xz + g xy + h xyz (proof of Prop. 6.4.1)
        const double b = F(0, 0, 1) - F(0, 0, 0), c = F(0, 1, 0) - F(0, 0, 0);
        const double dd = F(0, 0, 0) + F(0, 1, 1) - F(0, 0, 1) - F(0, 1, 0);
        const double e = F(1, 0, 0) - F(0, 0, 0);
        const double f = F(0, 0, 0) + F(1, 0, 1) - F(0, 0, 1) - F(1, 0, 0);
        const double gg = F(0, 0, 0) + F(1, 1, 0) - F(0, 1, 0) - F(1, 0, 0);
        const double h = F(1, 1, 1) - F(1, 1, 0) - F(1, 0, 1) + F(1, 0, 0) - F(0, 1, 1) + F(0, 1, 0) + F(0, 0, 1) - F(0, 0, 0);
        double M[3] = {0, 0, 0};
        const int N = 6;
        for (int i = 0; i <= N; ++i)
          for (int j = 0; j <= N; ++j)
            for (int k = 0; k <= N; ++k) {
              const double X = -0.4 + 1.8 * i / N, Y = -0.4 + 1.8 * j / N, Z = -0.4 + 1.8 * k / N;
              M[0] = std::max(M[0], std::abs(e + f * Z + gg * Y + h * Y * Z) / g.spacing[0]);
              M[1] = std::max(M[1], std::abs(c + dd * Z + gg * X + h * X * Z) / g.spacing[1]);
              M[2] = std::max(M[2], std::abs(b + dd * Y + f * X + h * X * Y) / g.spacing[2]);
            }
        if (in_box) best = std::max(best, std::sqrt(3.0) * std::max({M[0], M[1], M[2]}));
        if (near_max && least < r) *near_max = std::max(*near_max, std::sqrt(3.0) * std::max({M[0], M[1], M[2]}));
        if (least < r && !in_box && near_inside) *near_inside = false;
        if (least >= r) {
          if (beyond) *beyond = std::max(*beyond, (M[0] * d[0] + M[1] * d[1] + M[2] * d[2]) / least);
          if (m_beyond) *m_beyond = std::max({*m_beyond, M[0], M[1], M[2]});
        }
      }
  return best;
}

} // namespace

TEST_CASE("d, g_min and L_max as the thesis defines them (brute force)", "[pu]") {
  for (unsigned seed = 1; seed <= 4; ++seed) {
    const Vec3 sp = seed % 2 ? Vec3{1, 1, 1} : Vec3{0.5, 1.0, 1.75};
    BinaryImage im = random_wc(9, 8, 10, seed + 30, sp, 4);
    const PartitionOfUnity f = implicit_from_well_composed(im);
    const FloatImage g = f.samples().to_image();
    // g_min from brute-force distances of the (possibly padded) grid.
    BinaryImage sign(g.geometry(), 0);
    for (std::size_t i = 0; i < g.data.size(); ++i) sign.data[i] = g.data[i] < 0;
    double gmin = 1e300;
    for (long z = 0; z < long(g.size[2]); ++z)
      for (long y = 0; y < long(g.size[1]); ++y)
        for (long x = 0; x < long(g.size[0]); ++x) gmin = std::min(gmin, std::abs(brute_distance(sign, x, y, z)));
    REQUIRE(f.g_min() == Approx(gmin).epsilon(1e-6));
    // Every voxel centre is at least half a voxel from bdCA(X).
    REQUIRE(gmin >= 0.5 * std::min({sp[0], sp[1], sp[2]}) - 1e-6);
    double beyond = 0, m_beyond = 0;
    bool near_inside = false;
    const double lmax = brute_lmax(g, PartitionOfUnity::weight_margin(sp), f.d(), &beyond, &m_beyond, &near_inside);
    REQUIRE(f.l_max() == Approx(lmax).epsilon(1e-9));
    // The cells far from S hold 6.4.2 at their vertices by distance alone,
    // and the near ones all count in L_max.
    REQUIRE(beyond < 1);
    REQUIRE(m_beyond <= 3.24 * (1 + 1e-6));
    REQUIRE(near_inside);
    for (int i = 0; i < 3; ++i) {
      REQUIRE(f.d()[i] == Approx(std::min(sp[i] / 5, gmin / (2 * lmax))).epsilon(1e-6));
      REQUIRE(f.d()[i] <= sp[i] / 5 * (1 + 1e-12));
    }
  }
}

TEST_CASE("copies evaluate identically; concurrent evaluation is consistent", "[pu]") {
  const PartitionOfUnity f = implicit_from_well_composed(torus(16, {0.8, 1.0, 1.2}));
  PartitionOfUnity copy = f;
  PartitionOfUnity moved = std::move(copy);
  const SampleGrid& g = f.samples();
  std::vector<Vec3> pts;
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> u(0, 1);
  for (int i = 0; i < 20000; ++i) pts.push_back(g.world(u(rng) * 15, u(rng) * 15, u(rng) * 15));
  std::vector<double> a(pts.size()), b(pts.size());
  std::thread t1([&] { for (std::size_t i = 0; i < pts.size(); ++i) a[i] = f.value(pts[i]); });
  std::thread t2([&] { for (std::size_t i = 0; i < pts.size(); ++i) b[i] = moved.value(pts[i]); });
  t1.join();
  t2.join();
  REQUIRE(a == b);
  REQUIRE(f.in_domain(g.world(0, 0, 0)));
  REQUIRE(f.in_domain(g.world(15, 15, 15)));
  REQUIRE_FALSE(f.in_domain(g.world(-0.01, 3, 3)));
  REQUIRE_FALSE(f.in_domain(g.world(3, 15.01, 3)));
}

// f straight from (6.6)-(6.9): sum over the cells k around q (index units)
// of phi_k f_k, w_k = prod_i eta((|t_i| - alpha_1) / beta) with t_i the
// offset from the cell's centre, f_k the trilinear interpolant (extrapolated
// outside C_k).
double reference_f(const PartitionOfUnity& f, const Vec3& q) {
  const SampleGrid& g = f.samples();
  long lo[3];
  for (int i = 0; i < 3; ++i) lo[i] = std::max(0L, std::min(long(q[i]), long(g.size[i]) - 2) - 1);
  double sum_w = 0, sum_wf = 0;
  for (long c = lo[2]; c <= std::min(lo[2] + 2, long(g.size[2]) - 2); ++c)
    for (long b = lo[1]; b <= std::min(lo[1] + 2, long(g.size[1]) - 2); ++b)
      for (long a = lo[0]; a <= std::min(lo[0] + 2, long(g.size[0]) - 2); ++a) {
        const long k[3] = {a, b, c};
        double w = 1, loc[3];
        for (int i = 0; i < 3; ++i) {
          const double delta = g.spacing[i], d = f.d()[i];
          const double t = (q[i] - (double(k[i]) + 0.5)) * delta;
          w *= pu_eta((std::abs(t) - (delta / 2 - d)) / (2 * d));
          loc[i] = q[i] - double(k[i]);
        }
        if (w == 0) continue;
        double fk = 0;
        for (int corner = 0; corner < 8; ++corner) {
          double basis = 1;
          for (int i = 0; i < 3; ++i) basis *= (corner >> i & 1) ? loc[i] : 1 - loc[i];
          fk += basis * g(a + (corner & 1), b + (corner >> 1 & 1), c + (corner >> 2 & 1));
        }
        sum_w += w;
        sum_wf += w * fk;
      }
  return sum_wf / sum_w;
}

TEST_CASE("f equals the thesis's sum of phi_k f_k over the neighbouring cells", "[pu]") {
  for (unsigned seed = 1; seed <= 3; ++seed) {
    BinaryImage im = random_wc(11, 12, 10, seed + 30, seed == 2 ? Vec3{0.6, 1.0, 1.5} : Vec3{1, 1, 1});
    if (seed == 3) rotate(im);
    const PartitionOfUnity f = implicit_from_well_composed(im);
    const SampleGrid& g = f.samples();
    const double scale = max_abs_g(f);
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> u(0, 1);
    for (int trial = 0; trial < 20000; ++trial) {
      Vec3 q;
      for (int i = 0; i < 3; ++i) q[i] = u(rng) * double(g.size[i] - 1);
      // Most points within d of 1, 2 or 3 grid planes (where cells blend),
      // including the domain's end planes and the ends of the weight ramps.
      for (int i = 0; i < 3; ++i)
        if ((trial >> i) % 4 != 0) {
          const double ramp = f.d()[i] / g.spacing[i];
          const double off = trial % 5 == 0 ? (trial % 2 ? ramp : -ramp) : (2 * u(rng) - 1) * ramp;
          q[i] = std::min(double(g.size[i] - 1), std::max(0.0, std::round(q[i]) + off));
        }
      INFO("seed " << seed << " q " << q[0] << " " << q[1] << " " << q[2]);
      REQUIRE(std::abs(f.value(g.world(q[0], q[1], q[2])) - reference_f(f, q)) <= 1e-12 * scale);
    }
  }
}

TEST_CASE("values() at many points equals value() and value_gradient() point by point", "[pu]") {
  BinaryImage im = random_wc(14, 12, 13, 7, Vec3{0.7, 1.0, 1.6});
  rotate(im);
  const PartitionOfUnity f = implicit_from_well_composed(im);
  const SampleGrid& g = f.samples();
  std::mt19937 rng(9);
  std::uniform_real_distribution<double> u(-0.2, 1.2);  // some points outside the domain
  std::vector<Vec3> pts;
  for (int i = 0; i < 5000; ++i) {
    Vec3 q;
    for (int k = 0; k < 3; ++k) q[k] = u(rng) * double(g.size[k] - 1);
    if (i % 3 == 0) q[i % 2] = std::round(q[i % 2]) + (u(rng) - 0.5) * f.d()[i % 2] / g.spacing[i % 2];
    pts.push_back(g.world(q[0], q[1], q[2]));
  }
  pts[17][1] = std::nan("");
  for (std::size_t n : {std::size_t(0), std::size_t(1), std::size_t(5), pts.size()}) {
    std::vector<double> v(n), vg(n);
    std::vector<Vec3> gr(n);
    f.values(pts.data(), n, v.data());
    f.values(pts.data(), n, vg.data(), gr.data());
    for (std::size_t i = 0; i < n; ++i) {
      Vec3 ref;
      const double fr = f.value_gradient(pts[i], ref);
      if (i == 17) {
        REQUIRE(std::isnan(v[i]));
        REQUIRE(std::isnan(vg[i]));
        REQUIRE(std::isnan(gr[i][0]));
        continue;
      }
      REQUIRE(v[i] == f.value(pts[i]));
      REQUIRE(vg[i] == fr);
      REQUIRE(gr[i] == ref);
    }
  }
}

TEST_CASE("constructor rejects bad samples and a d beyond the bound", "[pu]") {
  FloatImage g(grid(4, 4, 4), 1.0f);
  g(1, 1, 1) = -0.5f;
  REQUIRE_NOTHROW(PartitionOfUnity(g));
  FloatImage zero = g;
  zero(2, 2, 2) = 0;
  REQUIRE_THROWS_AS(PartitionOfUnity(zero), Error);
  FloatImage nan = g;
  nan(2, 2, 2) = std::nanf("");
  REQUIRE_THROWS_AS(PartitionOfUnity(nan), Error);
  FloatImage thin(grid(4, 1, 4), 1.0f);
  REQUIRE_THROWS_AS(PartitionOfUnity(thin), Error);
  REQUIRE_THROWS_AS(PartitionOfUnity(g, Vec3{0.3, 0.3, 0.3}), Error);  // > delta/5
}

// The meshers' f' (on g clamped at clamp_for's T, far samples not stored):
// its zero set and signs are f's, it is f wherever |f| <= 2e, and wherever
// the two differ both exceed 2e (PartitionOfUnity::clamp_for's argument).
TEST_CASE("f on clamped samples: f's signs everywhere, f itself wherever |f| <= 2e", "[pu]") {
  for (unsigned seed = 1; seed <= 4; ++seed) {
    const Vec3 sp = seed % 2 ? Vec3{1, 1, 1} : Vec3{0.6, 0.6, 1.3};
    BinaryImage im = random_wc(34, 30, 28, seed + 40, sp, 3);
    if (seed == 3) rotate(im);
    const PartitionOfUnity f = implicit_from_well_composed(im);
    const double e = seed == 4 ? 0.0 : 0.3 * sp[0];
    const FloatImage g = f.samples().to_image();
    const float t = PartitionOfUnity::clamp_for(g, e);
    // Blocks (what the meshers get on large grids), or dense on odd seeds.
    const auto storage = seed % 2 ? SampleGrid::Storage::dense : SampleGrid::Storage::blocks;
    const PartitionOfUnity fc(g, f.d(), 1, t, storage);
    INFO("seed " << seed << ", T " << t);
    if (!fc.samples().dense()) REQUIRE(fc.samples().stored_blocks() < fc.samples().blocks());
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> u(0, 1);
    long differ = 0, near = 0;
    for (int i = 0; i < 200000; ++i) {
      const Vec3 p = g.world(u(rng) * double(g.size[0] - 1), u(rng) * double(g.size[1] - 1), u(rng) * double(g.size[2] - 1));
      Vec3 gr, grc;
      const double a = f.value_gradient(p, gr), b = fc.value_gradient(p, grc);
      REQUIRE((a < 0) == (b < 0));
      REQUIRE(b != 0);
      if (std::abs(a) <= 2 * e || std::abs(b) <= 2 * e) {
        ++near;
        REQUIRE(a == b);
        REQUIRE(gr == grc);
      }
      if (a != b) {
        ++differ;
        REQUIRE(std::abs(a) > 2 * e);
        REQUIRE(std::abs(b) > 2 * e);
      }
    }
    CHECK(differ > 0);  // the clamp changed f somewhere: the test saw both kinds of points
    if (e > 0) CHECK(near > 100);
  }
  // Under the stencil's diameter the argument fails: refused.
  const PartitionOfUnity f = implicit_from_well_composed(random_wc(12, 12, 12, 7));
  CHECK_THROWS_AS(PartitionOfUnity(f.samples().to_image(), f.d(), 1, 0.5f * PartitionOfUnity::clamp_for(f.samples(), 0)), Error);
}

// Blocks of a distance map hold 16-bit codes into a palette of its few
// values (here made a few thousand, more than a byte's codes: 11 steps of
// noise); with noise of every value it takes more than kCodes values and
// its blocks stay floats. Either gives dense f's numbers, one point at a
// time or many.
TEST_CASE("f on coded blocks and on float blocks is f on dense samples", "[pu]") {
  const Vec3 sp{0.6, 0.7, 1.3};
  const FloatImage g = implicit_from_well_composed(random_wc(48, 44, 40, 91, sp, 3)).samples().to_image();
  FloatImage stepped = g, noisy = g;
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> u(0, 1);
  for (float& v : stepped.data) v += float(std::round(10 * u(rng)) * 1e-3);
  for (float& v : noisy.data) v += float(0.01 * (u(rng) - 0.5));
  for (const bool coded : {true, false}) {
    const FloatImage& im = coded ? stepped : noisy;
    const float t = coded ? PartitionOfUnity::clamp_for(im, 0) : std::numeric_limits<float>::infinity();
    const PartitionOfUnity dense(im, {0, 0, 0}, 1, t, SampleGrid::Storage::dense);
    const PartitionOfUnity blocks(im, dense.d(), 1, t, SampleGrid::Storage::blocks);
    REQUIRE(blocks.samples().coded() == coded);
    REQUIRE(!blocks.samples().dense());
    std::vector<Vec3> ps;
    for (int i = 0; i < 20000; ++i)
      ps.push_back(im.world(u(rng) * double(im.size[0] - 1), u(rng) * double(im.size[1] - 1), u(rng) * double(im.size[2] - 1)));
    std::vector<double> fd(ps.size()), fb(ps.size());
    std::vector<Vec3> gd(ps.size()), gb(ps.size());
    dense.values(ps.data(), ps.size(), fd.data(), gd.data());
    blocks.values(ps.data(), ps.size(), fb.data(), gb.data());
    for (std::size_t i = 0; i < ps.size(); ++i) {
      INFO("coded " << coded << ", point " << i);
      REQUIRE(fb[i] == fd[i]);
      REQUIRE(gb[i] == gd[i]);
      REQUIRE(blocks.value(ps[i]) == fd[i]);
    }
  }
}

// weight_constant computes L_k only where a cheaper bound of it exceeds the
// largest so far: on rough samples (not a distance: every cell's L_k
// differs, many near the maximum) that must still give the brute force's.
TEST_CASE("L_max on rough samples is the brute force's, smooth cells skipped or not", "[pu]") {
  std::mt19937 rng(11);
  for (const Vec3 sp : {Vec3{1, 1, 1}, Vec3{0.6, 1.4, 0.9}}) {
    for (double rough : {0.05, 0.5, 3.0}) {
      FloatImage g(grid(14, 11, 9, sp));
      std::uniform_real_distribution<double> u(-rough, rough);
      for (std::size_t z = 0; z < 9; ++z)
        for (std::size_t y = 0; y < 11; ++y)
          for (std::size_t x = 0; x < 14; ++x) {
            const double smooth = 0.3 * double(x) * sp[0] - 2.0 + 0.1 * double(y * z);
            double v = smooth + u(rng);
            if (std::abs(v) < 0.01) v = 0.01;
            g(x, y, z) = float(v);
          }
      double gm, lm;
      PartitionOfUnity::weight_constant(g, &gm, &lm);
      REQUIRE(lm == Approx(brute_lmax(g, PartitionOfUnity::weight_margin(sp))).epsilon(1e-9));
    }
  }
}

TEST_CASE("d depends on g near S only: the cells of the foreground's box grown by weight_margin", "[pu]") {
  for (unsigned seed = 1; seed <= 3; ++seed) {
    const Vec3 sp = seed == 2 ? Vec3{0.6, 0.6, 1.3} : Vec3{1, 1, 1};
    BinaryImage small = random_wc(10, 9, 8, seed + 70, sp, 2);
    BinaryImage big = pad(small, {3, 2, 1}, {25, 4, 3}, std::uint8_t(0));
    const FloatImage g = implicit_from_well_composed(big).samples().to_image();
    double gm, lm;
    const Vec3 d = PartitionOfUnity::weight_constant(g, &gm, &lm);
    // Far beyond the grown box, a steep ridge (values far above R): the
    // thesis's whole-grid L_max takes it, ours must not.
    FloatImage ridged = g;
    for (std::size_t z = 0; z < g.size[2]; ++z)
      for (std::size_t y = 0; y < g.size[1]; ++y)
        for (std::size_t x = g.size[0] - 8; x < g.size[0]; ++x)
          ridged(x, y, z) = g(x, y, z) + float(0.9 * std::min(sp[0], sp[1]) * double((x + y + z) % 2));
    REQUIRE(brute_lmax(ridged, {1000, 1000, 1000}) > lm);
    double gm2, lm2;
    const Vec3 d2 = PartitionOfUnity::weight_constant(ridged, &gm2, &lm2);
    REQUIRE(gm2 == gm);
    REQUIRE(lm2 == lm);
    REQUIRE(d2 == d);
  }
}

TEST_CASE("f streamed a slice at a time is the constructor's f, checks included", "[pu]") {
  for (unsigned seed = 1; seed <= 3; ++seed) {
    const Vec3 sp = seed == 2 ? Vec3{0.6, 0.6, 1.3} : Vec3{1, 1, 1};
    const FloatImage g = implicit_from_well_composed(random_wc(20, 18, 17, seed + 60, sp, 4)).samples().to_image();
    const float t = seed == 1 ? std::numeric_limits<float>::infinity() : PartitionOfUnity::clamp_for(g, 0.3);
    const auto storage = seed == 3 ? SampleGrid::Storage::blocks : SampleGrid::Storage::automatic;
    const PartitionOfUnity a(g, {0, 0, 0}, 1, t, storage);
    std::size_t z = 0;
    const std::size_t n = g.size[0] * g.size[1];
    const PartitionOfUnity b = PartitionOfUnity::streamed(g, {0, 0, 0}, g, a.d(), t, [&](float* slice) {
      std::copy_n(g.data.data() + z++ * n, n, slice);
    }, storage);
    REQUIRE(z == g.size[2]);
    REQUIRE(b.d() == a.d());
    REQUIRE(b.g_min() == a.g_min());
    REQUIRE(b.l_max() <= a.l_max());  // the cells near S, among those of the grown box
    REQUIRE(b.samples().to_image().data == a.samples().to_image().data);
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> u(0, 1);
    for (int i = 0; i < 2000; ++i) {
      const Vec3 p = g.world(u(rng) * double(g.size[0] - 1), u(rng) * double(g.size[1] - 1), u(rng) * double(g.size[2] - 1));
      REQUIRE(b.value(p) == a.value(p));
    }
  }
  // A zero or NaN sample in a later slice is refused as the constructor does.
  FloatImage g = implicit_from_well_composed(random_wc(10, 10, 10, 5)).samples().to_image();
  g(3, 4, 7) = std::nanf("");
  std::size_t z = 0;
  REQUIRE_THROWS_WITH(PartitionOfUnity::streamed(g, {0, 0, 0}, g, {0.1, 0.1, 0.1}, std::numeric_limits<float>::infinity(),
                                                 [&](float* slice) {
                                                   std::copy_n(g.data.data() + z++ * 100, 100, slice);
                                                 }),
                      Catch::Contains("finite and nonzero"));
}

// streamed() measures only the cells between rows that hold a sample
// under R: its L_max must be the largest L_k of every cell near S.
TEST_CASE("f streamed: L_max is the largest L_k of the cells with a vertex under R (brute force)", "[pu]") {
  for (unsigned seed = 1; seed <= 6; ++seed) {
    const Vec3 sp = seed % 3 == 0 ? Vec3{0.7, 1.2, 0.9} : Vec3{1, 1, 1};
    const FloatImage g = implicit_from_well_composed(random_wc(21, 23, 12, seed + 90, sp, 2)).samples().to_image();
    std::size_t z = 0;
    const std::size_t n = g.size[0] * g.size[1];
    const PartitionOfUnity f = PartitionOfUnity::streamed(g, {0, 0, 0}, g, {0.01, 0.01, 0.01},
                                                          std::numeric_limits<float>::infinity(), [&](float* slice) {
                                                            std::copy_n(g.data.data() + z++ * n, n, slice);
                                                          });
    double near_max = 0;
    brute_lmax(g, {0, 0, 0}, {0, 0, 0}, nullptr, nullptr, nullptr, &near_max);
    REQUIRE(near_max > 0);
    REQUIRE(f.l_max() == Approx(near_max).epsilon(1e-9));
  }
  // One sample under R among rough ones far above it: the largest L_k of
  // the eight cells at it, whichever rows and slices they span.
  std::mt19937 rng(4);
  std::uniform_real_distribution<double> u(3, 6);
  for (int trial = 0; trial < 40; ++trial) {
    FloatImage g(grid(7, 6, 5));
    for (float& v : g.data) v = float(u(rng));
    g(1 + trial % 5, 1 + trial / 5 % 4, 1 + trial / 20 % 3) = 0.5f;
    std::size_t z = 0;
    const PartitionOfUnity f = PartitionOfUnity::streamed(g, {0, 0, 0}, g, {0.001, 0.001, 0.001},
                                                          std::numeric_limits<float>::infinity(), [&](float* slice) {
                                                            std::copy_n(g.data.data() + z++ * 42, 42, slice);
                                                          });
    double near_max = 0;
    brute_lmax(g, {0, 0, 0}, {0, 0, 0}, nullptr, nullptr, nullptr, &near_max);
    REQUIRE(f.l_max() == Approx(near_max).epsilon(1e-9));
  }
}

TEST_CASE("f from bands of x is the constructor's d and streamed f's numbers, the cells across bands included", "[pu]") {
  // g steps only between x = 3 and x = 4, where the first band (one block)
  // ends: the largest L_k is that of cells across two bands. No foreground
  // sample: every cell counts for d.
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> u(0, 1);
  for (const Vec3 sp : {Vec3{1, 1, 1}, Vec3{0.6, 1.4, 0.9}}) {
    FloatImage g(grid(13, 7, 6, sp));
    for (std::size_t z = 0; z < 6; ++z)
      for (std::size_t y = 0; y < 7; ++y)
        for (std::size_t x = 0; x < 13; ++x) g(x, y, z) = float(0.5 + 0.05 * u(rng) + (x >= 4 ? 1.5 : 0));
    const float t = PartitionOfUnity::clamp_for(g, 0.3);
    const PartitionOfUnity whole(g, {0, 0, 0}, 1);
    std::size_t z = 0;
    const std::size_t n = g.size[0] * g.size[1];
    const PartitionOfUnity streamed = PartitionOfUnity::streamed(g, {0, 0, 0}, g, whole.d(), t, [&](float* slice) {
      std::copy_n(g.data.data() + z++ * n, n, slice);
    });
    const PartitionOfUnity bands = PartitionOfUnity::from_bands(
        g, {0, 0, 0}, g, {0, 0, 0}, {-1, -1, -1}, t,
        [&](std::size_t x0, std::size_t x1, float* band) {
          for (std::size_t zz = 0; zz < 6; ++zz)
            for (std::size_t y = 0; y < 7; ++y)
              for (std::size_t x = x0; x < x1; ++x) *band++ = g(x, y, zz);
        },
        1, SampleGrid::Storage::automatic, 7 * 6 * sizeof(float));
    REQUIRE(whole.d()[0] < sp[0] / 5);  // L_max, the step's, sets d
    REQUIRE(bands.d() == whole.d());
    REQUIRE(bands.g_min() == streamed.g_min());
    REQUIRE(bands.l_max() == streamed.l_max());
    REQUIRE(bands.samples().to_image().data == streamed.samples().to_image().data);
  }
  // A negative sample outside the foreground's box given is refused.
  FloatImage g(grid(8, 5, 5));
  g.data.assign(g.count(), 1.0f);
  g(6, 2, 2) = -0.5f;
  CHECK_THROWS_WITH(PartitionOfUnity::from_bands(g, {0, 0, 0}, g, {1, 1, 1}, {3, 3, 3}, 4.0f,
                                                 [&](std::size_t x0, std::size_t x1, float* band) {
                                                   for (std::size_t zz = 0; zz < 5; ++zz)
                                                     for (std::size_t y = 0; y < 5; ++y)
                                                       for (std::size_t x = x0; x < x1; ++x) *band++ = g(x, y, zz);
                                                 }),
                    Catch::Contains("outside the foreground's box"));
}
