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
  tool.app.add_option("OUT", out, "Output surface: .off, .ply, .obj or .stl (- for OFF on stdout)")->required();
  tool.data_output(out);
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
  tool.app.add_flag("--normals", normals, "Write per-vertex normals from grad f (PLY and OBJ)");
  tool.app.add_option("--fallback-rounds", opt.fallback_rounds,
                      "Where the final certificate finds a component with the wrong topology (TOPOLOGY should "
                      "leave none), at most this many rounds of HandleDetection and then denser sampling there; "
                      "if it still differs, the mesh is written and the exit status is 3, naming the component")
      ->type_name("N")
      ->check(CLI::NonNegativeNumber)
      ->capture_default_str();
  // Tests only (hidden): no VorEdge, TopoDisk, FacetCycle or HandleDetection,
  // so that the certificate fails and its repairs must act.
  bool skip_topology = false;
  tool.app.add_flag("--skip-topology-steps", skip_topology)->group("");
  tool.app.add_flag("--seed-deletion", opt.seed_deletion,
                    "SAMPLETOPOLOGY as published (7.6.2): TOPOLOGY alone first, then delete the seeds and HandleDetection's points one by one; "
                    "slower and not smaller in practice");

  return tool.run(argc, argv, [&] {
    const std::string ext = extension_of(out);
    if (out != "-" && ext != ".off" && ext != ".ply" && ext != ".obj" && ext != ".stl")
      throw UsageError("output format is chosen by extension: .off, .ply, .obj or .stl", out);
    if (!(opt.ratio >= min_ratio_bound()))
      throw UsageError("--ratio " + std::to_string(opt.ratio) + " is below the termination limit (1+k)^2 = 1.1236");
    if (!(opt.roughness >= min_roughness_bound()))
      throw UsageError("--roughness " + std::to_string(opt.roughness) +
                       " is below the termination limit 2(arcsin k + arcsin(2k/sqrt 3)) = 0.2587 rad (14.8 degrees)");
    if (!(opt.max_distance >= 0) || !std::isfinite(opt.max_distance))
      throw UsageError("--max-distance must be a finite number >= 0");
    opt.topology_steps = !skip_topology;
    opt.seed = tool.seed();
    opt.threads = tool.threads();
    if (tool.progress()) opt.progress = [&](const std::string& msg) { tool.report_progress(msg); };

    tool.report_progress("reading " + in);
    const PartitionOfUnity pu = read_implicit(in);
    const PartitionOfUnitySurface surface(pu);
    RestrictedDelaunayResult res = restricted_delaunay_mesh(surface, opt);
    if (normals) add_normals(surface, res.mesh);
    write_surface(out, res.mesh);

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
