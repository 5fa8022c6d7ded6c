// From a 2D segmented image to a PSLG (thesis 2.3, 3.3.3): the pixel-boundary
// complex bdCA(X) of a well-composed image plus the rectangle conv(D),
// simplified with topology kept and a Hausdorff bound, with one regional
// point per region carrying its label.
#pragma once
#include "image/grid.hpp"
#include "planar/planar_formats.hpp"
#include "planar/triangle_io.hpp"
#include "util/json.hpp"

#include <array>
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace imgmesh {

struct ImagePslgOptions {
  double tolerance = 1.0;  // E: Hausdorff bound between each simplified curve and bdCA, in pixels
  // Simplification does not create angles below this (degrees) between the
  // segments at a vertex, so no needlessly small input angles reach the mesher.
  double min_angle = 30;
  std::uint64_t seed = 0;  // for the well-composed repair
  // Tests only: false simplifies without the tolerance stop, so that the
  // final Hausdorff measure must find the bound broken (img2poly's hidden
  // --skip-tolerance-stop).
  bool tolerance_stop = true;
};

// The interface between two labels a < b, written as segment marker `marker`.
struct PixelInterface {
  int marker = 0;
  std::int32_t a = 0, b = 0;
};

struct ImagePslgResult {
  // World coordinates. The rectangle is the image's extent (pixel squares
  // included); curves may end on it. Segment marker 1 = the rectangle, 2, 3, ... = the
  // interfaces (see `interfaces`); one regional point per region (a pixel
  // centre deep inside it) with the region's label; no holes.
  PlanarMesh pslg;
  // The label image the curves bound (same grid as the input): repaired, no
  // two-label diagonal 2x2 pattern left.
  LabelImage labels;
  std::vector<PixelInterface> interfaces;
  std::size_t critical_configurations = 0;  // two-label diagonal 2x2 blocks in the input
  std::size_t changed_pixels = 0;           // pixels the repair changed
  std::size_t curves = 0, closed_curves = 0;
  std::size_t junctions = 0;  // curve ends: vertices of degree 3 or 4, and where curves meet the rectangle
  std::size_t boundary_vertices = 0;    // vertices of bdCA (before simplification)
  std::size_t simplified_vertices = 0;  // curve vertices after
  std::size_t regions = 0;
  double smallest_angle = 180;  // measured: smallest angle between two segments at a vertex, degrees
  double hausdorff = 0;  // measured, pixels: max over curves of the distance between each and its original
  double tolerance = 0, min_angle_bound = 0;  // the options' bounds

  Json to_json() const;
  std::string failed_guarantee() const;  // the Hausdorff bound, when hausdorff exceeds tolerance
};

// `img` must be 2D (or one slice). Labels are the pixel values; two distinct
// values make a binary image (well-composed by lib/wellcomposed's repair);
// more make a label image (repaired here, see image_pslg.cpp). Throws Error.
ImagePslgResult image_to_pslg(const LabelImage& img, const ImagePslgOptions& opt = {});

// The well-composed label image img2poly traces (ImagePslgResult::labels):
// two values go through lib/wellcomposed's repair with `seed` (foreground =
// the higher value), more through the label repair of image_pslg.cpp. A 2D
// image (or one slice); dimension 2 on return. Optional counts: two-label
// diagonal 2x2 blocks in the input, pixels changed. meshinfo repeats it to
// check a planar mesh against the image it came from.
LabelImage well_composed_labels(const LabelImage& img, std::uint64_t seed = 0, std::size_t* critical = nullptr,
                                std::size_t* changed = nullptr);

// The label image as a grey SVG background (labels spread over 40..215).
SvgBackground label_background(const LabelImage& labels);

} // namespace imgmesh
