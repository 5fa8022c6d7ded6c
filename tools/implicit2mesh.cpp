// implicit2mesh: a closed, oriented triangle surface of f^-1(0) with the
// topology of the voxel boundary and bounded radius-edge ratios (thesis
// ch. 7-8: restricted Delaunay surface, simplified Cheng-Dey-Ramos-Ray).
#include "cli/cli.hpp"
#include "implicit/implicit_file.hpp"
#include "mesh/surface_io.hpp"
#include "surface/restricted_delaunay.hpp"
#include "util/atomic_file.hpp"
#include "util/error.hpp"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdlib>
#include <sstream>

using namespace imgmesh;

namespace {

// An angle of the command line in degrees ("90", "90deg"), or in radians
// with a suffix "rad" ("1.5708rad") or as a multiple of pi ("pi/2",
// "2pi/3", "0.5pi"). NaN when it is none of these.
double parse_angle(std::string s) {
  s.erase(std::remove_if(s.begin(), s.end(), [](unsigned char c) { return std::isspace(c); }), s.end());
  const auto number = [](const std::string& t, double empty) {
    if (t.empty()) return empty;
    char* end = nullptr;
    const double v = std::strtod(t.c_str(), &end);
    return end == t.c_str() + t.size() && std::isfinite(v) ? v : NAN;
  };
  const auto suffix = [&s](const std::string& x) {
    if (s.size() <= x.size() || s.compare(s.size() - x.size(), x.size(), x) != 0) return false;
    s.resize(s.size() - x.size());
    return true;
  };
  const std::size_t pi = s.find("pi");
  if (pi != std::string::npos) {  // [a][*]pi[/b]
    std::string a = s.substr(0, pi), b = s.substr(pi + 2);
    if (!a.empty() && a.back() == '*') a.pop_back();
    if (!b.empty() && b[0] != '/') return NAN;
    const double den = b.empty() ? 1.0 : number(b.substr(1), NAN);
    return number(a, 1.0) * M_PI / den;
  }
  if (suffix("rad")) return number(s, NAN);
  suffix("deg");
  return number(s, NAN) * M_PI / 180;
}

} // namespace

int main(int argc, char** argv) {
  cli::Tool tool("implicit2mesh",
                 "Mesh the zero set of an implicit function file (wc2implicit's output) by a restricted Delaunay "
                 "surface: closed, oriented, with the components and Euler characteristics of the voxel boundary, "
                 "and every triangle's radius-edge ratio within --ratio (Siqueira 2006, ch. 7-8).");
  std::string in, out;
  RestrictedDelaunayOptions opt;
  // The tool's defaults (issue 17, measured in doc/benchmarks.md): triangles
  // of smallest angle about 24.6 degrees, one-voxel features not resolved,
  // the error bounded by a quarter of a voxel. The library keeps the
  // thesis's values (rho_0 = 2, g = pi/3, no distance bound).
  opt.ratio = 1.2;
  std::string roughness = "90";
  std::string max_distance = "1/4 voxel";
  bool normals = false;
  tool.app.add_option("IN", in, "Implicit function file written by wc2implicit (- for stdin)")->required();
  tool.app.add_option("OUT", out, "Output surface: .off, .ply, .obj or .stl (- for OFF on stdout)")->required();
  tool.data_output(out);
  tool.app.add_option("--ratio", opt.ratio,
                      "Radius-edge ratio bound rho_0 of every triangle (>= (1+k)^2 = 1.1236); 1.2 gives a smallest "
                      "angle of 24.6 degrees, 2 (the thesis's) 14.5")
      ->type_name("R")
      ->capture_default_str();
  tool.app.add_option("--roughness", roughness,
                      "Roughness bound g in degrees (radians as pi/3 or 1.05rad): largest angle between the normals "
                      "of two triangles sharing an edge (>= 14.8 degrees); 90 leaves one-voxel features of noisy "
                      "labels unresolved, 60 (the thesis's) resolves each")
      ->type_name("G")
      ->capture_default_str();
  tool.app.add_option("--max-distance", max_distance,
                      "Refine while a triangle's surface Delaunay ball centre (a point of the surface) is farther "
                      "than E (world units) from the triangle's plane; 0: off")
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
  tool.app.add_flag("--seed-deletion", opt.seed_deletion,
                    "SAMPLETOPOLOGY as published (7.6.2): TOPOLOGY alone first, then delete the seeds and HandleDetection's points one by one; "
                    "slower and not smaller in practice");

  return tool.run(argc, argv, [&] {
    const std::string ext = extension_of(out);
    if (out != "-" && ext != ".off" && ext != ".ply" && ext != ".obj" && ext != ".stl")
      throw UsageError("output format is chosen by extension: .off, .ply, .obj or .stl", out);
    opt.roughness = parse_angle(roughness);
    if (std::isnan(opt.roughness))
      throw UsageError("--roughness " + roughness + ": not an angle (degrees, or radians as pi/3 or 1.05rad)");
    if (max_distance != "1/4 voxel") {
      char* end = nullptr;
      opt.max_distance = std::strtod(max_distance.c_str(), &end);
      if (max_distance.empty() || end != max_distance.c_str() + max_distance.size()) opt.max_distance = NAN;
    }
    if (!(opt.ratio >= min_ratio_bound()))
      throw UsageError("--ratio " + std::to_string(opt.ratio) + " is below the termination limit (1+k)^2 = 1.1236");
    if (!(opt.roughness >= min_roughness_bound()))
      throw UsageError("--roughness " + roughness +
                       " is below the termination limit 2(arcsin k + arcsin(2k/sqrt 3)) = 14.8 degrees (0.2587 rad; "
                       "a number without unit is in degrees)");
    if (!(opt.max_distance >= 0) || !std::isfinite(opt.max_distance))
      throw UsageError("--max-distance must be a finite number >= 0");
    opt.seed = tool.seed();
    opt.threads = tool.threads();
    if (tool.progress()) opt.progress = [&](const std::string& msg) { tool.report_progress(msg); };

    tool.report_progress("reading " + in);
    const PartitionOfUnity pu = read_implicit(in);
    const PartitionOfUnitySurface surface(pu);
    if (max_distance == "1/4 voxel") {
      const Vec3& h = surface.samples().spacing;
      opt.max_distance = std::min({h[0], h[1], h[2]}) / 4;
    }
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
