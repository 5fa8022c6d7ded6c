// Seeds (thesis 8.1): the first points of W, on every component of S,
// from the cube grid alone (no critical points needed). A query: it returns
// the points; DELMESH inserts them.
#pragma once
#include "surface/cube_grid.hpp"

#include <cstdint>
#include <utility>
#include <vector>

namespace imgmesh::surface_detail {

class Seeds {
public:
  explicit Seeds(const SurfaceSampler& f);
  // Crossings of mixed cube edges in every component's extremal cubes along
  // +-x, +-y, +-z (at least two per component), each once, in insertion
  // order (shuffled by `seed`).
  std::vector<Vec3> points(std::uint64_t seed) const;
  // Degenerate seed sets (a single voxel, a one-voxel rod): the crossing of
  // the next other mixed edge, false when none is left. DELMESH takes them
  // until its triangulation is 3D.
  bool next_extra(Vec3& x);
  // The crossing on the `which`-th mixed edge of cube (x, y, z): unique, f
  // monotone along the edge (F2). False if the cube has fewer mixed edges.
  bool crossing(long x, long y, long z, Vec3& out, int which = 0) const;

private:
  const SurfaceSampler& f_;
  const CubeGrid& grid_;
  const std::vector<ActiveCube>& cubes_;  // active cubes in key order
  std::size_t next_cube_ = 0;
  int next_edge_ = 0;
};

} // namespace imgmesh::surface_detail
