// Internal: topology-keeping simplification of pixel-boundary curves with
// CGAL's Polyline_simplification_2 (the one file of img2poly with CGAL).
#pragma once
#include "planar/triangle_io.hpp"

#include <vector>

namespace imgmesh {

struct PolylineSet {
  std::vector<std::vector<Point2>> lines;  // endpoints of open lines are kept
  std::vector<char> closed;                // closed: last point joins the first (not repeated)
};

struct SimplifyReport {
  double hausdorff = 0;  // max distance of an original point to its simplified segment
  std::size_t removed = 0;
};

// Simplifies every polyline so that each stays within `tolerance` of its
// original (Hausdorff) and no removal sweeps over another polyline or any of
// the `obstacles` points: the curves stay simple, disjoint, and separate the
// obstacles as before. Lines may share endpoints (junctions), never cross.
// A removal that would make an angle below `min_angle` degrees between two
// segments at a vertex is not made (checked when it is considered).
SimplifyReport simplify_polylines(PolylineSet& set, const std::vector<Point2>& obstacles, double tolerance,
                                  double min_angle = 0);

} // namespace imgmesh
