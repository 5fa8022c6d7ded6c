// Combinatorial topology of polygon meshes and of the voxel boundary bdCA(X)
// of a binary image: components, Euler characteristic V - E + F, genus,
// boundary loops, manifoldness and orientation. The one topology module:
// meshinfo and the mesher's certificate (thesis Thm 7.3.1: the mesh has the
// topology of bdCA(X)) both count here, and so does the 2D certificate
// (planar meshes against pixel regions, at the end; topology_planar.cpp).
// Plain data, no OpenMesh.
#pragma once
#include "image/grid.hpp"
#include "image/sample_grid.hpp"
#include "mesh/surface_io.hpp"
#include "util/json.hpp"

#include <array>
#include <cstddef>
#include <cstdint>
#include <string>
#include <utility>
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
  std::size_t first_vertex = 0;   // its smallest vertex id: a place to find it by
};

struct MeshTopology {
  std::vector<ComponentTopology> components;  // largest (by faces) first
  std::vector<int> component_of;              // per vertex: its component, -1 if in no face (empty for 2D pixel loops)
  std::size_t isolated_vertices = 0;          // in no face
  std::size_t boundary_edges = 0, nonmanifold_edges = 0, nonmanifold_vertices = 0;
  std::size_t inconsistent_edges = 0;         // shared edge traversed the same way twice
  long long euler = 0;
  std::size_t boundary_loops = 0;
  bool closed = false, manifold = false, oriented = false;
  std::vector<long long> euler_list() const;  // one per component, in order
  std::vector<long long> sorted_euler() const;  // the same, ascending
  Json to_json() const;
};

// Euler characteristics as people read them: ascending, each value once with
// how often ("-2, 0, 2 (x32)"), whatever their order.
std::string euler_summary(std::vector<long long> euler);

// Faces as corner lists (offsets has faces + 1 entries into corners). Throws
// Error on an id out of range or a face with fewer than 3 distinct corners.
MeshTopology mesh_topology(std::size_t num_vertices, const std::vector<int>& corners,
                           const std::vector<std::size_t>& offsets);
MeshTopology mesh_topology(std::size_t num_vertices, const std::vector<std::vector<int>>& faces);
MeshTopology mesh_topology(std::size_t num_vertices, const std::vector<std::array<int, 3>>& triangles);
MeshTopology mesh_topology(const SurfaceMesh& mesh);

// The voxel boundary bdCA(X) of a set of voxels X (unit squares between a
// voxel of X and one not in X or outside the grid, outward oriented) as a
// quad mesh on the lattice of voxel corners. Corner (i, j, k) is where
// voxels i-1..i, j-1..j, k-1..k meet (voxel v spans [v, v+1]); in a grid of
// samples it is the cube whose lowest sample is (i-1, j-1, k-1). Vertex ids
// follow the corners' order, z slowest. Per component c of
// t = mesh_topology(b): t.components[c].euler, and b.corner(first_vertex) a
// corner of it, to map it to other components by place.
struct VoxelBoundary {
  std::array<std::size_t, 3> lattice{0, 0, 0};  // corners per axis: image size + 1
  std::vector<std::uint64_t> lattice_ids;       // of each vertex, ascending
  std::vector<int> corners;                     // 4 per quad, counter-clockwise seen from outside
  std::vector<std::size_t> offsets;             // quads + 1 entries
  // Per vertex, the quads whose lowest corner it is (a quad is known by its
  // lowest corner and the axis it is normal to): bit a (0..2) the quad
  // normal to axis a, bit 3 + a set when its outward normal is +a. Kept when
  // the quads are dropped: the certificate measures distances and the
  // orientation of each component with them.
  std::vector<std::uint8_t> faces;
  enum : std::uint8_t { kNormalAxis = 1, kPlus = 8 };  // kNormalAxis << a, kPlus << a
  std::array<std::size_t, 3> corner(std::size_t vertex) const;
};
// X = the foreground; a single slice gives the two faces of a slab.
VoxelBoundary voxel_boundary(const BinaryImage& img);
// X = {g < 0} (the mesher's samples); X may be empty (no quad).
VoxelBoundary voxel_boundary(const SampleGrid& g);
// Components, Euler characteristics, manifoldness (false exactly when X is
// not well-composed), orientation of bdCA(X).
MeshTopology mesh_topology(const VoxelBoundary& boundary);
// The same for X = {g < 0}.
MeshTopology voxel_boundary_topology(const SampleGrid& g);

// The topology of bdCA(X), X the foreground, for a 3D image. For a 2D image,
// the pixel boundary curves: each loop is a component of Euler characteristic
// 0 (edges act as faces-free 1-cells; manifold when no lattice point has four
// boundary edges). Throws Error on an empty foreground.
MeshTopology voxel_boundary_topology(const BinaryImage& img);

// Same components, matched by count and sorted Euler characteristics.
bool same_topology(const MeshTopology& a, const MeshTopology& b);

