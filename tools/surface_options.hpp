// The surface mesher's options, one definition for every tool that meshes a
// surface (implicit2mesh, implicit2tet, seg2mesh): the same names, units,
// defaults and checks. The defaults are the tools' (doc/benchmarks.md,
// issue 17): --ratio 1.2 (smallest angle about 24.6 degrees), --roughness
// 120 degrees (one-voxel features of noisy labels left unresolved), and
// --max-distance 0.3 of the smallest voxel spacing; the library's
// RestrictedDelaunayOptions keep the thesis's values.
#pragma once
#include "cli/cli.hpp"
#include "surface/restricted_delaunay.hpp"

#include <string>

namespace imgmesh {

class SurfaceOptions {
public:
  // Adds --ratio, --roughness, --max-distance, --fallback-rounds and
  // --max-points (described
  // for `what`, e.g. "triangle" or "boundary triangle") and sets the tools'
  // defaults in opt, which must outlive this object.
  SurfaceOptions(cli::Tool& tool, RestrictedDelaunayOptions& opt, const std::string& what = "triangle");
  // After parsing: the angle and the distance read, every bound checked
  // (UsageError naming the option). smallest_spacing is the grid's smallest
  // voxel spacing, for the default distance bound.
  void resolve(double smallest_spacing);
  // Before the grid is known: the checks of resolve() that need no grid.
  void check() const;

private:
  RestrictedDelaunayOptions& opt_;
  std::string roughness_ = "120";
  std::string max_distance_ = "0.3 voxel";
};

// An angle of the command line in degrees ("90", "90deg"), or in radians
// with a suffix "rad" ("1.5708rad") or as a multiple of pi ("pi/2",
// "2pi/3", "0.5pi"), in radians. NaN when it is none of these.
double parse_angle(std::string text);

} // namespace imgmesh
