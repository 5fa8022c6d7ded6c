// The voxel interface complex K(X) of a well-composed label image X (issue
// 36): the combinatorial object every multi-label mesh is certified against.
//
// K(X) in brief (the section doc/design.md cites)
// -----------------------------------------------
// X gives every voxel a label; beyond the grid is label 0 (the background).
// Corner (i, j, k) is where voxels i-1..i, j-1..j, k-1..k meet (voxel v spans
// [v, v+1], as VoxelBoundary in mesh/topology.hpp); corner ids run x fastest,
// z slowest, over lattice = image size + 1 per axis.
//   face      a voxel face between two voxels of different labels. Known by
//             its lowest corner and the axis it is normal to. Oriented out of
//             the higher label: (behind, front) = (higher, lower), the normal
//             pointing from behind into front. Why: label 0 (background, and
//             beyond the grid) is the lowest, so every label's surface against
//             the background points outward, and a two-label image gives
//             bdCA(X) with the orientation of voxel_boundary() and of every
//             SurfaceMesh here (counter-clockwise seen from outside).
//   patch     a component of the faces of one label pair {a, b}, faces joined
//             when they share a voxel edge. Its Euler characteristic is
//             V - E + F of its cells; its boundary edges are the voxel edges
//             where it has exactly one face, all on curves; its boundary loops
//             the components of those edges (joined at corners).
//   curve edge a voxel edge whose four voxels carry three or four labels.
//   junction  a corner with curve edges where a curve cannot pass straight
//             on: the number of curve edges at it is neither 0 nor 2, or it
//             is 2 and their label sets differ.
//   curve     a component of curve edges joined at corners that are not
//             junctions: a closed loop (no junction on it) or an arc between
//             two junctions (maybe the same one). A curve has one label set.
//   bdCA(L)   for each label L (0 included), the faces with L on one side: a
//             closed surface; its components (faces joined at edges, through
//             every patch of a pair containing L) and their Euler
//             characteristics, as mesh_topology(voxel_boundary(X = L))
//             counts them (label 0: X != 0, the same faces).
// What well-composedness (no C1, no C2 for any label's indicator, 0's
// included) guarantees, and what is counted when it fails. At an edge the
// four voxels read a a a b, a a b b (two faces of one pair: inside a patch),
// a a b c (three pairs, a face each) or a b c d (four). Three or four faces
// of one pair at an edge would need a diagonal a b a b, a C1 of a and b; a
// b a c is a C1 of a. So every edge of a patch has one or two of its faces
// (a patch is a surface along its edges, with boundary on the curves), and
// bdCA(L) has two faces at each of its edges (and is a closed 2-manifold).
// At a corner, well-composedness does not make a patch a disc: where four
// labels meet, two of them may touch along two arcs of the corner's link,
// the other two between them (the 2x2x2 block 0 0 0 1 2 0 3 3, bit k the
// voxel (k & 1, k >> 1 & 1, k >> 2 & 1), is well-composed and patch {3, 0}
// is two fans at its centre). On well-composed input such a pinch lies on
// four of the patch's boundary edges (two a fan), hence at a junction. It is
// counted (pinched_vertices: the patch's faces at the corner, joined through
// the corner's edges, fall in two classes or more) and listed (pinches); the
// Euler characteristic counts the corner once, and the two loops through it
// are one component of the boundary edges. An edge with a C1 (some label on
// a diagonal only) is counted in `critical` (its faces all joined, as the
// definition says), and so is each 2x2x2 block with a C2 of some label;
// failed_guarantee() names them.
//
// Algorithm: two scans over the corners, each reading the 2x2x2 block of
// labels around a corner; faces and curve edges are numbered in scan order
// (a face at its lowest corner), and the ids of those at the previous lattice
// plane are kept (two planes of ids: memory (nx+1)(ny+1), not a voxel's
// worth). Scan 1 numbers faces and curve edges and joins them in union-finds
// (patches; curves; the sides of faces around curve edges, for bdCA(L));
// scan 2 counts V and E of every patch and every bdCA(L) component and joins
// boundary edges into loops. Linear time; per face 12 bytes (its key and its
// patch).
//
// For the tools: summary() is the line "interface complex: N patches, M
// curves, J junctions"; to_json() the counts (faces, patches,
// boundary_loops, curves, closed_curves, junctions, c1, c2,
// pinched_vertices, pinches).
//
// 2D (a single-slice image of dimension 2): faces are pixel edges, patches
// are the components of one pair's pixel edges (arcs between junctions, or
// loops), junctions the corners where three or more labels meet; there are no
// curves (they would be points: the junctions). bdCA(L) is a set of loops
// (Euler characteristic 0 each).
#pragma once
#include "image/grid.hpp"
#include "util/json.hpp"
#include "wellcomposed/well_composed.hpp"

