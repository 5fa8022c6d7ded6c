// poly2tri: constrained quality triangulation of a PSLG (what the thesis did
// with Triangle, section 3.3.3), with CGAL's Delaunay refinement.
#include "cli/cli.hpp"
#include "planar/planar_formats.hpp"
#include "planar/triangulate.hpp"
#include "shared_options.hpp"
#include "util/error.hpp"

#include <sstream>

using namespace imgmesh;

int main(int argc, char** argv) {
  cli::Tool tool("poly2tri",
                 "Triangulate a planar straight-line graph (Triangle .poly, or OFF polygons) into a "
                 "constrained Delaunay mesh with a minimum angle, conforming to every segment");
  std::string in, out, svg;
  TriangulateOptions opt;
  opt.grading = 0.25;
  double max_vertices = double(opt.max_vertices);
  tool.app.add_option("IN", in, "Input PSLG: Triangle .poly (or its .node) or OFF of polygons (- for a .poly on stdin)")->required();
  tool.app.add_option("OUT", out,
                      "Output mesh: NAME.ele (writes NAME.node and NAME.poly beside it); .off, .vtk, .msh "
                      "or .svg also work; - for OFF on stdout")
      ->required();
  tool.data_output(out);
  PlanarWriteOptions wo;
  add_ascii_option(tool, wo.ascii, "a .vtk OUT");
  tool.app.add_option("--min-angle", opt.min_angle,
                      "Smallest angle in degrees (0 = no quality refinement; at most 34); the bound holds "
                      "except near input angles below 60 degrees")
      ->capture_default_str()
      ->type_name("A");
  auto* area = tool.app.add_option("--max-area", opt.max_area, "No triangle larger than S > 0 (world units squared; default: no bound)")
                   ->type_name("S")
                   ->check(CLI::PositiveNumber.description(""));
  tool.app.add_option("--max-edge", opt.max_edge, "No edge longer than L > 0 (world units; default: no bound)")
      ->type_name("L")
      ->check(CLI::PositiveNumber.description(""))
      ->excludes(area);
  auto* lattice = tool.app.add_option("--lattice", opt.lattice,
                                      "Fill the domain with Steiner points on an equilateral-triangle lattice of "
                                      "side L, half a side away from the segments, before refining (tri2quad "
                                      "then makes 60-degree rhombi of them); L > 0 in world units, default: none")
                      ->type_name("L")
                      ->check(CLI::PositiveNumber.description(""));
  double square_lattice = -1;  // < 0: default_lattice_side
  tool.app.add_option("--square-lattice", square_lattice,
                      "Seed the domain with a square lattice of side L along the segments, coarsening away from "
                      "them (--grading) and down to L/2 where the domain is narrow (--no-narrow); its right "
                      "triangles make squares, which tri2quad merges first. "
                      "0: no lattice, Delaunay refinement's own points")
      ->default_str("half the median segment length, at least twice its 10th percentile")
      ->type_name("L")
      ->check(CLI::NonNegativeNumber.description(""))
      ->excludes(lattice);
  tool.app.add_option("--grading", opt.grading,
                      "Square lattice: at distance d from a segment of length S the side grows to about max(L, S) + G d, "
                      "doubling at most once from one cell to the next (0 to 0.5); 0: uniform")
      ->default_str("0.25")
      ->type_name("G")
      ->check(CLI::Range(0.0, 0.5).description(""));
  bool wide_only = false;
  tool.app.add_flag("--no-narrow", wide_only,
                    "Square lattice: no side under L (by default the lattice goes down to L/2 where the domain is "
                    "narrower than the size field asks for)");
  tool.app.add_option("--max-side", opt.max_side, "Square lattice: the coarsest side M > 0 (world units)")
      ->default_str("a tenth of the shorter side of the bounding box")
      ->type_name("M")
      ->check(CLI::PositiveNumber.description(""));
  tool.app.add_option("--max-vertices", max_vertices,
                      "Stop refining beyond this many vertices (exit status 3); a size bound that alone asks for more is refused at once")
      ->default_str(std::to_string(opt.max_vertices))
      ->type_name("N")
      ->check(CLI::PositiveNumber.description(""));
  bool svg_whole = false;
  tool.app.add_flag("--svg-whole", svg_whole, "Draw the whole mesh in the SVG, not a frame around the foreground");
  tool.app.add_option("--svg", svg, "Also draw the mesh (regions coloured, segments on top) to this SVG file")
      ->type_name("FILE");

  return tool.run(argc, argv, [&] {
    // Before any work; "-": OFF on standard output (the one single-file format for triangles).
    planar_output_extension(out);
    opt.max_vertices = std::size_t(max_vertices);
    if (tool.progress())
      opt.progress = [&](std::size_t n) { tool.report_progress(std::to_string(n) + " vertices"); };
    const PlanarMesh pslg = read_pslg(in);
    // The default: a graded square lattice from the curves' own sampling.
    if (opt.lattice <= 0 && square_lattice != 0) {
      opt.lattice = square_lattice > 0 ? square_lattice : default_lattice_side(pslg);
      opt.lattice_optional = square_lattice < 0;
      opt.square_lattice = opt.lattice > 0;
      if (opt.max_side <= 0) opt.max_side = default_max_side(pslg);
      opt.narrow = !wide_only;
    }
    const auto r = naming_input(in, [&] { return triangulate_pslg(pslg, opt); });
    write_planar_mesh(out, r.mesh, wo);  // "-": OFF on stdout
    if (!svg.empty()) {
      PlanarWriteOptions so;
      so.svg_frame_foreground = !svg_whole;
      write_planar_mesh(svg, r.mesh, so);
    }

    tool.stats["input"] = in;
    if (opt.square_lattice) {
      tool.stats["square_lattice"] = opt.lattice;
      tool.stats["grading"] = opt.grading;
      tool.stats["max_side"] = opt.max_side;
      tool.stats["narrow"] = opt.narrow;
    }
    std::ostringstream msg;
    msg << r.mesh.elements.size() << " triangles, " << r.mesh.points.size() << " vertices ("
        << r.steiner_points << " Steiner), smallest angle " << r.min_angle << " degrees";
    tool.info(msg.str());
    if (r.regions_outside_domain)
      tool.info(std::to_string(r.regions_outside_domain) + " regional point(s) lie outside the domain (ignored)");
    return tool.finish(r);
  });
}
