// Planar meshes in and out by file extension (doc/design.md "Data contracts"):
// Triangle's .ele/.node/.poly, OFF (z = 0), legacy VTK (binary unless
// PlanarWriteOptions::ascii), Gmsh 2.2 and SVG.
#pragma once
#include "planar/triangle_io.hpp"

#include <array>
#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

namespace imgmesh {

// A grey raster drawn under an SVG picture: pixel (c, r)'s centre sits at
// world (x, y) = origin + c * column + r * row.
struct SvgBackground {
  std::size_t width = 0, height = 0;
  std::vector<std::uint8_t> grey;  // width * height, row r = c + width * r
  std::vector<std::uint8_t> rgb;   // or 3 * width * height: a colour raster (used when set)
  Point2 origin{0, 0}, column{1, 0}, row{0, 1};
};

struct PlanarWriteOptions {
  // Legacy .vtk as text; else binary (big-endian, as the format requires).
  bool ascii = false;
  // Optional per-element scalar (one per element): VTK cell data and the SVG
  // fill colour (a blue-to-yellow map over its range). Without it the SVG
  // colours elements by their region attribute.
  std::vector<double> element_scalar;
  std::string scalar_name = "quality";
  // The colour scale's ends (e.g. 0 and 1 for Joe's mu, so that pictures
  // compare); NaN: the scalar's range.
  double scalar_min = std::nan(""), scalar_max = std::nan("");
  // SVG only.
  const SvgBackground* background = nullptr;
  double svg_width_px = 1000;  // picture width; the height follows the aspect ratio
  std::string svg_title;       // the title line; empty: svg_counts(m)
  bool svg_frame_foreground = true;  // frame the foreground (nonzero regions, curves); false: the whole picture
};

// The SVG tint of a region label (0: background grey); img2poly's raster
// uses the same.
std::array<std::uint8_t, 3> region_tint(long label);
// "V vertices, T triangles, Q quads, S segments[, P regional points], L labels".
std::string svg_counts(const PlanarMesh& m);
// The SVG picture alone (write_planar_mesh chooses it for .svg).
void write_svg(const std::string& path, const PlanarMesh& m, const PlanarWriteOptions& opt);

// By extension: .ele (+ .node beside it, + .poly with the segments when there
// are any), .off, .vtk, .msh, .svg. Every file is written atomically.
// Throws Error on an unknown extension.
void write_planar_mesh(const std::string& path, const PlanarMesh& m, const PlanarWriteOptions& opt = {});

// .ele (with its .node, and the .poly beside it for segments if it exists)
// or .off (z ignored; faces of 3 or 4 vertices); "-" reads OFF from standard
// input. Throws Error.
PlanarMesh read_planar_mesh(const std::string& path);

// The segments of `poly` (a .poly read from poly_path) as ids of m's
// vertices: the same ids when the .poly has no vertices of its own or the
// same ones, else matched by position. Their markers go to *markers (empty
// when the .poly has none). Throws Error on an id out of range or a vertex
// that is not one of m's.
std::vector<std::array<int, 2>> segments_on_mesh(const PlanarMesh& poly, const PlanarMesh& m,
                                                 const std::string& poly_path, std::vector<int>* markers);

// A planar straight-line graph: .poly, or an OFF of polygons (every polygon
// edge a segment, marker 1). Throws Error.
PlanarMesh read_pslg(const std::string& path);

} // namespace imgmesh
