#include "implicit_input.hpp"

#include "implicit/crop.hpp"
#include "implicit/implicit_file.hpp"

#include <sstream>

namespace imgmesh {

MesherInput read_mesher_input(const cli::Tool& tool, const std::string& in, const SurfaceOptions& surface_options) {
  surface_options.check();
  tool.report_progress("reading " + in);
  RestrictedDelaunayOptions options;
  ScanFrame frame;
  bool placed = false;
  float clamp = 0;
  PartitionOfUnity f = read_implicit(
      in,
      [&](const Geometry& grid) {
        options = surface_options.resolve(grid.spacing);
        return clamp = PartitionOfUnity::clamp_for(grid, options.max_distance);
      },
      &frame, &placed);
  if (f.samples().clamp() < clamp) {
    std::ostringstream note;
    note << "note: the file's samples are clamped for a --max-distance up to " << kCoveredMaxDistance
         << " voxel: meshed on them (the same surface and signs; the |f| <= 2 E test sees them clamped; "
            "wc2implicit --full-distance keeps them all)";
    tool.info(note.str());
  }
  if (frame.present() && !placed)
    tool.info("note: the crop's margin does not cover this --max-distance: meshed on the crop's own grid (the same "
              "surface; its points may differ by rounding from those of the scan's whole grid, img2wc --full-grid)");
  return {std::move(f), std::move(options)};
}

} // namespace imgmesh
