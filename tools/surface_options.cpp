#include "surface_options.hpp"

#include "util/error.hpp"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdlib>

namespace imgmesh {

double parse_angle(std::string s) {
  s.erase(std::remove_if(s.begin(), s.end(), [](unsigned char c) { return std::isspace(c); }), s.end());
  const auto number = [](const std::string& t, double empty) {
    if (t.empty()) return empty;
    char* end = nullptr;
    const double v = std::strtod(t.c_str(), &end);
    return end == t.c_str() + t.size() && std::isfinite(v) ? v : NAN;
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

SurfaceOptions::SurfaceOptions(cli::Tool& tool, RestrictedDelaunayOptions& opt, const std::string& what) : opt_(opt) {
  opt_.ratio = 1.2;
  tool.app.add_option("--ratio", opt_.ratio,
                      "Radius-edge ratio bound rho_0 of every " + what +
                          " (>= (1+k)^2 = 1.1236); 1.2 gives a smallest angle of 24.6 degrees, 2 (the thesis's) 14.5")
      ->type_name("R")
      ->capture_default_str();
  tool.app.add_option("--roughness", roughness_,
                      "Roughness bound g in degrees (radians as pi/3 or 1.05rad): largest angle between the normals "
                      "of two " + what + "s sharing an edge (>= 14.8 degrees); 120 and 90 leave one-voxel features of "
                      "noisy labels unresolved, 60 (the thesis's) resolves each")
      ->type_name("G")
      ->capture_default_str();
  tool.app.add_option("--max-distance", max_distance_,
                      "Refine while a " + what + "'s surface Delaunay ball centre (a point of the surface) is farther "
                      "than E (world units) from the " + what + "'s plane, or |f| at its centroid is more than 2E; 0: off")
      ->type_name("E")
      ->capture_default_str();
  tool.app.add_option("--fallback-rounds", opt_.fallback_rounds,
                      "Where the final certificate finds a component with the wrong topology (TOPOLOGY should "
                      "leave none), at most this many rounds of HandleDetection and then denser sampling there; "
                      "if it still differs, the mesh is written and the exit status is 3, naming the component")
      ->type_name("N")
      ->check(CLI::NonNegativeNumber.description(""))
      ->capture_default_str();
  tool.app.add_option("--max-points", opt_.max_points,
                      "Safety bound on the number of sample points; when hit, the mesh is written and the exit "
                      "status is 3")
      ->type_name("N")
      ->capture_default_str();
}

void SurfaceOptions::check() const {
  if (!(opt_.ratio >= min_ratio_bound()))
    throw UsageError("--ratio " + std::to_string(opt_.ratio) + " is below the termination limit (1+k)^2 = 1.1236");
  const double g = parse_angle(roughness_);
  if (std::isnan(g))
    throw UsageError("--roughness " + roughness_ + ": not an angle (degrees, or radians as pi/3 or 1.05rad)");
  if (!(g >= min_roughness_bound()))
    throw UsageError("--roughness " + roughness_ +
                     " is below the termination limit 2(arcsin k + arcsin(2k/sqrt 3)) = 14.8 degrees (0.2587 rad; "
                     "a number without unit is in degrees)");
  if (max_distance_ != "0.3 voxel") {
    char* end = nullptr;
    const double e = std::strtod(max_distance_.c_str(), &end);
    if (max_distance_.empty() || end != max_distance_.c_str() + max_distance_.size() || !(e >= 0) ||
        !std::isfinite(e))
      throw UsageError("--max-distance must be a finite number >= 0");
  }
  if (opt_.max_points < 4) throw UsageError("--max-points must be at least 4");
}

void SurfaceOptions::resolve(double smallest_spacing) {
  check();
  opt_.roughness = parse_angle(roughness_);
  opt_.max_distance = max_distance_ == "0.3 voxel" ? 0.3 * smallest_spacing : std::strtod(max_distance_.c_str(), nullptr);
}

} // namespace imgmesh
