// The coordinates the tools take (their man pages say it too): finite
// numbers of magnitude at most 1e30, spanning (largest minus smallest, on
// some axis) 0 or at least 1e-30. Then what the tools compute from them
// stays a normal double: differences of at most 2e30, so the products of
// differences that lengths, areas, circumcentres and quality measures form
// (up to the 4th power) cannot overflow, and a mesh at least 1e-30 across,
// whose own sizes cannot underflow. A value as small as you like (a
// denormal, 1e-300 next to 1) is fine; what is below double precision next
// to the size of its coordinates (1e-15 next to 1e15) is a matter for the
// tools' own checks. The bound holds in 32-bit floats too (OBJ, STL and PLY
// are read as those). A real mesh is nowhere near either end: a value past
// them is a corrupt or hostile file, refused by every reader.
#pragma once
#include "util/error.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <string>
#include <string_view>
#include <vector>

namespace imgmesh {

constexpr double kMaxCoordinate = 1e30, kMinExtent = 1e-30;

// Finite and at most kMaxCoordinate in magnitude.
inline bool valid_coordinate(double v) { return std::fabs(v) <= kMaxCoordinate; }
// The same for a value a file holds as a 32-bit float (binary STL, PLY):
// the float nearest 1e30 is the end.
inline bool valid_coordinate(float v) { return std::fabs(v) <= float(kMaxCoordinate); }

// All of s as a coordinate: a number (as strtod reads it) within the range.
bool parse_coordinate(std::string_view s, double& v);

// What a reader says of text parse_coordinate refuses: "'x' is not a
// number", or "coordinate '1e300' is out of range (finite, at most 1e30 in
// magnitude)".
std::string coordinate_error(std::string_view text);
// The same for a value with no text (binary files), shown as %.17g.
std::string coordinate_error(double v);

// The largest extent along an axis (largest minus smallest coordinate) of
// what was added, one coordinate at a time (0 for nothing or one point).
class Extent {
public:
  void add(std::size_t axis, double v) {
    lo_[axis] = std::min(lo_[axis], v);
    hi_[axis] = std::max(hi_[axis], v);
  }
  double value() const {
    double e = 0;
    for (std::size_t k = 0; k < 3; ++k)
      if (lo_[k] <= hi_[k]) e = std::max(e, hi_[k] - lo_[k]);
    return e;
  }

private:
  std::array<double, 3> lo_{HUGE_VAL, HUGE_VAL, HUGE_VAL}, hi_{-HUGE_VAL, -HUGE_VAL, -HUGE_VAL};
};
template <std::size_t D> double extent(const std::vector<std::array<double, D>>& points) {
  static_assert(D <= 3);
  Extent e;
  for (const auto& p : points)
    for (std::size_t k = 0; k < D; ++k) e.add(k, p[k]);
  return e.value();
}
// Throws Error naming `path` when the points span more than 0 and less than
// kMinExtent (all points equal is the tools' to judge: a degenerate mesh).
void check_extent(double extent, const std::string& path);
template <std::size_t D> void check_extent(const std::vector<std::array<double, D>>& points, const std::string& path) {
  check_extent(extent(points), path);
}

} // namespace imgmesh
