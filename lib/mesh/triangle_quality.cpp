#include "mesh/triangle_quality.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace imgmesh {

namespace {

constexpr double kDeg = 180.0 / 3.14159265358979323846;

double tri_area3(const std::array<double, 3>& a, const std::array<double, 3>& b, const std::array<double, 3>& c) {
  const double ux = b[0] - a[0], uy = b[1] - a[1], uz = b[2] - a[2];
  const double vx = c[0] - a[0], vy = c[1] - a[1], vz = c[2] - a[2];
  const double x = uy * vz - uz * vy, y = uz * vx - ux * vz, z = ux * vy - uy * vx;
  return 0.5 * std::sqrt(x * x + y * y + z * z);
}

double dist(const std::array<double, 3>& a, const std::array<double, 3>& b) {
  return std::sqrt((a[0] - b[0]) * (a[0] - b[0]) + (a[1] - b[1]) * (a[1] - b[1]) + (a[2] - b[2]) * (a[2] - b[2]));
}

template <class Faces>
TriangleQualityReport report(const std::vector<std::array<double, 3>>& points, const Faces& faces) {
  TriangleQualityReport q;
  std::size_t n = 0;
  double min_ang = 180, max_ang = 0, sum_min = 0, max_re = 0, sum_re = 0;
  double amin = 0, amax = 0, asum = 0;
  for (const auto& f : faces) {
    if (f.size() != 3) continue;
    const auto &a = points[f[0]], &b = points[f[1]], &c = points[f[2]];
    const double la = dist(b, c), lb = dist(c, a), lc = dist(a, b);
    const double area = tri_area3(a, b, c);
    if (!(area > 0)) { ++q.degenerate; continue; }
    // Angles by the law of cosines, clamped.
    auto ang = [](double opp, double s1, double s2) {
      return std::acos(std::max(-1.0, std::min(1.0, (s1 * s1 + s2 * s2 - opp * opp) / (2 * s1 * s2)))) * kDeg;
    };
    const double A = ang(la, lb, lc), B = ang(lb, lc, la), C = 180 - A - B;
    const double mn = std::min({A, B, C}), mx = std::max({A, B, C});
    const double R = la * lb * lc / (4 * area);
    const double re = R / std::min({la, lb, lc});
    if (n == 0) amin = amax = area;
    ++n;
    min_ang = std::min(min_ang, mn);
    max_ang = std::max(max_ang, mx);
    sum_min += mn;
    max_re = std::max(max_re, re);
    sum_re += re;
    amin = std::min(amin, area);
    amax = std::max(amax, area);
    asum += area;
    ++q.min_angle_histogram[std::min<std::size_t>(5, std::size_t(mn / 10))];
  }
  q.triangles = n;
  if (n == 0) return q;
  q.min_angle = min_ang;
  q.max_angle = max_ang;
  q.mean_min_angle = sum_min / double(n);
  q.max_radius_edge_ratio = max_re;
  q.mean_radius_edge_ratio = sum_re / double(n);
  q.min_area = amin;
  q.max_area = amax;
  q.total_area = asum;
  return q;
}

} // namespace

double TriangleQualityReport::smallest_angle() const { return degenerate ? 0.0 : min_angle; }

double TriangleQualityReport::largest_radius_edge_ratio() const {
  return degenerate ? std::numeric_limits<double>::infinity() : max_radius_edge_ratio;
}

Json TriangleQualityReport::to_json() const {
  Json j = Json::object();
  j["triangles"] = triangles;
  j["degenerate"] = degenerate;
  if (triangles == 0) return j;
  j["min_angle"] = min_angle;
  j["max_angle"] = max_angle;
  j["mean_min_angle"] = mean_min_angle;
  j["max_radius_edge_ratio"] = max_radius_edge_ratio;
  j["mean_radius_edge_ratio"] = mean_radius_edge_ratio;
  j["min_area"] = min_area;
  j["max_area"] = max_area;
  j["total_area"] = total_area;
  Json h = Json::array();
  for (std::size_t c : min_angle_histogram) h.push_back(c);
  j["min_angle_histogram_10deg"] = h;
  return j;
}

TriangleQualityReport triangle_quality_report(const std::vector<std::array<double, 3>>& points,
                                              const std::vector<std::vector<int>>& faces) {
  return report(points, faces);
}

TriangleQualityReport triangle_quality_report(const SurfaceMesh& mesh) { return report(mesh.points, mesh.triangles); }

} // namespace imgmesh