// The topology certificate by correspondence (thesis Thm 7.3.1, component by
// component), the part of the surface certificate (surface_certificate.hpp)
// that pairs components: each mesh component is placed on the bdCA(X)
// component that every one of its vertices lies within `tolerance` of
// (world distance to the component's voxel faces); when several qualify, on
// the one whose farthest vertex is nearest, and an exact tie is a failure,
// never broken by index. A vertex within the tolerance of no component its
// predecessors lie near leaves its component unplaced. The match must be one
// to one, and each matched pair must have the same Euler characteristic.
// The mesher's vertices lie on S, in the active cubes around the boundary
// corners: within half a voxel diagonal of bdCA(X).
struct ComponentCorrespondence {
  struct MeshSide {
    int boundary = -1;            // matched bdCA(X) component, -1 when unplaced or tied
    // 3D: placed = vertices within the tolerance of `boundary`. Planar
    // (match_regions): faces, not vertices; votes: placed faces on `boundary`.
    std::size_t vertices = 0, placed = 0, votes = 0;
    long long euler = 0;
    std::int32_t label = 0;       // planar: the region label of its faces
    // 3D: the farthest vertex from `boundary` and its distance (world); when
    // unplaced, the vertex that is beyond the tolerance, `near` the bdCA(X)
    // component its predecessors lay near (-1: none within the tolerance of
    // the first); when tied, `tied` the components as near.
    double distance = -1;
    std::size_t far_vertex = 0;
    Vec3 far_point{0, 0, 0};
    int near = -1;
    std::vector<int> tied;
    // 3D: "ok", "unplaced", "tie", "matched twice", "nesting differs" (set by
    // certify_surface), "euler differs". Planar: "ok", "unplaced", "matched
    // twice", "euler differs".
    std::string verdict;
  };
  struct BoundarySide {
    long long euler = 0;
    std::int32_t label = 0;       // planar: the pixel region's label
    std::vector<int> matched_by;  // mesh components
    long long volume = 0;         // 3D: signed volume in voxels (> 0 an outer surface, < 0 a cavity's)
    std::string verdict;          // "ok", "unmatched", "matched twice"
  };
  std::vector<MeshSide> mesh;          // as MeshTopology::components (planar: as mesh_regions)
  std::vector<BoundarySide> boundary;  // as bdCA(X)'s components (planar: as PixelRegions)
  bool planar = false;                 // made by match_regions: regions of faces and of pixels
  double tolerance = 0;                // 3D: the place tolerance (world units)
  bool matches() const;                // every verdict "ok"
  Json to_json() const;
  // Each failing component and why, those with one of `verdicts` only when
  // given.
  std::string failed_guarantee(const std::vector<std::string>& verdicts = {}) const;
};
// points: the mesh's vertices in world coordinates; grid: the image's (the
// lattice of `boundary` is its voxel corners; boundary.faces is read, not its
// quads); boundary_topology = mesh_topology(boundary); tolerance > 0, world
// units.
ComponentCorrespondence match_components(const MeshTopology& mesh, const std::vector<Vec3>& points,
                                         const Geometry& grid, const VoxelBoundary& boundary,
                                         const MeshTopology& boundary_topology, double tolerance);
// The world position of a VoxelBoundary vertex (a voxel corner).
Vec3 corner_position(const Geometry& grid, const VoxelBoundary& boundary, std::size_t vertex);

// The certificate by correspondence in 2D (planar meshes against a 2D label
// image; topology_planar.cpp). What is matched are regions, not boundary
// curves: the curves bound the regions, so regions matched one to one with
// the same Euler characteristic (1 - holes) fix the curves too.
//
// A pixel region: a 4-connected component of pixels of one nonzero label
// (the foreground; 0 is background). Well-composed images (img2wc, or
// img2poly's repair, well_composed_labels) make 4- and 8-connectivity the
// same. Its Euler characteristic is V - E + F of its closed pixel squares.
struct PixelRegions {
  Geometry grid;
  std::vector<int> region_of;        // per pixel (x + size[0] * y): its region, -1 on label 0
  std::vector<std::int32_t> label;   // per region
  std::vector<long long> euler;      // per region
  std::vector<std::size_t> pixels;   // per region
};
// Regions in the order of their first pixel (x fastest). A 2D image or one slice.
PixelRegions pixel_regions(const LabelImage& labels);

// A mesh region: faces with the same nonzero label joined by edges (faces
// meeting at a vertex only are two regions, as 4-connected pixels are), with
// V - E + F over its faces.
struct MeshRegions {
  std::vector<int> region_of;        // per face, -1 for label 0
  std::vector<std::int32_t> label;   // per region
  std::vector<long long> euler;      // per region
  std::vector<std::size_t> faces;    // per region
};
// face_labels: one per face (empty: every face is label 1, the foreground
// of a 0/1 image). Throws Error on a bad face.
MeshRegions mesh_regions(std::size_t num_vertices, const std::vector<std::vector<int>>& faces,
                         const std::vector<std::int32_t>& face_labels);

// The vote and the verdicts of a correspondence whose sides are sized (their
// Euler characteristics set): votes holds (mesh component, image component)
// once per placed element; a mesh component goes to the image component with
// most votes (ties: the lower index), then one to one and equal Euler
// characteristics are checked. match_regions' and the multi-label
// certificate's (surfacenets/interface_certificate.hpp) patches'.
void tally_votes(ComponentCorrespondence& r, std::vector<std::pair<int, int>>& votes);

// Each face is placed by its centroid (world coordinates; the image's x-y
// plane): on the region of the nearest pixel centre of the face's label less
// than `reach` pixels away (index units). A mesh region goes to the pixel
// region most of its placed faces lie on (ties: the lower index); the match
// must be one to one and each pair must have the same label and Euler
// characteristic. img2poly moves a curve up to its --tolerance E off the
// pixel boundary, so a face of a right mesh lies within E of its pixel
// region, whose nearest pixel centre is then within E + sqrt(2)/2: reach
// E + 1 places every face of a right mesh.
ComponentCorrespondence match_regions(const MeshRegions& mesh, const std::vector<Vec3>& points,
                                      const std::vector<std::vector<int>>& faces, const PixelRegions& image,
                                      double reach);

} // namespace imgmesh
