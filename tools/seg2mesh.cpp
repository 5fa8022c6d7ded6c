// seg2mesh: every label of a segmentation meshed in one command, in
// parallel, into one surface file with a label per face: for each label L,
// what img2wc --label L | wc2implicit | implicit2mesh make, certified alike.
// --fast: surface nets on the repaired partition's interface complex, each
// interface once with its two labels (segmentation/label_surface_nets.hpp);
// --conforming (experimental): the restricted Delaunay surface of that
// partition (conforming/conforming_surface.hpp).
#include "cli/cli.hpp"
#include "image/io.hpp"
#include "mesh/surface_io.hpp"
#include "mesh/topology.hpp"
#include "segmentation/label_surface_nets.hpp"
#include "segmentation/label_surfaces.hpp"
#include "shared_options.hpp"
#include "surface_options.hpp"
#include "util/error.hpp"
#include "util/memory.hpp"

#include <algorithm>
#include <chrono>
#include <sstream>
#include <thread>

using namespace imgmesh;

namespace {
// The options of the Delaunay mesher, which --fast does not run.
// (--voxel-sides is one option with --no-voxel-sides.)
const char* const kDelaunayOnly[] = {"--jobs",          "--mode",        "--ratio",      "--roughness", "--max-distance",
                                     "--fallback-rounds", "--voxel-sides", "--max-points", "--seed",      "--normals"};

// The options of the per-label Delaunay mesher that --conforming does not
// take (it takes --ratio, --max-distance, --max-points, --voxel-sides).
const char* const kNotConforming[] = {"--jobs", "--mode", "--roughness", "--fallback-rounds", "--seed", "--normals",
                                      "--smooth"};

int run_fast(cli::Tool& tool, const std::string& in, const std::string& out, LabelSurfaceNetsOptions& opt,
             const SurfaceWriteOptions& write_opt, const SurfaceOptions& mesher) {
  auto refuse = [&](const auto& names, const std::string& why) {
    for (const char* name : names)
      if (const CLI::Option* o = tool.app.get_option_no_throw(name); o && o->count())
        throw UsageError(std::string(name) + why);
  };
  if (opt.conforming) {
    refuse(kNotConforming, ": --conforming does not take it");
    mesher.check();
  } else {
    refuse(kDelaunayOnly, " is the Delaunay mesher's: --fast does not take it");
  }
  if (tool.progress()) opt.progress = [&](const std::string& msg) { tool.report_progress(msg); };
  tool.report_progress("reading " + in);
  LabelImage image = read_labels(in, &opt.names);
  if (opt.conforming) {
    const RestrictedDelaunayOptions r = mesher.resolve(image.spacing, MesherBounds::Mesher::kConforming);
    opt.conforming_options.ratio = r.ratio;
    opt.conforming_options.max_distance = r.max_distance;
    opt.conforming_options.max_points = r.max_points;
    opt.conforming_options.voxel_sides = r.voxel_sides;
  }
  LabelSurfaceNetsResult res = naming_input(in, [&] { return mesh_label_surface_nets(std::move(image), opt); });
  const auto t0 = std::chrono::steady_clock::now();
  tool.report_progress("writing " + out);
  release_free_memory();  // the certificate's pages, before the writer's buffers
  write_surface(out, res.mesh, write_opt);
  res.seconds.push_back({"write", std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count()});
  tool.stats["input"] = in;
  tool.stats["output"] = out;
  for (const InterfaceCertificate::Label* l : res.meshed_labels()) {
    const auto name = res.mesh.label_names.find(int(l->label));
    const std::vector<long long> euler = l->surface.topology.sorted_euler();
    std::ostringstream msg;
    msg << "label " << l->label << (name == res.mesh.label_names.end() ? "" : " (" + name->second + ")") << ": "
        << l->triangles << " triangles, " << euler.size() << " components, Euler characteristics "
        << euler_summary(euler) << "; volume " << l->volume << " against " << l->voxel_volume << " of voxels";
    tool.debug(msg.str());
  }
  return tool.finish(res);
}
} // namespace

