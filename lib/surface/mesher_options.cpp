#include "surface/mesher_options.hpp"

#include "util/error.hpp"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdlib>

namespace imgmesh {

namespace surface_detail {

// The one check of the bounds, in the order of the options; `roughness` is
// g as it was written (the messages quote it).
void check_bounds(const RestrictedDelaunayOptions& o, const std::string& roughness) {
  if (!(o.ratio >= min_ratio_bound()))
    throw UsageError("--ratio " + std::to_string(o.ratio) + " is below the termination limit (1+k)^2 = 1.1236");
  if (std::isnan(o.roughness))
    throw UsageError("--roughness " + roughness + ": not an angle (degrees, or radians as pi/3 or 1.05rad)");
  if (!(o.roughness >= min_roughness_bound()))
    throw UsageError("--roughness " + roughness +
                     " is below the termination limit 2(arcsin k + arcsin(2k/sqrt 3)) = 14.8 degrees (0.2587 rad; "
                     "a number without unit is in degrees)");
  if (!(o.max_distance >= 0) || !std::isfinite(o.max_distance))
    throw UsageError("--max-distance must be a finite number >= 0");
  if (o.max_points < 4) throw UsageError("--max-points must be at least 4");
}

// The whole of `text` as a number; NaN when it is not one.
double parse_number(const std::string& text) {
  char* end = nullptr;
  const double v = std::strtod(text.c_str(), &end);
  return text.empty() || end != text.c_str() + text.size() ? NAN : v;
}

} // namespace surface_detail

double parse_angle(std::string s) {
  s.erase(std::remove_if(s.begin(), s.end(), [](unsigned char c) { return std::isspace(c); }), s.end());
  const auto number = [](const std::string& t, double empty) {
    if (t.empty()) return empty;
    const double v = surface_detail::parse_number(t);
    return std::isfinite(v) ? v : NAN;
  };
  const auto suffix = [&s](const std::string& x) {
    if (s.size() <= x.size() || s.compare(s.size() - x.size(), x.size(), x) != 0) return false;
    s.resize(s.size() - x.size());
    return true;
  };
  const std::size_t pi = s.find("pi");
  if (pi != std::string::npos) {  // [a][*]pi[/b]
    std::string a = s.substr(0, pi), b = s.substr(pi + 2);
    if (!a.empty() && a.back() == '*') a.pop_back();
    if (!b.empty() && b[0] != '/') return NAN;
    const double den = b.empty() ? 1.0 : number(b.substr(1), NAN);
    return number(a, 1.0) * M_PI / den;
  }
  if (suffix("rad")) return number(s, NAN);
  suffix("deg");
  return number(s, NAN) * M_PI / 180;
}

RestrictedDelaunayOptions MesherBounds::resolve(const Vec3& spacing, Mesher mesher) const {
  RestrictedDelaunayOptions o;
  o.ratio = ratio;
  o.roughness = parse_angle(roughness);
  const double fraction = voxel_sides && mesher == Mesher::kDelaunay ? kVoxelSidesFraction : kPlainFraction;
  o.max_distance = max_distance == kVoxelDistance ? fraction * std::min({spacing[0], spacing[1], spacing[2]})
                                                  : surface_detail::parse_number(max_distance);
  o.fallback_rounds = fallback_rounds;
  o.max_points = max_points;
  o.voxel_sides = voxel_sides;
  surface_detail::check_bounds(o, roughness);
  return o;
}

void MesherBounds::check() const { resolve({1, 1, 1}); }

void check_options(const RestrictedDelaunayOptions& options) {
  surface_detail::check_bounds(options, std::to_string(options.roughness) + "rad");
}

} // namespace imgmesh
