// tri2quad: strictly convex quadrilateral mesh of bounded size from a
// (constrained) triangle mesh (thesis chapter 3 and appendix B).
#include "cli/cli.hpp"
#include "planar/planar_formats.hpp"
#include "quad/quality.hpp"
#include "quad/tri2quad.hpp"
#include "util/atomic_file.hpp"
#include "util/error.hpp"

#include <cstdio>
#include <cstdlib>
#include <map>

#include <unistd.h>

using namespace imgmesh;

namespace {
// Segments of a .poly given as ids of m (same numbering) or, with inline
// vertices, matched to m's vertices by position.
std::vector<std::array<int, 2>> constraints_from(const std::string& path, const PlanarMesh& m,
                                                 std::vector<int>& markers) {
  const PlanarMesh p = read_poly(path);
  auto s = segments_on_mesh(p, m, path, &markers);
  markers.resize(s.size(), 1);  // unmarked segments: marker 1
  return s;
}
} // namespace

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
  tool.app.add_option("--constraints", constraints, "Constraint segments from this .poly instead")
      ->type_name("FILE");
  tool.app.add_flag("--allow-outside", opt.allow_outside,
                    "Thesis step 5 as published: one Steiner point may lie outside the domain "
                    "(default: Joe's 5-quad split keeps every point inside)");
  tool.app.add_option("--pair-above", opt.pair_above,
                      "First merge adjacent triangles whose quad has Joe's mu of at least MU degrees (best "
                      "first), then convert the rest around them; same guarantees (the plain conversion "
                      "is used where they would not hold)")
      ->type_name("MU")
      ->check(CLI::Range(0.0, 45.0));
  tool.app.add_option("--svg", svg, "Also draw the quad mesh, coloured by Joe's mu, to this SVG file")
      ->type_name("FILE");

  return tool.run(argc, argv, [&] {
    // "-": OFF on standard output (the one single-file format for quads).
    const std::string ext = out == "-" ? std::string(".off") : extension_of(out);
    if (ext != ".ele" && ext != ".off" && ext != ".vtk" && ext != ".msh" && ext != ".svg")
      throw UsageError("OUT must end in .ele, .off, .vtk, .msh or .svg (or be - for OFF on stdout)", out);
    if (!svg.empty() && extension_of(svg) != ".svg") throw UsageError("--svg needs a .svg file name", svg);
    PlanarMesh m;
    if (in == "-") {
      // OFF on standard input, spooled to a temporary .off (the readers
      // choose the format by extension).
      const std::string text = read_all("-");
      const char* dir = std::getenv("TMPDIR");
      std::string tmp = std::string(dir && *dir ? dir : "/tmp") + "/tri2quad-stdin-XXXXXX.off";
      const int fd = mkstemps(tmp.data(), 4);
      if (fd < 0) throw Error("cannot create a temporary file", tmp);
      const bool ok = ::write(fd, text.data(), text.size()) == ssize_t(text.size());
      ::close(fd);
      try {
        if (!ok) throw Error("cannot write a temporary file", tmp);
        m = read_planar_mesh(tmp);
      } catch (const Error& e) {
        std::remove(tmp.c_str());
        throw Error(e.what(), "-");
      }
      std::remove(tmp.c_str());
    } else {
      m = read_planar_mesh(in);
    }
    Tri2QuadInput ti;
    ti.path = in;
    ti.index_base = m.first_index;
    ti.points = m.points;  // m.points is released below
    for (std::size_t i = 0; i < m.elements.size(); ++i) {
      const auto& e = m.elements[i];
      if (e.size() != 3)
        throw Error("element " + std::to_string(i + m.first_index) + " is not a triangle", in);
      ti.triangles.push_back({e[0], e[1], e[2]});
    }
    if (!m.element_attributes.empty() && m.element_attributes.size() == m.elements.size()) {
      for (const auto& a : m.element_attributes) ti.region.push_back(a.empty() ? 0.0 : a[0]);
      bool any = false;
      for (const auto& a : m.element_attributes) any = any || !a.empty();
      if (!any) ti.region.clear();
    }
    if (!constraints.empty()) {
      ti.constraints = constraints_from(constraints, m, ti.constraint_markers);
    } else {
      ti.constraints = m.segments;
      ti.constraint_markers = m.segment_markers;
    }
    // The per-element vectors cost ~56 bytes a triangle: free them now.
    std::vector<std::vector<int>>().swap(m.elements);
    std::vector<std::vector<double>>().swap(m.element_attributes);
    std::vector<Point2>().swap(m.points);
    if (tool.progress()) tool.report_progress("converting " + std::to_string(ti.triangles.size()) + " triangles");
    const Tri2QuadResult r = tri2quad(ti, opt);

    PlanarMesh q;
    q.first_index = m.first_index;
    q.points = r.points;
    q.elements.reserve(r.quads.size());
    for (const auto& f : r.quads) q.elements.push_back({f[0], f[1], f[2], f[3]});
    if (!r.region.empty())
      for (double a : r.region) q.element_attributes.push_back({a});
    q.segments = r.segments;
    q.segment_markers = r.segment_markers;
    const QualityReport quality = quality_report(r.points, r.quads);
    PlanarWriteOptions wo;
    std::vector<double> mu;
    mu.reserve(r.quads.size());
    for (const auto& f : r.quads)
      mu.push_back(joe_mu(r.points[f[0]], r.points[f[1]], r.points[f[2]], r.points[f[3]]));
    if (ext == ".svg" || ext == ".vtk") { wo.element_scalar = mu; wo.scalar_name = "mu"; }
    if (out == "-") {
      AtomicOutput o("-", false, ".off");
      write_planar_mesh(o.path(), q, wo);
      o.commit();
    } else {
      write_planar_mesh(out, q, wo);
    }
    if (!svg.empty()) {
      PlanarWriteOptions so;
      so.element_scalar = mu;
      so.scalar_name = "mu";
      write_planar_mesh(svg, q, so);
    }

    const bool quads_ok = r.quads.size() <= r.quad_bound();
    const bool steiner_ok = r.steiner <= r.steiner_bound(opt.allow_outside);
    tool.stats["input"] = in;
    tool.stats["triangles"] = r.triangles;
    tool.stats["components"] = r.components;
    tool.stats["quads"] = r.quads.size();
    tool.stats["steiner_points"] = r.steiner;
    tool.stats["steiner_outside"] = r.steiner_outside;
    tool.stats["repair_splits"] = r.repairs;
    tool.stats["quad_bound"] = r.quad_bound();
    tool.stats["steiner_bound"] = r.steiner_bound(opt.allow_outside);
    tool.stats["within_bounds"] = quads_ok && steiner_ok;
    tool.stats["quads_per_triangle"] = double(r.quads.size()) / double(r.triangles);
    tool.stats["steiner_per_triangle"] = double(r.steiner) / double(r.triangles);
    tool.stats["non_convex"] = quality.non_convex;
    Json cases = Json::object();
    for (const auto& [name, n] : r.cases) cases[name] = n;
    tool.stats["cases"] = cases;
    tool.stats["quality"] = quality.to_json();
    tool.stats["library_seconds"] = r.seconds;
    tool.stats["library_cpu_seconds"] = r.cpu_seconds;
    tool.info(std::to_string(r.triangles) + " triangles -> " + std::to_string(r.quads.size()) + " quads, " +
              std::to_string(r.steiner) + " Steiner points");
    if (quality.non_convex) {
      tool.info("guarantee not met: " + std::to_string(quality.non_convex) + " quads not strictly convex");
      return cli::kGuarantee;
    }
    if (!quads_ok || !steiner_ok) {
      tool.info("guarantee not met: size bound exceeded (quads " + std::to_string(r.quads.size()) + " / " +
                std::to_string(r.quad_bound()) + ", Steiner points " + std::to_string(r.steiner) + " / " +
                std::to_string(r.steiner_bound(opt.allow_outside)) + ")");
      return cli::kGuarantee;
    }
    return cli::kOk;
  });
}
