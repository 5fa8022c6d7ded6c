#include "surface_options.hpp"

#include "mesh/surface_io.hpp"
#include "util/path.hpp"

namespace imgmesh {

SurfaceOptions::SurfaceOptions(cli::Tool& tool, const std::string& what, bool roughness_and_fallbacks) {
  const std::string article = std::string("aeiou").find(what.front()) != std::string::npos ? "an " : "a ";
  tool.app.add_option("--ratio", bounds_.ratio,
                      "Radius-edge ratio bound rho_0 of every " + what +
                          " (>= (1+k)^2 = 1.1236); 1.2 gives a smallest angle of 24.6 degrees, 2 (the thesis's) 14.5")
      ->type_name("R")
      ->capture_default_str();
  if (roughness_and_fallbacks) {
    tool.app.add_option("--roughness", bounds_.roughness,
                        "Roughness bound g in degrees (radians as pi/3 or 1.05rad): largest angle between the normals "
                        "of two " + what + "s sharing an edge (>= 14.8 degrees); 120 and 90 leave one-voxel features "
                        "of noisy labels unresolved, 60 (the thesis's) resolves each")
        ->type_name("G")
        ->capture_default_str();
  }
  tool.app.add_option("--max-distance", bounds_.max_distance,
                      "Refine while " + article + what + "'s surface Delaunay ball centre (a point of the surface) is farther "
                      "than E (world units) from the " + what + "'s plane, or |f| at its centroid is more than 2E; 0: off. "
                      "The default is 0.4 voxel with --voxel-sides (which bounds the error at the voxel centres), "
                      "0.3 voxel with --no-voxel-sides and for the conforming mesher (seg2mesh --conforming, seg2tet)")
      ->type_name("E")
      ->capture_default_str();
  if (roughness_and_fallbacks) {
    tool.app.add_option("--fallback-rounds", bounds_.fallback_rounds,
                        "Where the final certificate finds a component with the wrong topology (TOPOLOGY should "
                        "leave none), at most this many rounds of HandleDetection and then denser sampling there; "
                        "if it still differs, the mesh is written and the exit status is 3, naming the component")
        ->type_name("N")
        ->check(CLI::NonNegativeNumber.description(""))
        ->capture_default_str();
  }
  tool.app.add_flag("--voxel-sides,!--no-voxel-sides", bounds_.voxel_sides,
                    "Refine until every voxel centre next to the voxel boundary lies on its own side of the "
                    "surface (foreground inside, background outside), a point of the surface near it inserted "
                    "where not; the certificate counts the centres on the "
                    "wrong side and fails on one (on by default; --no-voxel-sides: off, counted only)");
  tool.app.add_option("--max-points", bounds_.max_points,
                      "Safety bound on the number of sample points; when hit, the mesh is written and the exit "
                      "status is 3")
      ->type_name("N")
      ->capture_default_str();
}

void add_normals_option(cli::Tool& tool, bool& normals) {
  tool.app.add_flag("--normals", normals, "Write per-vertex normals from grad f (PLY, OBJ, VTP, VTK, msh)");
}

void warn_normals_ignored(const cli::Tool& tool, bool normals, const std::string& out, const std::string& advice) {
  if (normals && !surface_output_holds_normals(out))
    tool.info("warning: --normals ignored: " + surface_format_name(out) + " holds no normals" + advice);
}

std::string surface_format_name(const std::string& out) { return out == "-" ? "OFF" : extension_of(out); }

} // namespace imgmesh