#include <array>
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace imgmesh {

struct InterfaceComplex {
  int dimension = 3;
  std::array<std::size_t, 3> lattice{0, 0, 0};  // corners per axis: size + 1 (2D: lattice[2] = 1)

  // Faces in key order: key = ((corner id * 3 + normal axis) << 1) | plus,
  // plus set when the normal (out of the higher label) points to +axis.
  std::vector<std::uint64_t> faces;
  std::vector<std::uint32_t> face_patch;  // per face

  struct Patch {
    std::int32_t behind = 0, front = 0;   // behind > front: the pair
    // 2D: vertices are corners, faces its pixel edges, edges 0.
    std::size_t faces = 0, vertices = 0, edges = 0;
    long long euler = 0;                  // V - E + F
    std::size_t boundary_edges = 0;       // edges with one face of it (2D: its ends, corners with one)
    std::size_t boundary_loops = 0;       // components of those (2D: 0)
    std::size_t pinched_vertices = 0;     // corners where its faces form two fans or more (2D: four edges)
    std::size_t first_face = 0;
  };
  std::vector<Patch> patches;  // in the order of their first faces

  // Curve edges in key order: key = corner id * 3 + axis (from the corner to
  // corner + e_axis). 3D only.
  std::vector<std::uint64_t> curve_edges;
  std::vector<std::uint32_t> curve_edge_curve;  // per curve edge
  struct Curve {
    std::array<std::int32_t, 4> labels{0, 0, 0, 0};  // the label set, ascending
    int label_count = 0;                              // 3 or 4
    std::size_t edges = 0, first_edge = 0;
    bool closed = false;
    std::array<std::uint64_t, 2> ends{0, 0};  // an arc's junction corners, ascending
  };
  std::vector<Curve> curves;  // in the order of their first edges
  // Patches' boundary loops (3D). Per curve edge (lowest corner q, axis a;
  // b = a + 1, c = a + 2 mod 3) 4 entries: entry i for the face between its
  // voxels i and i + 1, voxel (s, t) = q - (1 - s) e_b - (1 - t) e_c in the
  // order (0,0), (1,0), (1,1), (0,1): the loop that face's patch has there
  // when it is the patch's only face at the edge, else kNoLoop.
  static constexpr std::uint32_t kNoLoop = 0xffffffffu;
  std::vector<std::uint32_t> curve_edge_loop;
  struct Loop {
    std::uint32_t patch = 0;
    std::size_t edges = 0, first_edge = 0;  // its curve edges
  };
  std::vector<Loop> loops;  // in the order of their first curve edges
  // Junction corner ids, ascending; 2D: the corners where >= 3 labels meet.
  std::vector<std::uint64_t> junctions;
  // Corners where some patch is pinched, ascending.
  std::vector<std::uint64_t> pinches;

  struct Component {
    std::size_t faces = 0, vertices = 0, edges = 0;
    long long euler = 0;
    std::size_t first_face = 0;
  };
  struct LabelBoundary {
    std::int32_t label = 0;
    std::size_t faces = 0;
    std::vector<Component> components;  // in the order of their first faces
    CriticalCounts critical;            // C1, C2 of {X = L} (label 0: of X != 0)
  };
  std::vector<LabelBoundary> labels;  // ascending; 0 (beyond the grid) always among them

  CriticalCounts critical;  // summed over the labels

  // A corner's lattice coordinates; a face key's lowest corner, normal axis,
  // orientation; the index of the face at a corner normal to an axis
  // (faces.size() when there is none).
  std::array<std::size_t, 3> corner(std::uint64_t corner_id) const;
  static std::uint64_t face_key(std::uint64_t corner, int axis, bool plus) {
    return (corner * 3 + std::uint64_t(axis)) << 1 | std::uint64_t(plus);
  }
  static std::uint64_t face_corner(std::uint64_t key) { return (key >> 1) / 3; }
  static int face_axis(std::uint64_t key) { return int((key >> 1) % 3); }
  static bool face_plus(std::uint64_t key) { return key & 1u; }
  std::size_t find_face(std::uint64_t corner, int axis) const;
  const LabelBoundary* find_label(std::int32_t label) const;

  std::size_t closed_curves() const;
  std::size_t pinched_vertices() const;  // summed over the patches
  // "interface complex: N patches, M curves, J junctions"
  std::string summary() const;
  Json to_json() const;
  std::string failed_guarantee() const;  // when some label is not well-composed
};

// K(X) of a 2D or 3D label image. Throws Error beyond 2^32 faces or curve
// edges. The image need not be well-composed; what fails is counted.
InterfaceComplex interface_complex(const LabelImage& labels);

} // namespace imgmesh
