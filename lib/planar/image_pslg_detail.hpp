// Stages of image_to_pslg, apart so that they can be tested alone: bdCA of a
// label image, its curves, the regional points. Internal to lib/planar (and
// its tests).
#pragma once
#include "image/grid.hpp"
#include "planar/triangle_io.hpp"

#include <cstddef>
#include <cstdint>
#include <optional>
#include <utility>
#include <vector>

namespace imgmesh::planar_detail {

// bdCA of a label image: the pixel edges between two labels, as bits per
// corner (i, j) at index point (i - 0.5, j - 0.5): bit 1 the edge to
// (i + 1, j), bit 2 the edge to (i, j + 1).
struct PixelBoundary {
  std::size_t W = 0, H = 0;  // pixels; the corners are (W + 1) x (H + 1)
  std::vector<std::uint8_t> edges;

  struct Edge {
    std::size_t i, j;  // its lower corner
    std::uint8_t bit;
  };
  std::size_t at(std::size_t i, std::size_t j) const { return i + (W + 1) * j; }
  // The edge from corner (i, j) in direction d (0: +x, 1: +y, 2: -x, 3: -y),
  // if bdCA has it.
  std::optional<Edge> edge(std::size_t i, std::size_t j, int d) const;
  int degree(std::size_t i, std::size_t j) const;
  // A curve end: a junction (degree 3 or 4), or where a curve meets the
  // image rectangle.
  bool fixed(std::size_t i, std::size_t j) const;
};
PixelBoundary pixel_boundary(const LabelImage& labels);

// A curve of bdCA between two curve ends, or closed; its corners in index
// space, the labels on its two sides (a < b).
struct PixelCurve {
  std::vector<Point2> points;
  bool closed = false;
  std::pair<std::int32_t, std::int32_t> labels;
};
// From every curve end (corners in raster order) along each of its edges,
// then the closed curves that are left.
std::vector<PixelCurve> trace_curves(const PixelBoundary& bd, const LabelImage& labels);

// One regional point per 4-connected region of equal label, at its deepest
// pixel (farthest from another label and from the image's border; ties: the
// first in raster order), in world coordinates carrying the label; and that
// pixel's centre in index space.
struct RegionPoints {
  std::vector<PlanarMesh::Region> regions;
  std::vector<Point2> pixels;
};
RegionPoints region_points(const LabelImage& labels);

// The smallest angle between two segments at a vertex, degrees (180 when no
// two meet).
double smallest_segment_angle(const PlanarMesh& pslg);

} // namespace imgmesh::planar_detail
