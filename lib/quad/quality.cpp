#include "quad/quality.hpp"

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>

#include <algorithm>
#include <cmath>

namespace imgmesh {

namespace {
using K = CGAL::Exact_predicates_inexact_constructions_kernel;
constexpr double kPi = 3.14159265358979323846;
constexpr double kDeg = 180.0 / kPi;

// Angle at p between p->q and p->r, degrees; 0 if an edge has zero length.
double angle_at(const Point2& p, const Point2& q, const Point2& r) {
  const double ux = q[0] - p[0], uy = q[1] - p[1];
  const double vx = r[0] - p[0], vy = r[1] - p[1];
  const double cr = ux * vy - uy * vx, dt = ux * vx + uy * vy;
  if ((ux == 0 && uy == 0) || (vx == 0 && vy == 0)) return 0;
  return std::atan2(std::fabs(cr), dt) * kDeg;  // atan2 is accurate near 0 and 180
}

// Interior angle of a counter-clockwise polygon at o, between the next
// corner n and the previous one r: above 180 at a reflex (right-turn) corner.
double corner_angle(const Point2& o, const Point2& n, const Point2& r) {
  const double ang = angle_at(o, n, r);
  const double cr = (n[0] - o[0]) * (r[1] - o[1]) - (n[1] - o[1]) * (r[0] - o[0]);
  return cr < 0 ? 360 - ang : ang;
}

// A number in [0, 4] that orders corners as corner_angle does (0 to 360),
// from the cross and dot products of the corner's edges, without trigonometry.
double pseudo_angle(double cr, double dt) {
  const double s = std::fabs(dt) + std::fabs(cr);
  if (!(s > 0)) return 0;  // a zero-length edge: angle 0
  return cr >= 0 ? 1 - dt / s : 3 + dt / s;
}
} // namespace

double min_triangle_angle(const Point2& a, const Point2& b, const Point2& c) {
  const double A = angle_at(a, b, c), B = angle_at(b, c, a);
  const double C = std::max(0.0, 180.0 - A - B);
  if (A == 0 || B == 0) return 0;
  return std::min({A, B, C});
}

namespace {
// sin of the smallest angle of (a, b, c): it is opposite the shortest edge
// and at most 60 degrees, where sin is monotone, so no trigonometry is
// needed to compare (sin = twice the area over the other two edges).
double sin_min_angle(const Point2& a, const Point2& b, const Point2& c) {
  const double abx = b[0] - a[0], aby = b[1] - a[1];
  const double bcx = c[0] - b[0], bcy = c[1] - b[1];
  const double cax = a[0] - c[0], cay = a[1] - c[1];
  const double lab = abx * abx + aby * aby, lbc = bcx * bcx + bcy * bcy, lca = cax * cax + cay * cay;
  const double cr = std::fabs(abx * cay - aby * cax);
  double den;
  if (lab <= lbc && lab <= lca) den = lbc * lca;
  else if (lbc <= lca) den = lab * lca;
  else den = lab * lbc;
  if (!(den > 0)) return 0;
  return std::min(1.0, cr / std::sqrt(den));
}
} // namespace

double joe_mu(const Point2& a, const Point2& b, const Point2& c, const Point2& d) {
  // Diagonal bd: T1 = [a,b,d], T2 = [c,d,b]; diagonal ac: T3 = [a,b,c], T4 = [d,a,c].
  // mu <= 45 degrees, so one asin of the smallest sine gives it.
  const double s = std::min(std::min(sin_min_angle(a, b, d), sin_min_angle(c, d, b)),
                            std::min(sin_min_angle(a, b, c), sin_min_angle(d, a, c)));
  return std::asin(s) * kDeg;
}

double scaled_jacobian(const Point2& a, const Point2& b, const Point2& c, const Point2& d) {
  const Point2* p[4] = {&a, &b, &c, &d};
  double sj = 1;
  for (int i = 0; i < 4; ++i) {
    const Point2& o = *p[i];
    const Point2& n = *p[(i + 1) % 4];
    const Point2& r = *p[(i + 3) % 4];
    const double ux = n[0] - o[0], uy = n[1] - o[1];
    const double vx = r[0] - o[0], vy = r[1] - o[1];
    const double len = std::sqrt((ux * ux + uy * uy) * (vx * vx + vy * vy));
    const double j = len > 0 ? (ux * vy - uy * vx) / len : 0;  // degenerate corner: 0
    sj = std::min(sj, j);
  }
  return sj;
}

std::array<double, 4> quad_angles(const Point2& a, const Point2& b, const Point2& c, const Point2& d) {
  const Point2* p[4] = {&a, &b, &c, &d};
  std::array<double, 4> out{};
  for (int i = 0; i < 4; ++i) out[i] = corner_angle(*p[i], *p[(i + 1) % 4], *p[(i + 3) % 4]);
  return out;
}

double quad_area(const Point2& a, const Point2& b, const Point2& c, const Point2& d) {
  // Diagonal cross product: exact same value as the shoelace formula, fewer terms.
  return 0.5 * ((c[0] - a[0]) * (d[1] - b[1]) - (c[1] - a[1]) * (d[0] - b[0]));
}

int mu_bin(double mu) {
  for (int i = 1; i < kMuBins; ++i)
    if (mu < kMuBinEdges[i]) return i - 1;
  return kMuBins - 1;
}

Json QualityReport::to_json() const {
  Json j = Json::object();
  j["quads"] = quads;
  j["non_convex"] = non_convex;
  Json bins = Json::array();
  for (int i = 0; i < kMuBins; ++i) {
    Json b = Json::object();
    b["from"] = kMuBinEdges[i];
    b["to"] = kMuBinEdges[i + 1];
    b["count"] = mu_histogram[i];
    bins.push_back(b);
  }
  j["mu_histogram"] = bins;
  j["min_mu"] = min_mu;
  j["median_mu"] = median_mu;
  j["mean_mu"] = mean_mu;
  j["min_scaled_jacobian"] = min_scaled_jacobian;
  j["mean_scaled_jacobian"] = mean_scaled_jacobian;
  j["angles_45_135"] = angles_45_135;
  j["min_angle"] = min_angle;
  j["max_angle"] = max_angle;
  j["mean_area"] = mean_area;
  j["area_stddev"] = area_stddev;
  return j;
}

QualityReport quality_report(const std::vector<Point2>& pts,
                             const std::vector<std::array<int, 4>>& quads) {
  QualityReport r;
  r.quads = quads.size();
  if (quads.empty()) return r;
  std::vector<double> mus;
  mus.reserve(quads.size());
  double sum_mu = 0, sum_sj = 0, sum_area = 0, sum_area2 = 0;
  std::size_t good_angles = 0;
  r.min_scaled_jacobian = 1;
  double min_pa = 5, max_pa = -1;
  std::array<const Point2*, 3> min_corner{}, max_corner{};  // corner, next, previous
  for (const auto& q : quads) {
    const Point2 &a = pts[q[0]], &b = pts[q[1]], &c = pts[q[2]], &d = pts[q[3]];
    if (!is_strictly_convex(a, b, c, d)) ++r.non_convex;
    const double mu = joe_mu(a, b, c, d);
    mus.push_back(mu);
    sum_mu += mu;
    ++r.mu_histogram[mu_bin(mu)];
    const double sj = scaled_jacobian(a, b, c, d);
    sum_sj += sj;
    r.min_scaled_jacobian = std::min(r.min_scaled_jacobian, sj);
    // Corner angles without trigonometry: in [45, 135] iff the turn is left
    // and |dot| <= cross; the extremes are tracked by pseudo-angle and
    // measured once at the end.
    const Point2* p[4] = {&a, &b, &c, &d};
    bool ok = true;
    for (int i = 0; i < 4; ++i) {
      const Point2 &o = *p[i], &n = *p[(i + 1) % 4], &w = *p[(i + 3) % 4];
      const double ux = n[0] - o[0], uy = n[1] - o[1], vx = w[0] - o[0], vy = w[1] - o[1];
      const double cr = ux * vy - uy * vx, dt = ux * vx + uy * vy;
      ok = ok && cr > 0 && std::fabs(dt) <= cr;
      const double pa = pseudo_angle(cr, dt);
      if (pa < min_pa) { min_pa = pa; min_corner = {&o, &n, &w}; }
      if (pa > max_pa) { max_pa = pa; max_corner = {&o, &n, &w}; }
    }
    good_angles += ok;
    const double area = quad_area(a, b, c, d);
    sum_area += area;
    sum_area2 += area * area;
  }
  r.min_angle = corner_angle(*min_corner[0], *min_corner[1], *min_corner[2]);
  r.max_angle = corner_angle(*max_corner[0], *max_corner[1], *max_corner[2]);
  const double n = double(quads.size());
  r.min_mu = *std::min_element(mus.begin(), mus.end());
  const std::size_t mid = mus.size() / 2;
  std::nth_element(mus.begin(), mus.begin() + mid, mus.end());
  r.median_mu = mus[mid];
  if (mus.size() % 2 == 0) {
    const double lower = *std::max_element(mus.begin(), mus.begin() + mid);
    r.median_mu = 0.5 * (r.median_mu + lower);
  }
  r.mean_mu = sum_mu / n;
  r.mean_scaled_jacobian = sum_sj / n;
  r.angles_45_135 = double(good_angles) / n;
  r.mean_area = sum_area / n;
  r.area_stddev = std::sqrt(std::max(0.0, sum_area2 / n - r.mean_area * r.mean_area));
  return r;
}

QualityReport quality_report(const PlanarMesh& m) {
  std::vector<std::array<int, 4>> quads;
  for (const auto& e : m.elements)
    if (e.size() == 4) quads.push_back({e[0], e[1], e[2], e[3]});
  return quality_report(m.points, quads);
}

} // namespace imgmesh
