// A stage of write_svg, apart so that it can be tested alone. Internal to
// lib/planar (and its tests).
#pragma once
#include "planar/planar_formats.hpp"

#include <array>

namespace imgmesh::planar_detail {

// The world box an SVG picture shows, {x0, y0, x1, y1}: the points and the
// background's pixels, or with opt.svg_frame_foreground the foreground (the
// elements of nonzero regions, the segments of markers other than 1) with a
// margin of a tenth of its size (at least 2% of the whole) within them.
std::array<double, 4> svg_frame(const PlanarMesh& m, const PlanarWriteOptions& opt);

} // namespace imgmesh::planar_detail
