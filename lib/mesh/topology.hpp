// Combinatorial topology of polygon meshes and of the voxel boundary bdCA(X)
// of a binary image: components, Euler characteristic V - E + F, genus,
// boundary loops, manifoldness and orientation. Plain data, no OpenMesh.
#pragma once
#include "image/grid.hpp"
#include "util/json.hpp"

#include <cstddef>
#include <vector>

namespace imgmesh {

struct ComponentTopology {
  std::size_t vertices = 0, edges = 0, faces = 0;
  long long euler = 0;            // V - E + F
  std::size_t boundary_loops = 0;
  bool closed = false;            // no boundary edge
  bool manifold = false;          // every edge in <= 2 faces, every vertex a single fan
  bool oriented = false;          // neighbouring faces traverse shared edges oppositely
  bool orientable = false;        // could be oriented (faces flipped)
  // Orientable manifold: (2 - euler - boundary_loops) / 2; non-orientable
  // manifold: 2 - euler - boundary_loops (cross-caps); -1 otherwise.
  long long genus = -1;
};

struct MeshTopology {
  std::vector<ComponentTopology> components;  // largest (by faces) first
  std::size_t isolated_vertices = 0;          // in no face
  std::size_t boundary_edges = 0, nonmanifold_edges = 0, nonmanifold_vertices = 0;
  std::size_t inconsistent_edges = 0;         // shared edge traversed the same way twice
  long long euler = 0;
  std::size_t boundary_loops = 0;
  bool closed = false, manifold = false, oriented = false;
  std::vector<long long> euler_list() const;  // one per component, in order
  Json to_json() const;
};

// Faces as corner lists (offsets has faces + 1 entries into corners). Throws
// Error on an id out of range or a face with fewer than 3 distinct corners.
MeshTopology mesh_topology(std::size_t num_vertices, const std::vector<int>& corners,
                           const std::vector<std::size_t>& offsets);
MeshTopology mesh_topology(std::size_t num_vertices, const std::vector<std::vector<int>>& faces);

// The voxel boundary of the foreground of a 3D image (unit squares between a
// foreground voxel and a background or outside one, outward oriented), as a
// quad mesh on the lattice of voxel corners; its topology is that of bdCA(X).
// For a 2D image, the pixel boundary curves: each loop is a component of
// Euler characteristic 0 (edges act as faces-free 1-cells; manifold when no
// lattice point has four boundary edges). Throws Error on an empty foreground.
MeshTopology voxel_boundary_topology(const BinaryImage& img);

// Same components, matched by count and sorted Euler characteristics.
bool same_topology(const MeshTopology& a, const MeshTopology& b);

} // namespace imgmesh
