// Planar meshes and PSLGs in Jonathan Shewchuk's Triangle formats
// (.node/.ele/.poly/.edge): '#' comments, first index 0 or 1, attributes,
// boundary markers. Quad meshes are .ele files with 4 nodes an element.
// Indices here are always 0-based; the first index of the file is remembered
// only to write the same way back.
#pragma once
#include <array>
#include <string>
#include <vector>

namespace imgmesh {

using Point2 = std::array<double, 2>;

struct PlanarMesh {
  std::vector<Point2> points;
  std::vector<std::vector<double>> point_attributes;  // empty or one vector per point
  std::vector<int> point_markers;                      // empty or one per point
  std::vector<std::vector<int>> elements;             // 3 or 4 ids each, counter-clockwise
  std::vector<std::vector<double>> element_attributes;  // empty or one vector per element (region label first)
  std::vector<std::array<int, 2>> segments;           // constraint / boundary segments
  std::vector<int> segment_markers;                    // empty or one per segment
  std::vector<Point2> holes;
  struct Region { Point2 point; double attribute = 0; double max_area = -1; };
  std::vector<Region> regions;
  int first_index = 0;  // 0 or 1, as read
};

// Readers throw Error naming the file and line on any malformed input
// (truncated, dangling id, NaN, wrong counts).
PlanarMesh read_node(const std::string& path);                 // points only
PlanarMesh read_poly(const std::string& path);                 // points (inline or from .node), segments, holes, regions
PlanarMesh read_ele(const std::string& ele_path);              // + the .node beside it
// Writers are atomic (AtomicOutput).
void write_node(const std::string& path, const PlanarMesh& m);
void write_ele(const std::string& path, const PlanarMesh& m);  // elements only (write_node for the .node)
void write_poly(const std::string& path, const PlanarMesh& m, bool with_points = true);

} // namespace imgmesh
