// img2poly: from a 2D segmented image to a PSLG of its simplified pixel
// boundary plus the domain rectangle (thesis 2.3, 3.3.3).
#include "cli/cli.hpp"
#include "image/io.hpp"
#include "planar/image_pslg.hpp"
#include "planar/planar_formats.hpp"
#include "shared_options.hpp"
#include "util/error.hpp"
#include "util/path.hpp"

#include <sstream>
#include <unordered_set>

using namespace imgmesh;

// More distinct values than this without --label or --threshold: a grey image, most likely.
constexpr std::size_t kGreyLevels = 64;

int main(int argc, char** argv) {
  cli::Tool tool("img2poly",
                 "Turn a 2D binary or label image into a Triangle .poly: the pixel boundary of its "
                 "well-composed version, simplified within a Hausdorff tolerance with its topology kept, "
                 "plus the image rectangle, with one regional point per region giving its label");
  std::string in, out, svg;
  Selection sel;
  ImagePslgOptions opt;
  tool.app.add_option("IN", in, "Input 2D image (PNG, NRRD, MetaImage, NIfTI; - for stdin)")->required();
  tool.app.add_option("OUT", out, "Output PSLG, Triangle .poly (- for stdout)")->required();
  tool.data_output(out);
  auto* label = tool.app.add_option("--label", sel.labels,
                                    "Keep this label (repeatable); other pixels become background 0. "
                                    "Default: every value is a label")
                    ->type_name("L")
                    ->allow_extra_args(false);
  auto* thr = tool.app.add_option("--threshold", sel.threshold, "Binary image: foreground is value >= T")
                  ->type_name("T")
                  ->excludes(label);
  tool.app.add_option("--tolerance", opt.tolerance,
                      "Hausdorff bound E between each simplified curve and the pixel boundary, in pixels, 0 to "
                      "1000000 (0 keeps every corner)")
      ->capture_default_str()
      ->type_name("E")
      ->check(CLI::Range(0.0, 1e6).description(""));
  tool.app.add_option("--min-angle", opt.min_angle,
                      "Do not simplify into angles below A degrees between segments, 0 to 60 (keeps thin parts "
                      "from becoming slivers; 0 = off)")
      ->capture_default_str()
      ->type_name("A")
      ->check(CLI::Range(0.0, 60.0).description(""));
  tool.app.add_option("--svg", svg, "Also draw the curves over the image to this SVG file")->type_name("FILE");
  bool svg_whole = false;
  tool.app.add_flag("--svg-whole", svg_whole, "Draw the whole image in the SVG, not a frame around the foreground");
  tool.add_seed();
  // Tests only (hidden): simplify without the tolerance stop, so that the
  // final Hausdorff measure must catch the broken bound (exit 3).
  bool skip_stop = false;
  tool.app.add_flag("--skip-tolerance-stop", skip_stop)->group("");

  return tool.run(argc, argv, [&] {
    if (extension_of(out) != ".poly" && out != "-") throw UsageError("OUT must end in .poly", out);
    check_svg_path(svg);
    opt.seed = tool.seed();
    opt.tolerance_stop = !skip_stop;
    if (in != "-") {
      // Refuse a volume or a huge grid from the header, before reading voxels.
      const ImageInfo info = read_image_info(in);
      const auto& g = info.geometry;
      if (g.dimension == 3 && g.size[2] != 1)
        throw Error("a 3D image (" + std::to_string(g.size[2]) + " slices): img2poly needs a 2D image", in);
      if (g.size[0] > 65536 || g.size[1] > 65536 || g.size[0] * g.size[1] > (std::size_t(1) << 28))
        throw Error("image too large for img2poly (at most 65536 pixels a side and 2^28 pixels)", in);
    }
    sel.has_threshold = thr->count() > 0;
    const LabelImage img = read_labels(in, sel);
    if (!sel.has_threshold && sel.labels.empty()) {
      // Every value is a label: a grey image makes a region of each.
      std::unordered_set<std::int32_t> values;
      for (std::size_t i = 0; i < img.data.size() && values.size() <= kGreyLevels; ++i) values.insert(img.data[i]);
      if (values.size() > kGreyLevels)
        tool.info(in + ": more than " + std::to_string(kGreyLevels) +
                  " distinct values, each taken as a label: for a grey image give --threshold T (or --label L)");
    }

    tool.report_progress("tracing and simplifying the pixel boundary");
    const auto r = naming_input(in, [&] { return image_to_pslg(img, opt); });
    write_poly(out, r.pslg);
    if (!svg.empty()) {
      const SvgBackground bg = label_background(r.labels);
      PlanarWriteOptions wo;
      wo.background = &bg;
      wo.svg_frame_foreground = !svg_whole;
      write_planar_mesh(svg, r.pslg, wo);
    }

    tool.stats["input"] = in;
    std::ostringstream msg;
    msg << r.curves << " curves, " << r.pslg.points.size() << " vertices (from " << r.boundary_vertices
        << "), " << r.regions << " regions, Hausdorff " << r.hausdorff << " px";
    tool.info(msg.str());
    return tool.finish(r);
  });
}