int main(int argc, char** argv) {
  cli::Tool tool("seg2mesh",
                 "Mesh every label of a 3D segmentation (or those of --labels) into one surface file with a label per "
                 "face: each label's surface is what img2wc (that label) | wc2implicit | implicit2mesh makes, certified "
                 "alike (closed, oriented, the topology of the label's voxel boundary); labels run in parallel.");
  std::string in, out, labels_text = "all";
  LabelSurfacesOptions opt;
  SurfaceWriteOptions write_opt;
  opt.jobs = int(std::max(1u, std::thread::hardware_concurrency()));
  tool.app.add_option("IN", in, "Label image (NRRD, MetaImage, NIfTI, 3D Slicer's .seg.nrrd; - for stdin)")->required();
  tool.app.add_option("OUT", out,
                      "Output surface in world (LPS) coordinates: .ply, .vtp, .vtk or .msh (a label and a component "
                      "id per face; with --fast the two labels each face separates); .off, .obj, .stl (no labels; - "
                      "for OFF on stdout)")
      ->required();
  tool.data_output(out);
  tool.app.add_option("--labels", labels_text, "Labels to mesh: all (every nonzero value) or a list such as 1,2,5")
      ->type_name("all|L,L,...")
      ->capture_default_str();
  tool.app.add_option("--jobs", opt.jobs, "Labels meshed at once, one thread each, 1 to 1024 (default: all cores)")
      ->type_name("N")
      ->check(CLI::Range(1, 1024).description(""));
  add_repair_mode_option(tool, opt.mode, "img2wc's --mode for each label: add, remove or min");
  SurfaceOptions surface_options(tool);
  tool.add_seed();
  add_normals_option(tool, opt.normals);
  add_msh_version_option(tool, write_opt.msh_version, "Gmsh format version of a .msh OUT");
  add_encoding_options(tool, write_opt.ascii, write_opt.msh_binary, ".ply, .stl, .vtp and .vtk");
  LabelSurfaceNetsOptions fast_opt;
  auto* fast = tool.app.add_flag("--fast",
                                 "Surface nets instead of the Delaunay mesher: the labels' partition repaired at once, "
                                 "every interface between two labels meshed once, its triangles carrying both labels "
                                 "(behind, front), each label's surface certified; seconds, not minutes");
  tool.app.add_option("--smooth", fast_opt.smooth_rounds,
                      "With --fast: rounds of smoothing, each vertex kept inside its voxel-corner cell (0: the voxel "
                      "faces)")
      ->type_name("N")
      ->check(CLI::Range(0, 1000).description(""))
      ->capture_default_str()
      ->needs(fast);
  auto* separate = tool.app.add_flag("--separate", fast_opt.separate,
                                     "With --fast or --conforming: each label's closed surface alone (interfaces "
                                     "written twice, a label per face) instead of each interface once with its two "
                                     "labels");
  auto* conforming =
      tool.app
          .add_flag("--conforming", fast_opt.conforming,
                    "Experimental: the labels' partition repaired at once, then its restricted Delaunay surface "
                    "(every interface once with its two labels, angles of asin(1/(2 --ratio)) or more, --max-distance), "
                    "refined until the interface certificate holds; exit 3 when it does not")
          ->excludes(fast);

  return tool.run(argc, argv, [&] {
    if (!is_surface_output(out))
      throw UsageError(std::string("output format is chosen by extension: ") + kSurfaceExtensions, out);
    if (!surface_output_holds_labels(out))
      tool.info("warning: " + surface_format_name(out) +
                " holds no labels: use .ply, .vtp, .vtk or .msh to tell the labels' surfaces apart");
    if (separate->count() && !fast->count() && !conforming->count())
      throw UsageError("--separate needs --fast or --conforming");
    if (fast->count() || conforming->count()) {
      fast_opt.labels = parse_label_list(labels_text);
      fast_opt.threads = std::max(1u, std::thread::hardware_concurrency());  // the same mesh whatever the count
      return run_fast(tool, in, out, fast_opt, write_opt, surface_options);
    }
    warn_normals_ignored(tool, opt.normals, out);
    opt.labels = parse_label_list(labels_text);
    surface_options.check();
    opt.threads = opt.jobs;
    if (tool.progress()) opt.progress = [&](const std::string& msg) { tool.report_progress(msg); };

    tool.report_progress("reading " + in);
    NarrowLabelImage image = read_labels_narrow(in, &opt.names);  // 1 or 2 bytes a voxel, until the last crop
    opt.mesher = surface_options.resolve(image.geometry().spacing);
    opt.mesher.seed = tool.seed();
    const LabelSurfacesResult res = naming_input(
        in, [&] { return image.visit([&](auto& im) { return mesh_label_surfaces(std::move(im), opt); }); });
    write_surface(out, res.mesh, write_opt);

    tool.stats["input"] = in;
    tool.stats["output"] = out;
    for (const LabelSurface& l : res.labels) {
      std::ostringstream msg;
      msg << "label " << l.label << (l.name.empty() ? "" : " (" + l.name + ")") << ": " << l.mesh.mesh.triangles.size()
          << " triangles, Euler characteristic(s)";
      for (long long e : l.mesh.topology.sorted_euler()) msg << ' ' << e;
      msg << ", " << l.seconds << " s";
      tool.debug(msg.str());
    }
    return tool.finish(res);
  });
}
