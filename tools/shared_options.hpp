// Options and checks that several tools share, declared once: --msh-version,
// --ascii and --msh-binary (implicit2mesh, implicit2tet, seg2mesh), --mode (img2wc, seg2mesh), the
// planar OUT of poly2tri and tri2quad and the --svg of img2poly and
// tri2quad. The surface mesher's own are in surface_options.hpp.
#pragma once
#include "cli/cli.hpp"
#include "wellcomposed/well_composed.hpp"

#include <cstdint>
#include <string>
#include <utility>
#include <vector>

namespace imgmesh {

// --msh-version: the Gmsh format version of a .msh output, 4.1 or 2.2.
CLI::Option* add_msh_version_option(cli::Tool& tool, std::string& version, const std::string& description);

// --ascii (alone: poly2tri, tri2quad, quadsmooth, whose .vtk is binary by
// default) and --msh-binary: OUT's encoding. Binary by default where the
// format has a binary form (`binary_formats`, e.g. ".ply, .stl, .vtp and
// .vtk"); .msh ASCII unless --msh-binary. The two exclude each other.
CLI::Option* add_ascii_option(cli::Tool& tool, bool& ascii, const std::string& binary_formats);
void add_encoding_options(cli::Tool& tool, bool& ascii, bool& msh_binary, const std::string& binary_formats);

// --cell-ratio, --cell-size, --sliver-angle, --max-cell-points: the bounds
// of cell refinement (implicit2tet, seg2tet), and their check after
// parsing (UsageError naming the option).
void add_cell_options(cli::Tool& tool, double& ratio, double& size, double& sliver_angle, long long& max_points);
// seg2tet's: --cell-size as text, "S" or per label "L=S,L=S[,S]" (parse_cell_sizes).
void add_cell_options(cli::Tool& tool, double& ratio, std::string& sizes, double& sliver_angle, long long& max_points);
struct CellSizes {
  double all = 0;                                      // the labels not named
  std::vector<std::pair<std::int32_t, double>> by_label;  // in the order given
};
// UsageError naming the item unless every item is S or L=S (S finite >= 0,
// L > 0), at most one bare S, no label twice.
// background: label 0 (the background, seg2tet --outside) may be given too.
CellSizes parse_cell_sizes(const std::string& text, bool background = false);
void check_cell_options(double ratio, double size, double sliver_angle, long long max_points);

// --labels: "all" (empty: every nonzero value) or a comma-separated list
// of integers ("1,2,5"); UsageError otherwise (seg2mesh, seg2tet).
std::vector<long long> parse_label_list(const std::string& text);

// --mode: img2wc's repair, add, remove or min; its default is mode's value.
void add_repair_mode_option(cli::Tool& tool, RepairMode& mode, const std::string& description);

// The extension of a planar mesh OUT (".off" for "-", OFF on stdout);
// UsageError unless it is .ele, .off, .vtk, .msh or .svg.
std::string planar_output_extension(const std::string& out);
// UsageError unless --svg FILE, when given, ends in .svg.
void check_svg_path(const std::string& svg);

} // namespace imgmesh
