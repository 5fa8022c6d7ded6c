// EdgeSurface (thesis 8.2) and the Voronoi edges VorEdge asks about: where
// the Voronoi edge (or hull ray) dual to a Delaunay facet meets S.
// A query: it reads the triangulation and f, and changes neither.
#pragma once
#include "surface/cube_grid.hpp"
#include "surface/delaunay_types.hpp"

namespace imgmesh::surface_detail {

struct EdgeCrossing {
  int count = 0;  // 0, 1 or 2 (two or more)
  Vec3 x{0, 0, 0};
};

// The crossings of S with segment [a, b] (a Voronoi edge): none, one, or
// two or more; x is the first crossing or, with two, the first or last
// one, whichever is farther from `site` (a vertex of the dual facet).
// Safe to call from several threads.
EdgeCrossing edge_surface(const SurfaceSampler& f, const Vec3& a, const Vec3& b, const Vec3& site);

// EdgeSurface on the Voronoi edge dual to facet (c, i): its state
// (kComputed, kRestricted, kMulti), surface centre x_t, ball radius and
// grad f there. `computed` is left 0 for the caller to stamp.
FacetInfo edge_surface_of(const Tr& tr, const SurfaceSampler& f, Ch c, int i);

} // namespace imgmesh::surface_detail
