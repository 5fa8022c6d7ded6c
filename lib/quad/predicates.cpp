#include "quad/predicates.hpp"

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>

namespace imgmesh {

int orientation_exact(const Point2& a, const Point2& b, const Point2& c) {
  using K = CGAL::Exact_predicates_inexact_constructions_kernel;
  const auto o = CGAL::orientation(K::Point_2(a[0], a[1]), K::Point_2(b[0], b[1]),
                                   K::Point_2(c[0], c[1]));
  return o == CGAL::LEFT_TURN ? 1 : (o == CGAL::RIGHT_TURN ? -1 : 0);
}

} // namespace imgmesh
