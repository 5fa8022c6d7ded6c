// The surface mesher's options, declared once for every tool that meshes a
// surface (implicit2mesh, implicit2tet, seg2mesh): the same names, units,
// defaults and help. Their defaults, checks and units are the library's
// (surface/mesher_options.hpp); SurfaceOptions hands back the finished
// RestrictedDelaunayOptions.
#pragma once
#include "cli/cli.hpp"
#include "surface/mesher_options.hpp"

#include <string>

namespace imgmesh {

class SurfaceOptions {
public:
  // Adds --ratio, --roughness, --max-distance, --fallback-rounds,
  // --voxel-sides / --no-voxel-sides and --max-points, described for
  // `what`, e.g. "triangle" or "boundary triangle". The options hold on to
  // this object: it must not move.
  // roughness_and_fallbacks false: --roughness and --fallback-rounds left
  // out (the label partition's mesher, seg2tet, runs neither).
  explicit SurfaceOptions(cli::Tool& tool, const std::string& what = "triangle", bool roughness_and_fallbacks = true);
  SurfaceOptions(const SurfaceOptions&) = delete;
  SurfaceOptions& operator=(const SurfaceOptions&) = delete;

  // After parsing, before the grid is known: UsageError naming a bad option.
  void check() const { bounds_.check(); }
  // After parsing: the options, checked, with their units resolved and the
  // distance's default from the grid's voxel spacing (and the mesher).
  RestrictedDelaunayOptions resolve(const Vec3& spacing,
                                    MesherBounds::Mesher mesher = MesherBounds::Mesher::kDelaunay) const {
    return bounds_.resolve(spacing, mesher);
  }

private:
  MesherBounds bounds_;
};

// --normals: per-vertex normals from grad f.
void add_normals_option(cli::Tool& tool, bool& normals);
// After parsing: a warning when --normals was given for an OUT that holds
// none, `advice` appended.
void warn_normals_ignored(const cli::Tool& tool, bool normals, const std::string& out, const std::string& advice = "");
// How the warnings name OUT's format: its extension, "OFF" for "-".
std::string surface_format_name(const std::string& out);

} // namespace imgmesh
