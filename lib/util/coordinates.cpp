#include "util/coordinates.hpp"

#include "util/parse.hpp"

#include <cstdio>

namespace imgmesh {

bool parse_coordinate(std::string_view s, double& v) { return parse_real(s, v) && valid_coordinate(v); }

std::string coordinate_error(std::string_view text) {
  // A hostile file's field may be long: the message stays one short line.
  const std::string shown = text.size() > 40 ? std::string(text.substr(0, 40)) + "..." : std::string(text);
  double v;
  if (!parse_real(text, v)) return "'" + shown + "' is not a number";
  return "coordinate '" + shown + "' is out of range (finite, at most 1e30 in magnitude)";
}

std::string coordinate_error(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.17g", v);
  return coordinate_error(std::string_view(buf));
}

void check_extent(double extent, const std::string& path) {
  if (extent > 0 && extent < kMinExtent) {
    char buf[160];
    std::snprintf(buf, sizeof buf,
                  "the coordinates span only %.3g: under 1e-30, too small for double arithmetic (scale the mesh)",
                  extent);
    throw Error(buf, path);
  }
}

} // namespace imgmesh
