// Stages of triangulate_pslg that need no CGAL, apart so that they can be
// tested alone: the lattices of Steiner points (lattice.cpp) and the input's
// small angles (triangulate.cpp). Internal to lib/planar (and its tests).
#pragma once
#include "planar/triangle_io.hpp"

#include <array>
#include <cstddef>
#include <functional>
#include <utility>
#include <vector>

namespace imgmesh::planar_detail {

// The bounding box of the input points: {x0, y0, x1, y1}.
std::array<double, 4> bounding_box(const PlanarMesh& in);

// The point of segment ab nearest to p, and its distance.
Point2 closest_on_segment(const Point2& p, const Point2& a, const Point2& b);
double distance_to_segment(const Point2& p, const Point2& a, const Point2& b);

// Whether a lattice point lies in the domain (a triangle of the constrained
// triangulation not in a hole); asked once per candidate, in order.
using InDomain = std::function<bool(const Point2&)>;

// The points of an equilateral-triangle lattice of side h (rows along x, from
// the corner of the input's bounding box) in the domain and at least h/2 from
// every input segment and vertex. Throws UsageError past `limit` points.
std::vector<Point2> equilateral_lattice(const PlanarMesh& in, double h, std::size_t limit, const InDomain& in_domain);

// The nodes of the square lattice of side h in the domain, graded by a size
// field (the options of the same names in TriangulateOptions; lattice.cpp
// says how). Throws UsageError past `limit` points.
std::vector<Point2> square_lattice(const PlanarMesh& in, double h, double grading, double max_side, bool narrow,
                                   std::size_t limit, const InDomain& in_domain);

// The angles between input segments at each vertex. Below 60 degrees the
// mesher protects the corner with clusters and cannot promise the bound in
// the disc around the apex whose radius is the shorter of the two segments.
struct InputAngles {
  double smallest = 180;          // degrees, between segments at a vertex
  std::size_t small_vertices = 0;  // vertices with an angle below 60 degrees
  // Per angle below 60 degrees: its apex (input vertex) and the disc's radius.
  std::vector<std::pair<std::size_t, double>> apexes;
};
InputAngles input_angles(const PlanarMesh& in);

} // namespace imgmesh::planar_detail
