#include "implicit_input.hpp"

#include "implicit/implicit_file.hpp"

namespace imgmesh {

MesherInput read_mesher_input(const cli::Tool& tool, const std::string& in, const SurfaceOptions& surface_options) {
  surface_options.check();
  tool.report_progress("reading " + in);
  RestrictedDelaunayOptions options;
  PartitionOfUnity f = read_implicit(in, [&](const Geometry& grid) {
    options = surface_options.resolve(grid.spacing);
    return PartitionOfUnity::clamp_for(grid, options.max_distance);
  });
  return {std::move(f), std::move(options)};
}

} // namespace imgmesh
