// HandleDetection (thesis 8.3): is S inside a Voronoi cell V(p) a disk? If
// not (a handle, or a second piece), a point of S there far from p.
// Queries on the triangulation and f; DELMESH inserts what they return.
#pragma once
#include "surface/cube_grid.hpp"
#include "surface/delaunay_types.hpp"

#include <array>
#include <cstddef>
#include <map>
#include <vector>

namespace imgmesh::surface_detail {

struct HalfSpace {  // d.x <= c
  Vec3 d;
  double c;
};

// V(p): |x - p|^2 <= |x - w|^2 for every Delaunay neighbour w (thread-safe).
void voronoi_cell(const Tr& tr, Vh p, std::vector<HalfSpace>& hs);

// The full test by marching tetrahedra, clipped to V(p): kNotDisk (a
// handle, or more than one piece) with q a point of S in V(p) far from p;
// kUndecided when V(p) is too large for the test's box or S n V(p) too small
// for its resolution. Thread-safe.
enum class HandleAnswer { kDisk, kNotDisk, kUndecided };
HandleAnswer handle_detection(const Tr& tr, const SurfaceSampler& f, Vh p, Vec3& q);

// A vertex of S n V(p) clipped by marching tetrahedra (MT): an MT vertex
// {0, i}, the point where MT edge i-j meets plane h {1, edge_key(i, j), h},
// or where planes h1 < h2 meet inside MT triangle t {2, t, h1 * H + h2}.
using ClipKey = std::array<long long, 3>;
struct ClipVertex {
  Vec3 x;
  ClipKey key;
  long long support;  // of the polygon edge to the next vertex: an MT edge key (>= 0) or -1 - plane
};
// The first `count` clipped pieces glued where their vertices' keys agree:
// vertices by key, edges by their ends, components by union-find, Euler
// characteristic V - E + F (pieces of fewer than 3 vertices are no face).
// S n V(p) is a disk iff faces > 0, components == 1 and chi == 1.
struct ClippedComplex {
  std::map<ClipKey, int> vkey;  // the vertices' ids, by key
  std::vector<Vec3> vx;         // their points
  long long faces = 0, components = 0, chi = 0;
};
void glue_pieces(const std::vector<std::vector<ClipVertex>>& polys, std::size_t count, ClippedComplex& k);

// The cheap certificate from the cube grid alone: true if S inside V(p) is
// certainly a disk (false: not settled). Thread-safe.
bool handle_free(const Tr& tr, const CubeGrid& grid, Vh p);

struct HandleChecks {
  long long full = 0;        // full tests run
  long long certified = 0;   // settled by handle_free
  long long undecided = 0;   // full tests without an answer: p's farthest surface centre went in instead
  long long unresolved = 0;  // of those, with no restricted facet at p to refine (counted, reported)
};

// TOPOLOGY's pass over `todo` (vertices whose Voronoi cell changed): the
// cheap certificate first, the full test where it does not settle; on
// `threads` threads. The points found, in `todo` order.
Candidates handle_points(const Tr& tr, const SurfaceSampler& f, const std::vector<Vh>& todo, int threads, HandleChecks& checks);

// The certificate's pass: the full test on every vertex of the S components
// in `bad`. A check costs about a thousand evaluations of f: false (nothing
// run) when that is more than kHandleBudget vertices.
constexpr std::size_t kHandleBudget = 20000;
bool handle_component_points(const Tr& tr, const SurfaceSampler& f, const std::vector<Vh>& vertices, const std::vector<int>& bad,
                             int threads, HandleChecks& checks, Candidates& pts);

} // namespace imgmesh::surface_detail
