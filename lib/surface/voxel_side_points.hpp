// VoxelSides (issue 38): the voxel centres next to S whose Delaunay cell
// lies on the other side of S, and the points of S that refine them. Once
// no Voronoi edge meets S twice (VorEdge has nothing left),
// the restricted facets are exactly the facets between a cell whose
// circumcentre f calls inside and one it calls outside (EdgeSurface sees
// every sign change of f along a Voronoi edge, and a Voronoi edge with one
// crossing joins circumcentres of opposite signs), an infinite cell or a
// circumcentre beyond the grid's box being outside: a point lies inside the
// mesh exactly when its cell's circumcentre does (doc/implicit2mesh.md 4.9).
// A query: it reads the triangulation and f, and changes neither.
#pragma once
#include "surface/cube_grid.hpp"
#include "surface/delaunay_types.hpp"

#include <cstdint>
#include <vector>

namespace imgmesh::surface_detail {

class VoxelSidePoints {
public:
  // near_starts: a centre's walk starts from a vertex of the cell it was
  // last found in (false, for tests: always from the last centre's cell;
  // the same answers, in more steps).
  explicit VoxelSidePoints(bool near_starts = true) : near_starts_(near_starts) {}

  // Every corner of an active cube (a voxel centre within a voxel of S;
  // f = g there, of the voxel's sign) whose Delaunay cell lies on the
  // other side of S (a centre on a facet, edge or vertex: any of the cells
  // holding it), in grid order: the point of S on the segment from the
  // centre to that cell's circumcentre (an infinite cell: to beyond the
  // box, away from its hull facet), with its clearance (squared distance to
  // W), unless that is under guard^2 (counted in `refused`). `wrong`: the
  // centres found on the wrong side. A centre found on its side is not
  // looked at again while its cell stands.
  Candidates operator()(const Tr& tr, const SurfaceSampler& f, const std::vector<Vh>& by_id, Vh near, double guard,
                        long long& wrong, long long& refused);

  // The per-centre memory let go (the surface mesher's certificate, at its
  // peak; a vertex removal, after which a cell's largest id no longer tells
  // it from the cells made later at its address): the next call looks at
  // every centre again.
  void release() {
    std::vector<std::uint8_t>().swap(corners_);
    std::vector<Ch>().swap(cell_);
    std::vector<std::uint32_t>().swap(top_);
  }

private:
  // Per centre (grid order, found once: a walk over the active cubes took
  // 7% of the bunny's instructions a run), 12 bytes in two arrays: the cell
  // it was last found right in (a cell's memory is reused), and the largest
  // vertex id of the cell it was last found in, + 1: where its next walk
  // starts (`by_id` is null where a vertex was deleted), and what tells that
  // cell from a later one at its address. Every cell made since holds the
  // vertex whose insertion made it, of an id larger than any before (W
  // only grows between passes: vertex removal releases this memory), so
  // that cell stands exactly when its address holds a cell of that largest
  // id (a hash of the four ids, in 8 bytes more a centre, told it nearly
  // always). Per active cube (sorted): the corners it visits, bit e for
  // corner e.
  std::vector<std::uint8_t> corners_;
  std::vector<Ch> cell_;
  std::vector<std::uint32_t> top_;
  bool near_starts_;
};

} // namespace imgmesh::surface_detail
