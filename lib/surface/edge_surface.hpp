// EdgeSurface (thesis 8.2) and the Voronoi edges VorEdge asks about: where
// the Voronoi edge (or hull ray) dual to a Delaunay facet meets S.
// A query: it reads the triangulation and f, and changes neither.
#pragma once
#include "surface/cube_grid.hpp"
#include "surface/delaunay_types.hpp"

#include <array>
#include <cstddef>
#include <cstdint>
#include <utility>
#include <vector>

namespace imgmesh::surface_detail {

struct EdgeCrossing {
  int count = 0;  // 0, 1 or 2 (two or more)
  Vec3 x{0, 0, 0};
};

// The crossings of S with segment [a, b] (a Voronoi edge): none, one, or
// two or more; x is the first crossing or, with two, the first or last
// one, whichever is farther from `site` (a vertex of the dual facet).
// `sites` (optional): the dual facet's three vertices, whose circumcentre
// is a point of the edge's line near them, for an edge whose two ends both
// lie far outside the box (walk_ends). Safe to call from several threads.
EdgeCrossing edge_surface(const SurfaceSampler& f, const Vec3& a, const Vec3& b, const Vec3& site,
                          const std::array<Vec3, 3>* sites = nullptr);
// The ends EdgeSurface walks between, [a0, b0] on the line of [a, b]
// holding all of it that lies in the box: a and b themselves unless a is
// far from the box (beyond 2^16 delta): points a + t (b - a) round to
// about 2^-53 |a| off the line, and a flat cell's circumcentre can lie
// 1e14 voxels away (anisotropic grids make such cells), which put surface
// centres 0.01 voxel off their Voronoi edge, nearer another site (issue
// 35: restricted Delaunay violations). Then b first if b is near, else
// the stretch of the line within reach of the box around the circumcentre
// of `sites` (when given). False: nothing to walk (a degenerate segment or facet, or
// a segment ending before it reaches the box).
bool walk_ends(const CubeGrid& grid, const Vec3& a, const Vec3& b, const std::array<Vec3, 3>* sites, Vec3& a0, Vec3& b0);
// Its stages on the segment a + t d, t in [0, 1]: the part inside the box
// of voxel centres, [t0, t1] (false: none), and the t in (ta, tb) where it
// crosses the planes x_i = k step[i] (Amanatides-Woo's events), sorted,
// after ta and tb.
bool clip_to_box(const CubeGrid& grid, const Vec3& a, const Vec3& d, double& t0, double& t1);
void plane_crossings(const Vec3& a, const Vec3& d, double ta, double tb, const double step[3], std::vector<double>& ts);

// The circumcentres of the cells one insertion made, each computed once
// for its four facets: a cell keeps no centre of its own (24 bytes a cell).
// Other cells' centres are computed when asked.
class CellCentres {
public:
  void assign(const Tr& tr, const std::vector<Ch>& cells);
  Vec3 operator()(const Tr& tr, Ch c) const;

private:
  // Open addressing on the cell's address, at most half full.
  std::size_t slot(const void* c) const { return (reinterpret_cast<std::uintptr_t>(c) >> 3) * 0x9E3779B97F4A7C15ull >> shift_; }
  std::vector<std::pair<const void*, Vec3>> table_;
  int shift_ = 64;
};

// EdgeSurface on the Voronoi edge dual to facet (c, i): its state
// (kComputed, kRestricted, kMulti), surface centre x_t, ball radius and
// grad f there. `computed` is left 0 for the caller to stamp.
FacetInfo edge_surface_of(const Tr& tr, const SurfaceSampler& f, Ch c, int i, const CellCentres& centres = {});

} // namespace imgmesh::surface_detail
