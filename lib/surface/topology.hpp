// Topology of the two sides that must agree (thesis Thm 7.3.1 + ch. 6):
// the voxel boundary bdCA(X) of the well-composed image X = {g < 0}, and the
// output triangle mesh, as the mesher reads them. Computed by lib/mesh
// (mesh/topology.hpp, mesh/triangle_quality.hpp); this header goes when the
// mesher uses those directly.
#pragma once
#include "image/grid.hpp"
#include "mesh/surface_io.hpp"

#include <vector>

namespace imgmesh {

// Euler characteristic of every component of a closed surface, sorted
// (ascending) so two surfaces can be compared component-wise.
struct SurfaceTopology {
  std::vector<int> euler;  // one per component, ascending
  bool manifold = true;    // every edge in exactly two faces, every vertex a disk
  bool oriented = true;    // neighbouring faces agree (meshes only)
  int components() const { return int(euler.size()); }
  bool same_as(const SurfaceTopology& o) const { return euler == o.euler; }
};

// bdCA(X) for X = {voxels with samples < 0} (voxels outside the grid are
// background): quads between a voxel of X and one not in X. manifold is false
// when X is not well-composed (an edge in four quads, or a vertex where two
// fans of quads meet).
SurfaceTopology voxel_boundary_topology(const FloatImage& samples);

// Components, Euler characteristic, manifoldness and orientation of a
// triangle mesh.
SurfaceTopology mesh_topology(const SurfaceMesh& mesh);

// Smallest angle (radians) and largest radius-edge ratio R / l_min of a mesh
// (0 and infinity when a triangle is degenerate).
struct TriangleQuality {
  double min_angle = 0, max_ratio = 0;
};
TriangleQuality triangle_quality(const SurfaceMesh& mesh);

} // namespace imgmesh
