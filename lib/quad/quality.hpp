// Shape quality of planar quadrilaterals (thesis 3.2.3, Tables 3.2 and 3.3).
// Quads are given by their corners a, b, c, d in counter-clockwise order.
// Angles are in degrees. CGAL stays inside quality.cpp.
#pragma once
#include "planar/triangle_io.hpp"
#include "quad/predicates.hpp"
#include "util/json.hpp"

#include <array>
#include <cmath>
#include <cstddef>
#include <vector>

namespace imgmesh {

// Joe's mu: the smallest angle of the four triangles [a,b,d], [c,d,b],
// [a,b,c], [d,a,c] obtained from either diagonal. 45 for a square, the
// maximum; tends to 0 for distorted quads. Meaningful for strictly convex
// quads; returns 0 for degenerate ones.
double joe_mu(const Point2& a, const Point2& b, const Point2& c, const Point2& d);

// Scaled Jacobian (Verdict): the minimum over the corners of
// cross(e_next, e_prev) / (|e_next| |e_prev|), in [-1, 1]; 1 for rectangles,
// <= 0 for non-convex or clockwise quads.
double scaled_jacobian(const Point2& a, const Point2& b, const Point2& c, const Point2& d);

// Interior angles at a, b, c, d (degrees; they add up to 360 for convex quads).
std::array<double, 4> quad_angles(const Point2& a, const Point2& b, const Point2& c, const Point2& d);

// Signed area (shoelace), positive when counter-clockwise.
double quad_area(const Point2& a, const Point2& b, const Point2& c, const Point2& d);

// Smallest angle of the triangle (a, b, c), degrees (0 when degenerate).
double min_triangle_angle(const Point2& a, const Point2& b, const Point2& c);

// The mu bins of Table 3.2: [0,5), [5,10), [10,25), [25,35), [35,45].
constexpr int kMuBins = 5;
constexpr std::array<double, kMuBins + 1> kMuBinEdges = {0, 5, 10, 25, 35, 45};
int mu_bin(double mu);  // index into the bins above
using MuHistogram = std::array<std::size_t, kMuBins>;

// Whole-mesh figures (Tables 3.2 and 3.3 and the usual FE bars).
struct QualityReport {
  std::size_t quads = 0;
  std::size_t non_convex = 0;     // quads that are not strictly convex
  MuHistogram mu_histogram{};     // Table 3.2 bins
  double min_mu = 0, median_mu = 0, mean_mu = 0;
  double min_scaled_jacobian = 0, mean_scaled_jacobian = 0;
  double angles_45_135 = 0;       // share (0..1) of quads with every angle in [45, 135]
  double min_angle = 0, max_angle = 0;
  double mean_area = 0, area_stddev = 0;  // Table 3.3
  Json to_json() const;
};

// Quality of the 4-node elements of m (3-node elements are ignored).
QualityReport quality_report(const PlanarMesh& m);
// Quality of quads given as corner index lists into points.
QualityReport quality_report(const std::vector<Point2>& points,
                             const std::vector<std::array<int, 4>>& quads);

} // namespace imgmesh
