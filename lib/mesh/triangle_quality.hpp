// Element quality of triangles in 3D: angles, radius-edge ratio R / l_min
// (the mesher's QUALITY bound, thesis 8.4) and areas. meshinfo reports it;
// the mesher checks its ratio bound on it.
#pragma once
#include "mesh/surface_io.hpp"
#include "util/json.hpp"

#include <array>
#include <cstddef>
#include <vector>

namespace imgmesh {

// Figures over the non-degenerate triangles (zero when there is none);
// angles in degrees.
struct TriangleQualityReport {
  std::size_t triangles = 0;   // non-degenerate ones
  std::size_t degenerate = 0;  // zero area: no angles, ratio infinite
  double min_angle = 0, max_angle = 0, mean_min_angle = 0;
  double max_radius_edge_ratio = 0, mean_radius_edge_ratio = 0;
  double min_area = 0, max_area = 0, total_area = 0;
  std::array<std::size_t, 6> min_angle_histogram{};  // smallest angles, 10-degree bins up to 60
  // Over every triangle, a degenerate one counting as angle 0 and ratio
  // infinity: what a bound is checked against.
  double smallest_angle() const;
  double largest_radius_edge_ratio() const;
  Json to_json() const;  // "triangles", "degenerate", then the figures when triangles > 0
};

// Faces that are not triangles are skipped.
TriangleQualityReport triangle_quality_report(const std::vector<std::array<double, 3>>& points,
                                              const std::vector<std::vector<int>>& faces);
TriangleQualityReport triangle_quality_report(const SurfaceMesh& mesh);

} // namespace imgmesh
