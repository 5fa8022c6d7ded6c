// seg2tet (experimental, issue 41): tetrahedra of every label of a
// segmentation in one conforming mesh, a region per label: seg2mesh
// --conforming's restricted Delaunay complex of the repaired partition, its
// labelled cells refined as implicit2tet refines one region
// (conforming/conforming_surface.hpp), certified per interface and per label
// (segmentation/label_surface_nets.hpp).
#include "cli/cli.hpp"
#include "image/io.hpp"
#include "mesh/volume_io.hpp"
#include "segmentation/label_surface_nets.hpp"
#include "shared_options.hpp"
#include "surface_options.hpp"
#include "util/error.hpp"

#include <algorithm>
#include <sstream>
#include <thread>

using namespace imgmesh;

int main(int argc, char** argv) {
  cli::Tool tool("seg2tet",
                 "Experimental: mesh every label of a 3D segmentation (or those of --labels) by tetrahedra, one "
                 "conforming mesh with a region per label: the labels' partition repaired at once, its interfaces "
                 "meshed once (seg2mesh's experimental conforming mode), then each label's tetrahedra refined until "
                 "every radius-edge ratio is within --cell-ratio; certified per interface and per label (each "
                 "label's boundary the topology of its voxels, every voxel centre in a tetrahedron of its own "
                 "label), exit 3 when it does not hold. --outside: the background too, region 0 up to the image box.");
  std::string in, out, labels_text = "all";
  LabelSurfaceNetsOptions opt;
  opt.conforming = true;
  ConformingTetOptions& tets = opt.conforming_options.tets;
  tets.on = true;
  TetWriteOptions wopt;
  wopt.vtu_cell_data = "label";
  tool.app.add_option("IN", in, "Label image (NRRD, MetaImage, NIfTI, 3D Slicer's .seg.nrrd; - for stdin)")->required();
  tool.app.add_option("OUT", out,
                      "Output tetrahedral mesh in world (LPS) coordinates, region = label: .msh (Gmsh), .mesh "
                      "(MEDIT), .vtu (VTK, cell data \"label\") or .inp (Abaqus)")
      ->required();
  tool.data_output(out);
  tool.app.add_option("--labels", labels_text, "Labels to mesh: all (every nonzero value) or a list such as 1,2,5")
      ->type_name("all|L,L,...")
      ->capture_default_str();
  tool.app.add_flag("--outside", tets.outside,
                    "Also the background (label 0) as region 0 up to the image box B (the voxels' extent; the world box "
                    "around it when the image's axes are not the world's), refined alike, B's faces its boundary "
                    "triangles; Gmsh group \"background\" (tag: the largest label + 1), box faces \"box\"; "
                    "certified to fill B and to hold every background voxel centre");
  std::string sizes = "0";
  add_cell_options(tool, tets.cell_ratio, sizes, tets.sliver_angle, tets.max_cell_points);
  add_msh_version_option(tool, wopt.msh_version, "Gmsh format version of a .msh output: 4.1 or 2.2")->type_name("V");
  add_encoding_options(tool, wopt.ascii, wopt.msh_binary, ".vtu");
  SurfaceOptions surface_options(tool, "interface triangle", false);
  // The conforming mesher's distance default, not the Delaunay mesher's with VoxelSides.
  tool.app.get_option("--max-distance")->default_str("0.3 voxel");

  return tool.run(argc, argv, [&] {
    if (out == "-") throw UsageError("tetrahedral meshes are written to a file (.msh, .mesh, .vtu or .inp), not to stdout");
    if (!is_tet_mesh_path(out))
      throw UsageError(std::string("output format is chosen by extension: ") + kTetMeshExtensions, out);
    const CellSizes cell_sizes = parse_cell_sizes(sizes, tets.outside);  // 0=S: the background's
    tets.cell_size = cell_sizes.all;
    tets.cell_size_by_label = cell_sizes.by_label;
    check_cell_options(tets.cell_ratio, tets.cell_size, tets.sliver_angle, tets.max_cell_points);
    surface_options.check();
    opt.labels = parse_label_list(labels_text);
    opt.threads = std::max(1u, std::thread::hardware_concurrency());  // the same mesh whatever the count
    if (tool.progress()) opt.progress = [&](const std::string& msg) { tool.report_progress(msg); };

    tool.report_progress("reading " + in);
    LabelImage image = read_labels(in, &opt.names);
    for (const auto& e : tets.cell_size_by_label)  // a typo would bound nothing, silently (0: --outside's region 0)
      if (e.first != 0 && std::find(image.data.begin(), image.data.end(), e.first) == image.data.end())
        throw UsageError("--cell-size: label " + std::to_string(e.first) + " is not in the map");
    const RestrictedDelaunayOptions r = surface_options.resolve(image.spacing, MesherBounds::Mesher::kConforming);
    opt.conforming_options.ratio = r.ratio;
    opt.conforming_options.max_distance = r.max_distance;
    opt.conforming_options.max_points = r.max_points;
    opt.conforming_options.voxel_sides = r.voxel_sides;
    const LabelSurfaceNetsResult res = naming_input(in, [&] { return mesh_label_surface_nets(std::move(image), opt); });
    tool.report_progress("writing " + out);
    write_tet_mesh(out, res.tets, wopt);

    tool.stats["input"] = in;
    tool.stats["output"] = out;
    for (const InterfaceCertificate::Label* l : res.meshed_labels()) {
      const auto v = res.tet_quality.volume_by_region.find(int(l->label));
      std::ostringstream msg;
      msg << "label " << l->label << ": volume " << (v == res.tet_quality.volume_by_region.end() ? 0.0 : v->second)
          << " against " << l->voxel_volume << " of voxels; its boundary "
          << (l->surface.ok() ? "certified" : "NOT certified: " + l->surface.failure());
      tool.debug(msg.str());
    }
    if (res.outside) {
      const auto v = res.tet_quality.volume_by_region.find(0);
      std::ostringstream b;
      b << "background (region 0): volume " << (v == res.tet_quality.volume_by_region.end() ? 0.0 : v->second)
        << " against " << res.background_voxel_volume << " of voxels; the tetrahedra "
        << (res.box_filled ? "fill" : "do NOT fill") << " the box, its faces " << (res.box_covered ? "" : "NOT ")
        << "covered";
      tool.debug(b.str());
    }
    std::ostringstream msg;
    msg << res.tets.tets.size() << " tetrahedra, " << res.tets.points.size() << " vertices, largest radius-edge ratio "
        << res.tet_quality.max_radius_edge_ratio << ", smallest dihedral angle " << res.tet_quality.min_dihedral
        << " degrees";
    tool.debug(msg.str());
    return tool.finish(res);
  });
}
