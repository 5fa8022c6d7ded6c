// implicit2mesh: a closed, oriented triangle surface of f^-1(0) with the
// topology of the voxel boundary and bounded radius-edge ratios (thesis
// ch. 7-8: restricted Delaunay surface, simplified Cheng-Dey-Ramos-Ray).
#include "cli/cli.hpp"
#include "implicit/implicit_file.hpp"
#include "mesh/surface_io.hpp"
#include "surface/restricted_delaunay.hpp"
#include "util/atomic_file.hpp"
#include "util/error.hpp"

#include <cmath>
#include <sstream>

using namespace imgmesh;

int main(int argc, char** argv) {
  cli::Tool tool("implicit2mesh",
                 "Mesh the zero set of an implicit function file (wc2implicit's output) by a restricted Delaunay "
                 "surface: closed, oriented, with the components and Euler characteristics of the voxel boundary, "
                 "and every triangle's radius-edge ratio within --ratio (Siqueira 2006, ch. 7-8).");
  std::string in, out;
  RestrictedDelaunayOptions opt;
  bool normals = false;
  tool.app.add_option("IN", in, "Implicit function file written by wc2implicit (- for stdin)")->required();
  tool.app.add_option("OUT", out,
                      "Output surface in world (LPS) coordinates: .off, .ply, .obj, .stl, .vtp, .vtk or .msh "
                      "(- for OFF on stdout); .ply, .vtp, .vtk and .msh carry each face's component id")
      ->required();
  tool.data_output(out);
  SurfaceWriteOptions write_opt;
  tool.app.add_option("--ratio", opt.ratio, "Radius-edge ratio bound rho_0 of every triangle (>= (1+k)^2 = 1.1236)")
      ->type_name("R")
      ->capture_default_str();
  tool.app.add_option("--roughness", opt.roughness,
                      "Roughness bound g in radians: largest angle between the normals of two triangles sharing an "
                      "edge (>= 2(arcsin k + arcsin(2k/sqrt 3)) = 0.2587); default pi/3")
      ->type_name("G");
  tool.app.add_option("--max-distance", opt.max_distance,
                      "Also refine while a triangle's surface Delaunay ball centre (a point of the surface) is "
                      "farther than E (world units) from the triangle's plane; 0: off")
      ->type_name("E")
      ->capture_default_str();
  tool.app.add_option("--max-points", opt.max_points,
                      "Safety bound on the number of sample points; when hit, the mesh is written and the exit "
                      "status is 3")
      ->type_name("N")
      ->capture_default_str();
  tool.add_seed();
  tool.add_threads();
  tool.app.add_flag("--normals", normals, "Write per-vertex normals from grad f (PLY, OBJ, VTP, VTK, msh)");
  tool.app.add_option("--msh-version", write_opt.msh_version, "Gmsh format version of a .msh OUT")
      ->check(CLI::IsMember({"4.1", "2.2"}))
      ->capture_default_str();
  tool.app.add_flag("--seed-deletion", opt.seed_deletion,
                    "SAMPLETOPOLOGY as published (7.6.2): TOPOLOGY alone first, then delete the seeds and HandleDetection's points one by one; "
                    "slower and not smaller in practice");

  return tool.run(argc, argv, [&] {
    if (!is_surface_output(out))
      throw UsageError(std::string("output format is chosen by extension: ") + kSurfaceExtensions, out);
    if (normals && !surface_output_holds_normals(out))
      tool.info("warning: --normals ignored: " + std::string(out == "-" ? "OFF" : extension_of(out)) +
                " holds no normals (use .ply, .obj, .vtp, .vtk or .msh)");
    if (!(opt.ratio >= min_ratio_bound()))
      throw UsageError("--ratio " + std::to_string(opt.ratio) + " is below the termination limit (1+k)^2 = 1.1236");
    if (!(opt.roughness >= min_roughness_bound()))
      throw UsageError("--roughness " + std::to_string(opt.roughness) +
                       " is below the termination limit 2(arcsin k + arcsin(2k/sqrt 3)) = 0.2587 rad (14.8 degrees)");
    if (!(opt.max_distance >= 0) || !std::isfinite(opt.max_distance))
      throw UsageError("--max-distance must be a finite number >= 0");
    opt.seed = tool.seed();
    opt.threads = tool.threads();
    if (tool.progress()) opt.progress = [&](const std::string& msg) { tool.report_progress(msg); };

    tool.report_progress("reading " + in);
    const PartitionOfUnity pu = read_implicit(in);
    const PartitionOfUnitySurface surface(pu);
    RestrictedDelaunayResult res = restricted_delaunay_mesh(surface, opt);
    if (normals) add_normals(surface, res.mesh);
    write_surface(out, res.mesh, write_opt);

    tool.stats["input"] = in;
    tool.stats["output"] = out;
    std::ostringstream msg;
    msg << res.mesh.triangles.size() << " triangles, " << res.mesh.points.size() << " vertices, "
        << res.topology.components.size() << " component(s), Euler characteristic(s)";
    for (long long e : res.topology.sorted_euler()) msg << ' ' << e;
    msg << (res.topology_ok ? " (as the voxel boundary)" : " (voxel boundary:");
    if (!res.topology_ok)
      for (long long e : res.expected.sorted_euler()) msg << ' ' << e;
    if (!res.topology_ok) msg << ")";
    tool.debug(msg.str());
    return tool.finish(res);
  });
}
