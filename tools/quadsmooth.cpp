// quadsmooth: improve a strictly convex quad mesh (thesis 3.2.3) without ever
// breaking convexity or moving a constrained vertex off its curve.
#include "cli/cli.hpp"
#include "planar/planar_formats.hpp"
#include "quad/quality.hpp"
#include "quadsmooth/smooth.hpp"
#include "shared_options.hpp"
#include "util/error.hpp"

#include <cmath>
#include <cstdio>
#include <string>

int main(int argc, char** argv) {
  imgmesh::cli::Tool tool("quadsmooth",
                          "Angle-based smoothing and topological clean-up of a strictly convex quad mesh");
  std::string in, out, svg;
  imgmesh::SmoothOptions opt;
  bool no_cleanup = false;
  tool.app.add_option("IN", in, "quad mesh: .ele (with its .node, and .poly for segments) or .off")->required();
  tool.app.add_option("OUT", out, "output mesh by extension: .ele (+ .node, .poly), .off, .vtk, .msh, .svg; - for OFF on stdout")
      ->required();
  tool.data_output(out);
  imgmesh::PlanarWriteOptions wo;
  imgmesh::add_ascii_option(tool, wo.ascii, "a .vtk OUT");
  tool.app.add_option("--iterations", opt.iterations, "smoothing passes, 0 to 1000000")
      ->type_name("N")
      ->check(CLI::Range(0, 1000000).description(""))
      ->capture_default_str();
  tool.app.add_flag("--no-cleanup", no_cleanup, "no diagonal swaps, doublet removal or quad collapses");
  tool.app.add_flag("--slide-boundary", opt.slide_boundary,
                    "let boundary and constrained vertices slide along their own straight segment");
  tool.app.add_option("--split-below", opt.split_below,
                      "split quad pairs around a new point where mu is below MU degrees, 0 to 45 (more: better "
                      "angles, more quads)")
      ->type_name("MU")
      ->check(CLI::Range(0.0, 45.0).description(""))
      ->capture_default_str();
  tool.app.add_option("--mean-rounds", opt.mean_rounds,
                      "rounds of the pass that raises the mean mu vertex by vertex after the smoothing, the "
                      "worst mu around each never lowered; 0 to 100")
      ->type_name("N")
      ->check(CLI::Range(0, 100).description(""))
      ->capture_default_str();
  tool.app.add_option("--grading", opt.grading,
                      "last, bring neighbouring quads whose sizes (square roots of the areas) differ by more than "
                      "R down to R where no quad falls under 10 degrees: vertex moves, collapses, pair splits; "
                      "0: off, else at least 1")
      ->type_name("R")
      ->default_str("2.449 (sqrt 6)");
  tool.app.add_option("--svg", svg, "also draw the result as SVG, quads coloured by Joe's mu")->type_name("FILE");
  bool svg_whole = false;
  tool.app.add_flag("--svg-whole", svg_whole, "Draw the whole mesh in the SVG, not a frame around the foreground");
  tool.add_threads();
  return tool.run(argc, argv, [&] {
    // Under 1 no pair could ever be within R.
    if (!(opt.grading == 0 || (opt.grading >= 1 && std::isfinite(opt.grading))))
      throw imgmesh::UsageError("--grading must be 0 or a finite number at least 1");
    opt.cleanup = !no_cleanup;
    opt.threads = tool.threads();
    if (tool.progress())
      opt.progress = [&](int pass, int passes) {
        tool.report_progress("pass " + std::to_string(pass) + "/" + std::to_string(passes));
      };
    imgmesh::PlanarMesh mesh = imgmesh::read_planar_mesh(in);
    bool quads_only = true;
    for (const auto& e : mesh.elements) quads_only = quads_only && e.size() == 4;
    // smooth_quad_mesh checks the input (conformity, orientation) first.
    const imgmesh::SmoothStats st = imgmesh::naming_input(in, [&] { return imgmesh::smooth_quad_mesh(mesh, opt); });
    if (!quads_only) tool.info(in + ": triangles found; their vertices stay fixed");
    imgmesh::write_planar_mesh(out, mesh, wo);
    if (!svg.empty()) {
      imgmesh::PlanarWriteOptions w;
      for (const auto& e : mesh.elements)
        w.element_scalar.push_back(e.size() == 4 ? imgmesh::joe_mu(mesh.points[e[0]], mesh.points[e[1]],
                                                                   mesh.points[e[2]], mesh.points[e[3]])
                                                 : 0.0);
      w.scalar_name = "Joe's mu (deg)";
      w.scalar_min = 0;
      w.scalar_max = 45;
      w.svg_frame_foreground = !svg_whole;
      imgmesh::write_planar_mesh(svg, mesh, w);
    }
    tool.stats["input"] = in;
    tool.stats["output"] = out;
    tool.stats["threads"] = tool.threads();
    char buf[200];
    std::snprintf(buf, sizeof buf, "%zu quads: Joe's mu min %.2f -> %.2f, median %.2f -> %.2f, mean %.2f -> %.2f",
                  st.after.quads, st.before.min_mu, st.after.min_mu, st.before.median_mu, st.after.median_mu,
                  st.before.mean_mu, st.after.mean_mu);
    if (tool.verbose()) tool.info(buf);
    return tool.finish(st);
  });
}
