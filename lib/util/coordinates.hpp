// The coordinates the tools take (doc/design.md "Data contracts"): finite,
// and 0 or between 1e-30 and 1e30 in magnitude. Within it what the tools
// compute from coordinates stays a normal double: two different coordinates
// differ by at least 1e-46 and at most 2e30, so the products of differences
// that lengths, areas, circumcentres and quality measures form (up to the
// 4th power, and beyond) neither overflow nor underflow. A real mesh is
// nowhere near either end, and the range holds in 32-bit floats too (OBJ and
// STL are read as those); a value past it is a corrupt or hostile file,
// refused by every reader with its line and text.
#pragma once
#include <cmath>
#include <string>
#include <string_view>

namespace imgmesh {

constexpr double kMinCoordinate = 1e-30, kMaxCoordinate = 1e30;

// Within the range; false for NaN and infinities.
inline bool valid_coordinate(double v) {
  const double a = std::fabs(v);
  return a == 0 || (a >= kMinCoordinate && a <= kMaxCoordinate);
}

// The same for a value a file holds as a 32-bit float (binary STL and PLY),
// whose nearest floats to 1e-30 and 1e30 are the ends.
inline bool valid_coordinate(float v) {
  const float a = std::fabs(v);
  return a == 0 || (a >= float(kMinCoordinate) && a <= float(kMaxCoordinate));
}

// All of s as a coordinate: a number (as strtod reads it) within the range.
// Text of a nonzero number that underflows ("1e-400") is out of it too,
// though it would read as 0.
bool parse_coordinate(std::string_view s, double& v);

// "coordinate 'TEXT' is not a number in the tools' range (0, or 1e-30 to
// 1e30 in magnitude)": what a reader says of text parse_coordinate refuses.
std::string coordinate_error(std::string_view text);
// The same for a value with no text (binary files): shown as %.17g.
std::string coordinate_error(double v);

} // namespace imgmesh
