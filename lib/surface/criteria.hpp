// DELMESH's refinement criteria beside TOPOLOGY, each a test on what the
// triangulation holds (DELMESH inserts the facet's surface centre when it
// fails): QUALITY(rho_0) (thesis 7.6.3), SMOOTH(g) (7.6.4) and the
// --max-distance bound. Their termination limits, min_ratio_bound() and
// min_roughness_bound(), are declared in restricted_delaunay.hpp.
#pragma once
#include "surface/cube_grid.hpp"
#include "surface/delaunay_types.hpp"

#include <utility>
#include <vector>

namespace imgmesh::surface_detail {

// Radius-edge ratio R / l_min (Def. 4.3.1); infinite for a degenerate triangle.
double ratio(const Vec3& a, const Vec3& b, const Vec3& c);

// QUALITY: a restricted facet (a, b, c) is refined when its ratio exceeds rho_0.
inline bool quality_refines(const Vec3& a, const Vec3& b, const Vec3& c, double rho0) { return ratio(a, b, c) > rho0; }

// --max-distance E: refined when its surface centre x is farther than E
// from the facet's plane.
bool distance_refines(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& x, double max_distance);
// ... and when |f| at its centroid exceeds 2E: the surface centre alone
// does not bound the triangle's distance from S where S bends across it
// (brain label 1 at the defaults: 0.63 voxel at a centroid, E = 0.3).
bool centroid_refines(const SurfaceSampler& f, const Vec3& a, const Vec3& b, const Vec3& c, double max_distance);

// SMOOTH on the oriented unit normals of the restricted facets around a
// vertex, each given with the other vertex of an edge it holds: every edge
// in exactly two facets has its normals within angle g (edges in another
// number of facets are TopoDisk's business). Sorts `normals`.
bool roughness_within(std::vector<std::pair<int, Vec3>>& normals, double g);

class Smooth {
public:
  // SMOOTH (7.6.4) at v: the roughness of every edge (v, u), the angle
  // between the oriented normals (along grad f) of its two restricted
  // facets, is at most g. Else false, and *worst is v's restricted facet
  // with the largest surface Delaunay ball.
  bool operator()(const Tr& tr, Vh v, double g, Facet* worst);
  // The same on v's restricted facets as restricted_around lists them.
  bool operator()(Vh v, const std::vector<Facet>& facets, double g, Facet* worst);

private:
  std::vector<Facet> facets_;
  std::vector<Ch> cells_;
  std::vector<std::pair<int, Vec3>> normals_;  // (other vertex of the edge, oriented unit normal)
};

} // namespace imgmesh::surface_detail
