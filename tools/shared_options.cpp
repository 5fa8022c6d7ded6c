#include "shared_options.hpp"

#include "util/error.hpp"
#include "util/parse.hpp"
#include "util/path.hpp"

#include <cmath>
#include <sstream>
#include <utility>
#include <vector>

namespace imgmesh {

CLI::Option* add_msh_version_option(cli::Tool& tool, std::string& version, const std::string& description) {
  return tool.app.add_option("--msh-version", version, description)
      ->check(CLI::IsMember({"4.1", "2.2"}))
      ->capture_default_str();
}

CLI::Option* add_ascii_option(cli::Tool& tool, bool& ascii, const std::string& binary_formats) {
  return tool.app.add_flag("--ascii", ascii,
                           "Write " + binary_formats + " as text; by default binary (exact: the same numbers as the "
                           "text, in less space and time)");
}

void add_encoding_options(cli::Tool& tool, bool& ascii, bool& msh_binary, const std::string& binary_formats) {
  auto* a = add_ascii_option(tool, ascii, binary_formats);
  tool.app.add_flag("--msh-binary", msh_binary, "Write .msh in Gmsh's binary form (little-endian); ASCII by default")
      ->excludes(a);
}

void add_repair_mode_option(cli::Tool& tool, RepairMode& mode, const std::string& description) {
  static const std::vector<std::pair<std::string, RepairMode>> modes{
      {"add", RepairMode::Add}, {"remove", RepairMode::Remove}, {"min", RepairMode::Min}};
  std::vector<std::string> names;
  std::string current;
  for (const auto& [name, m] : modes) {
    names.push_back(name);
    if (m == mode) current = name;
  }
  tool.app
      .add_option_function<std::string>(
          "--mode",
          [&mode](const std::string& given) {
            for (const auto& [name, m] : modes)
              if (name == given) mode = m;
          },
          description)
      ->check(CLI::IsMember(names))
      ->default_str(current);
}

std::string planar_output_extension(const std::string& out) {
  const std::string ext = out == "-" ? std::string(".off") : extension_of(out);
  if (ext != ".ele" && ext != ".off" && ext != ".vtk" && ext != ".msh" && ext != ".svg")
    throw UsageError("OUT must end in .ele, .off, .vtk, .msh or .svg (or be - for OFF on stdout)", out);
  return ext;
}

void check_svg_path(const std::string& svg) {
  if (!svg.empty() && extension_of(svg) != ".svg") throw UsageError("--svg needs a .svg file name", svg);
}

std::vector<long long> parse_label_list(const std::string& text) {
  std::vector<long long> out;
  if (text == "all") return out;
  std::istringstream in(text);
  for (std::string item; std::getline(in, item, ',');) {
    long long v = 0;
    if (!parse_integer(item, v))
      throw UsageError("--labels " + text + ": 'all' or a comma-separated list of integers expected");
    out.push_back(v);
  }
  if (out.empty()) throw UsageError("--labels: no label given");
  return out;
}

namespace {
// --cell-ratio, then --cell-size (add_size), then the rest, in --help's order.
template <class AddSize>
void add_cell_options_with(cli::Tool& tool, double& ratio, AddSize add_size, double& sliver_angle,
                           long long& max_points) {
  tool.app.add_option("--cell-ratio", ratio, "Radius-edge ratio bound R of every tetrahedron (>= 2)")
      ->type_name("R")
      ->capture_default_str();
  add_size();
  tool.app.add_option("--sliver-angle", sliver_angle,
                      "Slivers: refine every tetrahedron with a dihedral angle below A degrees too (its "
                      "circumcentre, or the surface triangle it encroaches on), after the ratio and size bounds; "
                      "best effort, counted in --stats; 0: off; below 30")
      ->type_name("A")
      ->capture_default_str();
  tool.app.add_option("--max-cell-points", max_points,
                      "Stop cell refinement after inserting N points (exit 3, the mesh written)")
      ->type_name("N")
      ->capture_default_str();
}
} // namespace

void add_cell_options(cli::Tool& tool, double& ratio, double& size, double& sliver_angle, long long& max_points) {
  add_cell_options_with(
      tool, ratio,
      [&] {
        tool.app.add_option("--cell-size", size, "Circumradius bound of every tetrahedron (world units); 0: none")
            ->type_name("S")
            ->capture_default_str();
      },
      sliver_angle, max_points);
}

void add_cell_options(cli::Tool& tool, double& ratio, std::string& sizes, double& sliver_angle,
                      long long& max_points) {
  add_cell_options_with(
      tool, ratio,
      [&] {
        tool.app
            .add_option("--cell-size", sizes,
                        "Circumradius bound of every tetrahedron (world units), or per label: 3=0.5,5=2 (a bare S "
                        "beside them: the other labels'); 0: none")
            ->type_name("S|L=S,...")
            ->capture_default_str();
      },
      sliver_angle, max_points);
}

CellSizes parse_cell_sizes(const std::string& text, bool background) {
  CellSizes out;
  bool bare = false;
  std::size_t start = 0;
  for (;;) {
    const std::size_t comma = text.find(',', start);
    const std::string item = text.substr(start, comma == std::string::npos ? std::string::npos : comma - start);
    const std::size_t eq = item.find('=');
    auto refuse = [&] {
      return UsageError("--cell-size: '" + item + "' is not S or L=S (S a finite number >= 0, L a label above 0" +
                        (background ? std::string(" or 0, the background)") : std::string("; 0, the background, with --outside)")));
    };
    auto number = [&](const std::string& t) {
      double v = -1;
      if (!parse_real(t, v) || !(v >= 0) || !std::isfinite(v)) throw refuse();
      return v;
    };
    if (eq == std::string::npos) {
      if (bare) throw UsageError("--cell-size: more than one bound for the other labels");
      bare = true;
      out.all = number(item);
    } else {
      const std::string l = item.substr(0, eq);
      long long label = 0;
      if (!parse_integer(l, label) || label < (background ? 0 : 1) || label > 2147483647) throw refuse();
      const double v = number(item.substr(eq + 1));
      for (const auto& e : out.by_label)
        if (e.first == label) throw UsageError("--cell-size: label " + l + " given twice");
      out.by_label.emplace_back(std::int32_t(label), v);
    }
    if (comma == std::string::npos) break;
    start = comma + 1;
  }
  return out;
}

void check_cell_options(double ratio, double size, double sliver_angle, long long max_points) {
  if (!(ratio >= 2) || !std::isfinite(ratio)) throw UsageError("--cell-ratio must be at least 2");
  if (!(size >= 0) || !std::isfinite(size)) throw UsageError("--cell-size must be a finite number >= 0");
  if (!(sliver_angle >= 0 && sliver_angle < 30)) throw UsageError("--sliver-angle must be in [0, 30) degrees");
  if (max_points < 1) throw UsageError("--max-cell-points must be at least 1");
}

} // namespace imgmesh
