#include "util/coordinates.hpp"

#include "util/parse.hpp"

#include <cstdio>

namespace imgmesh {

namespace {
// Whether number text that parsed to 0 is a zero: no nonzero digit before
// its exponent ("0", "-0.000", "0e99", "0x0p3"; not "1e-400", "0x1p-1100").
bool zero_text(std::string_view s) {
  const bool hex = s.find_first_of("xX") != std::string_view::npos;
  for (char c : s) {
    if (c == 'p' || c == 'P' || (!hex && (c == 'e' || c == 'E'))) break;
    const bool hex_letter = (c >= 'a' && c <= 'f') || (c >= 'A' && c <= 'F');
    if ((c >= '1' && c <= '9') || (hex && hex_letter)) return false;
  }
  return true;
}
} // namespace

bool parse_coordinate(std::string_view s, double& v) {
  return parse_real(s, v) && valid_coordinate(v) && (v != 0 || zero_text(s));
}

std::string coordinate_error(std::string_view text) {
  // A hostile file's field may be long: the message stays one short line.
  const std::string shown = text.size() > 40 ? std::string(text.substr(0, 40)) + "..." : std::string(text);
  return "coordinate '" + shown + "' is not a number in the tools' range (0, or 1e-30 to 1e30 in magnitude)";
}

std::string coordinate_error(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.17g", v);
  return coordinate_error(std::string_view(buf));
}

} // namespace imgmesh
