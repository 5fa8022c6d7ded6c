// What the multi-label certificate's files share (interface_certificate.cpp:
// the driver, labels, intersections, sides; interface_patches.cpp: the
// interfaces; interface_cells.cpp: the lattice shortcut). Internal to
// lib/surfacenets.
#pragma once
#include "surfacenets/interface_certificate.hpp"

#include <array>
#include <cstdint>
#include <functional>
#include <limits>
#include <string>
#include <vector>

namespace imgmesh::surfacenets_detail {

// work(i, w) for every i in [0, n), taken in turn by `threads` threads (w:
// which one, 0 the caller); each result in i's slot makes the outcome the
// same whatever their number. The first exception thrown is rethrown once
// all have stopped.
void for_each_index(std::size_t n, unsigned threads, const std::function<void(std::size_t, unsigned)>& work);

// The interfaces check: every pair of K(X) and of the mesh, each with its
// patches matched to K(X)'s and `why` set when it fails, the pairs taken
// by `threads` threads (the same whatever their number). tolerance > 0,
// world units.
// The triangles of the mesh patches of interface behind|front as the
// interfaces check joins them (along edges): entry p is patch p of its
// Interface (the order of their first triangles).
std::vector<std::vector<std::uint32_t>> interface_patch_triangles(const std::vector<std::array<int, 3>>& triangles,
                                                                  const std::vector<std::array<std::int32_t, 2>>& pairs,
                                                                  std::int32_t behind, std::int32_t front);

std::vector<InterfaceCertificate::Interface> certify_interfaces(const std::vector<Vec3>& points,
                                                                const std::vector<std::array<int, 3>>& triangles,
                                                                const std::vector<std::array<std::int32_t, 2>>& pairs,
                                                                const Geometry& grid, const InterfaceComplex& k,
                                                                double tolerance, unsigned threads);

// Whether the mesh is a surface-nets mesh of K(X) with every vertex
// strictly inside its voxel-corner cell (interface_cells.cpp: what that
// structure is, and why it decides the voxel sides and the nesting).
struct NetCells {
  static constexpr std::uint64_t kNoCorner = std::numeric_limits<std::uint64_t>::max();
  bool holds = false;
  std::string why;   // the first thing found that is not so, when it does not hold
  double slack = 0;  // voxels: how far inside its cell a vertex was asked to be
};
NetCells net_cells(const std::vector<Vec3>& points, const std::vector<std::array<int, 3>>& triangles,
                   const std::vector<std::array<std::int32_t, 2>>& pairs, const Geometry& grid,
                   const InterfaceComplex& k);
// The corner (K(X)'s lattice id) whose cell holds p `slack` voxels inside
// at least, or kNoCorner.
std::uint64_t net_corner(const Vec3& p, const Geometry& grid, const std::array<std::size_t, 3>& lattice, double slack);
// On a mesh where net_cells holds, per component of one label's surface
// (its topology `surface`, its points), how many of the others enclose it:
// what SurfaceGeometry::nesting_depths' rays find, from the faces of the
// crop's bdCA (vb, bt = mesh_topology(vb); crop_lo: the crop's first voxel
// in the image). Empty when a component's vertex is not where it should be.
std::vector<int> net_depths(const MeshTopology& surface, const std::vector<Vec3>& points, const Geometry& grid,
                            const std::array<std::size_t, 3>& lattice, double slack,
                            const std::array<std::size_t, 3>& crop_lo, const VoxelBoundary& vb, const MeshTopology& bt);

} // namespace imgmesh::surfacenets_detail
