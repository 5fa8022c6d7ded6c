// The region of the placement rule (doc/tri2quad.md section 1): a polygon
// clipped by half-planes (Sutherland-Hodgman), and its area centroid.
#include "quad/half_plane_clip.hpp"

#include <cmath>

namespace imgmesh {

namespace {
double cross(const Point2& o, const Point2& a, const Point2& b) {
  return (a[0] - o[0]) * (b[1] - o[1]) - (a[1] - o[1]) * (b[0] - o[0]);
}
double cross2(double ux, double uy, double vx, double vy) { return ux * vy - uy * vx; }
Point2 lerp(const Point2& a, const Point2& b, double t) { return {a[0] + t * (b[0] - a[0]), a[1] + t * (b[1] - a[1])}; }
} // namespace

std::vector<Point2> clip(const std::vector<Point2>& poly, const std::vector<HalfPlane>& hps) {
  std::vector<Point2> cur = poly, next;
  for (const auto& h : hps) {
    next.clear();
    const std::size_t n = cur.size();
    for (std::size_t i = 0; i < n; ++i) {
      const Point2& s = cur[i];
      const Point2& e = cur[(i + 1) % n];
      const double ds = cross(h.a, h.b, s), de = cross(h.a, h.b, e);
      // Closed half-planes (points on a line kept), so regions touching a
      // clip line survive; the candidates are interior points anyway.
      if (ds >= 0) next.push_back(s);
      if ((ds > 0 && de < 0) || (ds < 0 && de > 0)) next.push_back(lerp(s, e, ds / (ds - de)));
    }
    cur.swap(next);
    if (cur.size() < 3) return {};
  }
  return cur;
}

Point2 centroid(const std::vector<Point2>& v) {
  double a = 0, cx = 0, cy = 0;
  const std::size_t n = v.size();
  for (std::size_t i = 0; i < n; ++i) {
    const double w = cross2(v[i][0] - v[0][0], v[i][1] - v[0][1], v[(i + 1) % n][0] - v[0][0],
                            v[(i + 1) % n][1] - v[0][1]);
    a += w;
    cx += w * (v[i][0] + v[(i + 1) % n][0] - 2 * v[0][0]);
    cy += w * (v[i][1] + v[(i + 1) % n][1] - 2 * v[0][1]);
  }
  if (!(std::fabs(a) > 0)) {
    double sx = 0, sy = 0;
    for (const Point2& p : v) { sx += p[0]; sy += p[1]; }
    return {sx / double(n), sy / double(n)};
  }
  return {v[0][0] + cx / (3 * a), v[0][1] + cy / (3 * a)};
}

} // namespace imgmesh
