// Helpers shared by the quadsmooth unit tests: random quad meshes (a
// jittered grid, tri2quad's outputs), areas and mu of a mesh, and the state
// of a QuadMesh, to check that a refused operation changed nothing.
#pragma once
#include "planar/triangle_io.hpp"
#include "quadsmooth/smooth_mesh.hpp"

#include <cstddef>
#include <set>
#include <utility>
#include <vector>

namespace quadsmooth_test {

using imgmesh::PlanarMesh;
using imgmesh::Point2;
using imgmesh::quadsmooth_detail::QuadMesh;

// An n x n grid of [0,1]^2 with every interior node thrown up to 0.3 cells
// away (all quads stay convex).
PlanarMesh jittered_grid(int n, unsigned seed);
// tri2quad's output for a random triangle mesh: an n x n jittered grid of
// [0,1]^2 cut along random diagonals, region 1 left of x = 1/2 and region 2
// right of it (that column straight, and a constraint), boundary marker 1,
// constraint marker 2. Points carry 1 + their index as attribute.
PlanarMesh tri2quad_mesh(int n, unsigned seed);

// The area of the quads whose attribute is region.
double region_area(const PlanarMesh& m, double region);
double total_area(const PlanarMesh& m);
// Joe's mu of the quad e of m.
double quad_mu(const PlanarMesh& m, const std::vector<int>& e);
// Undirected edges used by exactly one element.
std::set<std::pair<int, int>> boundary_edges(const PlanarMesh& m);

// Everything an operation may change, to check that a refused one changed
// nothing.
struct State {
  std::vector<imgmesh::quadsmooth_detail::Quad> quads;
  std::vector<std::vector<int>> stars;
  std::vector<Point2> points;
  std::vector<double> sines;
  std::vector<char> quad_dead, vertex_dead;
  std::size_t elements;
};
State snapshot(const QuadMesh& qm);
void check_same(const State& a, const State& b);

bool live_quads_strictly_convex(const QuadMesh& qm);

} // namespace quadsmooth_test
