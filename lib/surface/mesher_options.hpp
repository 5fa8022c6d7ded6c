// The surface mesher's bounds in one place: as a command line gives them
// (MesherBounds: an angle with its unit, a distance that defaults to a
// fraction of the voxel size), their one check, and the finished
// RestrictedDelaunayOptions they resolve to. The defaults are the tools'
// (doc/benchmarks-log.md, issue 17): --ratio 1.2 (smallest angle about 24.6
// degrees), --roughness 120 degrees (one-voxel features of noisy labels left
// unresolved) and --max-distance 0.4 of the smallest voxel spacing with
// VoxelSides (0.3 without it, and for the conforming mesher; issue 38);
// RestrictedDelaunayOptions keep the thesis's values.
#pragma once
#include "image/grid.hpp"
#include "surface/restricted_delaunay.hpp"

#include <cstddef>
#include <string>

namespace imgmesh {

struct MesherBounds {
  // The default max_distance, a fraction of the smallest voxel spacing:
  // 0.4 where VoxelSides runs, which keeps every voxel centre next to S on
  // its side and so bounds the error where the staircase's corners are
  // (doc/implicit2mesh.md 4.9: about the triangles of 0.3 without it, and
  // less sampled |f| on the triangles); 0.3 without it, and for the
  // conforming mesher (its own bounds, measured at 0.3).
  static constexpr const char* kVoxelDistance = "0.4 voxel";
  static constexpr double kVoxelSidesFraction = 0.4, kPlainFraction = 0.3;
  enum class Mesher { kDelaunay, kConforming };

  double ratio = 1.2;                         // rho_0
  std::string roughness = "120";              // g, an angle as parse_angle reads it
  std::string max_distance = kVoxelDistance;  // E in world units, or kVoxelDistance
  int fallback_rounds = RestrictedDelaunayOptions().fallback_rounds;
  std::size_t max_points = RestrictedDelaunayOptions().max_points;
  bool voxel_sides = RestrictedDelaunayOptions().voxel_sides;

  // The bounds checked (UsageError naming the option, as check_options, and
  // quoting g as given) with their units resolved: g in radians, E from
  // `spacing` (a voxel's) when it is kVoxelDistance (its fraction as
  // above, for `mesher`). The other fields are RestrictedDelaunayOptions'
  // defaults.
  RestrictedDelaunayOptions resolve(const Vec3& spacing, Mesher mesher = Mesher::kDelaunay) const;
  // The checks of resolve(), before the grid is known.
  void check() const;
};

// An angle of the command line in degrees ("90", "90deg"), or in radians
// with a suffix "rad" ("1.5708rad") or as a multiple of pi ("pi/2",
// "2pi/3", "0.5pi"), in radians. NaN when it is none of these.
double parse_angle(std::string text);

// UsageError naming the option when a bound is outside what the proofs (and
// termination) allow; restricted_delaunay_mesh and tetrahedral_mesh check
// their options first.
void check_options(const RestrictedDelaunayOptions& options);

} // namespace imgmesh
