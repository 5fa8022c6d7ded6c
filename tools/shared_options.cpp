#include "shared_options.hpp"

#include "util/error.hpp"
#include "util/path.hpp"

#include <exception>
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
    std::size_t used = 0;
    long long v = 0;
    try {
      v = std::stoll(item, &used);
    } catch (const std::exception&) {
      used = 0;
    }
    if (used == 0 || used != item.size())
      throw UsageError("--labels " + text + ": 'all' or a comma-separated list of integers expected");
    out.push_back(v);
  }
  if (out.empty()) throw UsageError("--labels: no label given");
  return out;
}

} // namespace imgmesh
