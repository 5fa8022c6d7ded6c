// implicit2mesh: a closed, oriented triangle surface of f^-1(0) with the
// topology of the voxel boundary and bounded radius-edge ratios (thesis
// ch. 7-8: restricted Delaunay surface, simplified Cheng-Dey-Ramos-Ray).
#include "cli/cli.hpp"
#include "implicit_input.hpp"
#include "mesh/surface_io.hpp"
#include "shared_options.hpp"
#include "surface/restricted_delaunay.hpp"
#include "surface_options.hpp"
#include "util/error.hpp"

#include <sstream>

using namespace imgmesh;

int main(int argc, char** argv) {
  cli::Tool tool("implicit2mesh",
                 "Mesh the zero set of an implicit function file (wc2implicit's output) by a restricted Delaunay "
                 "surface: closed, oriented, with the components and Euler characteristics of the voxel boundary, "
                 "and every triangle's radius-edge ratio within --ratio (Siqueira 2006, ch. 7-8).");
  std::string in, out;
  bool normals = false, seed_deletion = false;
  tool.app.add_option("IN", in, "Implicit function file written by wc2implicit (- for stdin)")->required();
  tool.app.add_option("OUT", out,
                      "Output surface in world (LPS) coordinates: .off, .ply, .obj, .stl, .vtp, .vtk or .msh "
                      "(- for OFF on stdout); .ply, .vtp, .vtk and .msh carry each face's component id")
      ->required();
  tool.data_output(out);
  SurfaceWriteOptions write_opt;
  SurfaceOptions surface_options(tool);
  tool.add_seed();
  tool.add_threads();
  add_normals_option(tool, normals);
  add_msh_version_option(tool, write_opt.msh_version, "Gmsh format version of a .msh OUT");
  add_encoding_options(tool, write_opt.ascii, write_opt.msh_binary, ".ply, .stl, .vtp and .vtk");
  // Tests only (hidden): no VorEdge, TopoDisk, FacetCycle or HandleDetection,
  // so that the certificate fails and its repairs must act.
  bool skip_topology = false;
  tool.app.add_flag("--skip-topology-steps", skip_topology)->group("");
  tool.app.add_flag("--seed-deletion", seed_deletion,
                    "SAMPLETOPOLOGY as published (7.6.2): TOPOLOGY alone first, then delete the seeds and HandleDetection's points one by one; "
                    "slower and not smaller in practice");

  return tool.run(argc, argv, [&] {
    if (!is_surface_output(out))
      throw UsageError(std::string("output format is chosen by extension: ") + kSurfaceExtensions, out);
    warn_normals_ignored(tool, normals, out, " (use .ply, .obj, .vtp, .vtk or .msh)");
    MesherInput input = read_mesher_input(tool, in, surface_options);
    RestrictedDelaunayOptions& opt = input.options;
    opt.seed_deletion = seed_deletion;
    opt.topology_steps = !skip_topology;
    opt.seed = tool.seed();
    opt.threads = tool.threads();
    if (tool.progress()) opt.progress = [&](const std::string& msg) { tool.report_progress(msg); };
    const PartitionOfUnitySurface surface(input.f);
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
