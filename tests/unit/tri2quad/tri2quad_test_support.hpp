// Helpers shared by the tri2quad unit tests: random polygons and
// constrained Delaunay meshes, and the check of every guarantee of a result.
#pragma once
#include "tri2quad/polygons.hpp"
#include "tri2quad/tri2quad.hpp"

#include <random>
#include <vector>

namespace tri2quad_test {

using imgmesh::Tri2QuadInput;
using imgmesh::Tri2QuadResult;
using imgmesh::tri2quad_detail::P2;

constexpr double kPi = 3.14159265358979323846;

// Signed area of a polygon (positive when counter-clockwise).
double poly_area(const std::vector<P2>& v);
// A random simple (star-shaped) polygon around the origin.
std::vector<P2> random_star(std::mt19937& g, int n, double rmin, double rmax);

// Properties of a result against its input: strictly convex quads,
// conforming (each directed edge once, each interior edge in two quads),
// area, input vertices and every constraint kept as a chain of quad edges,
// and the size bounds.
void check_result(const Tri2QuadInput& in, const Tri2QuadResult& r, bool allow_outside);
// Largest excess over the size bounds check_result() has seen (must stay <= 0).
extern long small_excess_q, small_excess_s;

// A random constrained Delaunay triangulation of a star-shaped domain with
// up to four holes and interior constraint loops (regions), npoints more.
Tri2QuadInput random_cdt(std::mt19937& g, int npoints, int nholes, int nloops);

} // namespace tri2quad_test
