#include "implicit_input.hpp"

#include "implicit/implicit_file.hpp"

namespace imgmesh {

MesherInput read_mesher_input(const cli::Tool& tool, const std::string& in, const SurfaceOptions& surface_options) {
  surface_options.check();
  tool.report_progress("reading " + in);
  RestrictedDelaunayOptions options;
  ScanFrame frame;
  bool placed = false;
  PartitionOfUnity f = read_implicit(
      in,
      [&](const Geometry& grid) {
        options = surface_options.resolve(grid.spacing);
        return PartitionOfUnity::clamp_for(grid, options.max_distance);
      },
      &frame, &placed);
  if (frame.present() && !placed)
    tool.info("note: the crop's margin does not cover this --max-distance: meshed on the crop's own grid (the same "
              "surface; its points may differ by rounding from those of the scan's whole grid, img2wc --full-grid)");
  return {std::move(f), std::move(options)};
}

} // namespace imgmesh
