// implicit2tet: tetrahedra inside the certified surface of f^-1(0) (thesis
// 9.1), and with --outside between it and the image box too:
// implicit2mesh's restricted Delaunay surface, then the same triangulation
// refined until every tetrahedron's radius-edge ratio is within
// --cell-ratio, the surface certificate holding at the end.
#include "cli/cli.hpp"
#include "implicit_input.hpp"
#include "mesh/volume_io.hpp"
#include "shared_options.hpp"
#include "surface_options.hpp"
#include "util/error.hpp"
#include "volume/tet_refinement.hpp"

#include <sstream>

using namespace imgmesh;

int main(int argc, char** argv) {
  cli::Tool tool("implicit2tet",
                 "Mesh the inside of the zero set of an implicit function file (wc2implicit's output) by "
                 "tetrahedra: the surface as implicit2mesh makes it (closed, oriented, with the voxel boundary's "
                 "topology, certified), then the same Delaunay triangulation refined inside until every "
                 "tetrahedron's radius-edge ratio is within --cell-ratio (Siqueira 2006, 9.1; Oudot-Rineau-Yvinec 2005).");
  std::string in, out;
  TetRefinementOptions opt;
  TetWriteOptions wopt;
  tool.app.add_option("IN", in, "Implicit function file written by wc2implicit (- for stdin)")->required();
  tool.app.add_option("OUT", out, "Output tetrahedral mesh: .msh (Gmsh), .mesh (MEDIT), .vtu (VTK) or .inp (Abaqus)")
      ->required();
  tool.data_output(out);
  add_cell_options(tool, opt.cell_ratio, opt.cell_size, opt.sliver_angle, opt.max_cell_points);
  tool.app.add_flag("--outside", opt.outside,
                    "Also mesh the outside of the surface up to the image box (the voxels' extent) as region 2; "
                    "region 1 is the inside, the box's faces are boundary group 2");
  add_msh_version_option(tool, wopt.msh_version, "Gmsh format version of a .msh output: 4.1 or 2.2")->type_name("V");
  add_encoding_options(tool, wopt.ascii, wopt.msh_binary, ".vtu");
  SurfaceOptions surface_options(tool, "boundary triangle");
  tool.add_seed();
  tool.add_threads();

  return tool.run(argc, argv, [&] {
    if (out == "-") throw UsageError("tetrahedral meshes are written to a file (.msh, .mesh, .vtu or .inp), not to stdout");
    if (!is_tet_mesh_path(out))
      throw UsageError(std::string("output format is chosen by extension: ") + kTetMeshExtensions, out);
    check_cell_options(opt.cell_ratio, opt.cell_size, opt.sliver_angle, opt.max_cell_points);
    const MesherInput input = read_mesher_input(tool, in, surface_options);
    opt.surface = input.options;
    opt.surface.seed = tool.seed();
    opt.surface.threads = tool.threads();
    if (tool.progress()) opt.surface.progress = [&](const std::string& msg) { tool.report_progress(msg); };
    const PartitionOfUnitySurface surface(input.f);
    const TetRefinementResult res = tetrahedral_mesh(surface, opt);
    write_tet_mesh(out, res.mesh, wopt);

    tool.stats["input"] = in;
    tool.stats["output"] = out;
    std::ostringstream msg;
    msg << res.mesh.tets.size() << " tetrahedra, " << res.mesh.points.size() << " vertices, largest radius-edge ratio "
        << res.quality.max_radius_edge_ratio << ", smallest dihedral angle " << res.quality.min_dihedral << " degrees";
    tool.debug(msg.str());
    return tool.finish(res);
  });
}
