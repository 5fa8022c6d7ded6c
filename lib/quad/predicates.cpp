#include "quad/predicates.hpp"

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>

#include <algorithm>
#include <cmath>

namespace imgmesh {

namespace {
double cross(const Point2& o, const Point2& a, const Point2& b) {
  return (a[0] - o[0]) * (b[1] - o[1]) - (a[1] - o[1]) * (b[0] - o[0]);
}

// Margin relative to the element size: the independent checker accepts a
// turn only above 1e-12 * diag^2; we ask for 1e-10 so both agree.
constexpr double kMargin = 1e-10;

bool margin_ok(const Point2* q, int n) {
  double x0 = q[0][0], x1 = x0, y0 = q[0][1], y1 = y0;
  for (int i = 1; i < n; ++i) {
    x0 = std::min(x0, q[i][0]); x1 = std::max(x1, q[i][0]);
    y0 = std::min(y0, q[i][1]); y1 = std::max(y1, q[i][1]);
  }
  const double d2 = (x1 - x0) * (x1 - x0) + (y1 - y0) * (y1 - y0);
  if (!(d2 > 0) || !std::isfinite(d2)) return false;
  for (int i = 0; i < n; ++i)
    if (!(cross(q[i], q[(i + 1) % n], q[(i + 2) % n]) > kMargin * d2)) return false;
  return true;
}
} // namespace

int orientation_exact(const Point2& a, const Point2& b, const Point2& c) {
  using K = CGAL::Exact_predicates_inexact_constructions_kernel;
  const auto o = CGAL::orientation(K::Point_2(a[0], a[1]), K::Point_2(b[0], b[1]),
                                   K::Point_2(c[0], c[1]));
  return o == CGAL::LEFT_TURN ? 1 : (o == CGAL::RIGHT_TURN ? -1 : 0);
}

bool good_quad(const Point2& a, const Point2& b, const Point2& c, const Point2& d) {
  const Point2 q[4] = {a, b, c, d};
  return margin_ok(q, 4) && is_strictly_convex(a, b, c, d);
}

bool good_triangle(const Point2& a, const Point2& b, const Point2& c) {
  const Point2 q[3] = {a, b, c};
  return margin_ok(q, 3) && orientation(a, b, c) > 0;
}

bool simple_ccw(const std::vector<Point2>& v) {
  const std::size_t n = v.size();
  double area = 0;
  for (std::size_t i = 0; i < n; ++i) area += cross({0, 0}, v[i], v[(i + 1) % n]);
  if (!(area > 0)) return false;
  for (std::size_t i = 0; i < n; ++i)
    for (std::size_t j = i + 1; j < n; ++j) {
      const Point2 &a = v[i], &b = v[(i + 1) % n], &c = v[j], &d = v[(j + 1) % n];
      if (j == i + 1 || (i == 0 && j == n - 1)) {
        // Neighbouring edges meet only at their shared vertex: no fold-back.
        const Point2& s = (j == i + 1) ? b : a;
        const Point2& x = (j == i + 1) ? a : b;
        const Point2& y = (j == i + 1) ? d : c;
        if (orientation(x, s, y) == 0 &&
            ((x[0] - s[0]) * (y[0] - s[0]) + (x[1] - s[1]) * (y[1] - s[1])) > 0)
          return false;
        continue;
      }
      const int o1 = orientation(a, b, c), o2 = orientation(a, b, d), o3 = orientation(c, d, a), o4 = orientation(c, d, b);
      if (o1 * o2 <= 0 && o3 * o4 <= 0) {
        if (o1 == 0 && o2 == 0) {  // collinear: overlap test on the bounding boxes
          if (std::max(std::min(a[0], b[0]), std::min(c[0], d[0])) <=
                  std::min(std::max(a[0], b[0]), std::max(c[0], d[0])) &&
              std::max(std::min(a[1], b[1]), std::min(c[1], d[1])) <=
                  std::min(std::max(a[1], b[1]), std::max(c[1], d[1])))
            return false;
          continue;
        }
        return false;
      }
    }
  return true;
}

} // namespace imgmesh
