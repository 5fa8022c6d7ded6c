// tri2quad: strictly convex quadrilateral mesh of bounded size from a
// (constrained) triangle mesh (thesis chapter 3 and appendix B).
#include "cli/cli.hpp"
#include "planar/planar_formats.hpp"
#include "quad/quality.hpp"
#include "shared_options.hpp"
#include "tri2quad/tri2quad.hpp"
#include "util/error.hpp"

using namespace imgmesh;

int main(int argc, char** argv) {
  cli::Tool tool("tri2quad",
                 "Convert a triangle mesh (with constraint segments) into a strictly convex quadrilateral "
                 "mesh of bounded size (Siqueira 2006, chapter 3)");
  std::string in, out, constraints, svg;
  Tri2QuadOptions opt;
  tool.app.add_option("IN", in, "Input triangle mesh: Triangle .ele (with its .node; segments from the .poly "
                                "of the same basename when it exists) or OFF (- for OFF on stdin)")
      ->required();
  tool.app.add_option("OUT", out, "Output quad mesh by extension: .ele (+ .node, + .poly of the segments), "
                                  ".off, .vtk, .msh (Gmsh 2.2) or .svg; - for OFF on stdout")
      ->required();
  tool.data_output(out);
  PlanarWriteOptions wo;
  add_ascii_option(tool, wo.ascii, "a .vtk OUT");
  tool.app.add_option("--constraints", constraints, "Constraint segments from this .poly instead")
      ->type_name("FILE");
  tool.app.add_flag("--allow-outside", opt.allow_outside,
                    "Thesis step 5 as published: one Steiner point may lie outside the domain "
                    "(default: Joe's 5-quad split keeps every point inside)");
  // Beyond the thesis, on by default: a square lattice's halves (poly2tri's
  // default) become its squares, where the BFS pairing alone makes much of
  // it 45-degree parallelograms.
  opt.pair_above = 40;
  tool.app.add_option("--pair-above", opt.pair_above,
                      "First merge adjacent triangles whose quad has Joe's mu of at least MU degrees (best "
                      "first), then convert the rest around them; same guarantees (the plain conversion "
                      "is used where they would not hold); 0 to 45, 0: the thesis's conversion alone")
      ->capture_default_str()
      ->type_name("MU")
      ->check(CLI::Range(0.0, 45.0).description(""));
  // Tests only (hidden): pairs become quads without the convexity test, so
  // that the final check must catch the non-convex ones (exit 3).
  bool skip_convexity = false;
  tool.app.add_flag("--skip-convexity-test", skip_convexity)->group("");
  bool svg_whole = false;
  tool.app.add_flag("--svg-whole", svg_whole, "Draw the whole mesh in the SVG, not a frame around the foreground");
  tool.app.add_option("--svg", svg, "Also draw the quad mesh, coloured by Joe's mu, to this SVG file")
      ->type_name("FILE");

  return tool.run(argc, argv, [&] {
    // "-": OFF on standard output (the one single-file format for quads).
    const std::string ext = planar_output_extension(out);
    check_svg_path(svg);
    opt.convexity_test = !skip_convexity;
    PlanarMesh m = read_planar_mesh(in);
    if (!constraints.empty())
      m.segments = segments_on_mesh(read_poly(constraints), m, constraints, &m.segment_markers);
    const Tri2QuadInput input = tri2quad_input(std::move(m), in);
    if (tool.progress()) tool.report_progress("converting " + std::to_string(input.triangles.size()) + " triangles");
    const Tri2QuadResult r = tri2quad(input, opt);

    const PlanarMesh q = planar_mesh(r, input.index_base);
    std::vector<double> mu;
    mu.reserve(r.quads.size());
    for (const auto& f : r.quads)
      mu.push_back(joe_mu(r.points[f[0]], r.points[f[1]], r.points[f[2]], r.points[f[3]]));
    if (ext == ".svg" || ext == ".vtk") { wo.element_scalar = mu; wo.scalar_name = "mu"; }
    if (ext == ".svg") { wo.scalar_name = "Joe's mu (deg)"; wo.scalar_min = 0; wo.scalar_max = 45; wo.svg_frame_foreground = !svg_whole; }
    write_planar_mesh(out, q, wo);  // "-": OFF on stdout
    if (!svg.empty()) {
      PlanarWriteOptions so;
      so.element_scalar = mu;
      so.scalar_name = "Joe's mu (deg)";
      so.scalar_min = 0;
      so.scalar_max = 45;
      so.svg_frame_foreground = !svg_whole;
      write_planar_mesh(svg, q, so);
    }

    tool.stats["input"] = in;
    tool.info(std::to_string(r.triangles) + " triangles -> " + std::to_string(r.quads.size()) + " quads, " +
              std::to_string(r.steiner) + " Steiner points");
    return tool.finish(r);
  });
}
