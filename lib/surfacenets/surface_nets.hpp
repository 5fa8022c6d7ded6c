// Surface nets on the interface complex K(X) of a well-composed label image
// (issue 39; ../shared/notes/multilabel.md "Fast"). One vertex per voxel
// corner that K(X)'s faces touch, one quad per face of K(X), split into two
// triangles; every triangle carries the face's (behind, front) labels and is
// oriented from behind into front (right-hand rule in world coordinates), so
// that, as in K(X), behind is the higher label and every label's surface
// against the background points outward.
//
// Why it is right by construction: the combinatorics are K(X)'s, and on a
// well-composed partition the faces with L on one side are bdCA({X = L}), a
// closed 2-manifold with L's topology. Splitting each quad adds one edge and
// one face, so Euler characteristics and components are kept; the two
// diagonal corners of a voxel face are shared by no other face, so no edge
// is created twice. Before smoothing the mesh IS bdCA(L) per label, each
// vertex at its corner's world position. Smoothing (smoothing.cpp) moves
// vertices inside their cells only and never changes the quads (only
// which diagonal splits each: either way a disc, the topology kept).
//
// Vertex kinds, for smoothing: a junction of K(X) (where curves meet, and
// every corner where a patch pinches) never moves; a corner on a curve
// (voxel edges where three or more labels meet) moves only toward its two
// curve neighbours; any other corner toward its neighbours along face edges.
#pragma once
#include "image/grid.hpp"
#include "wellcomposed/interface_complex.hpp"

#include <array>
#include <cstddef>
#include <cstdint>
#include <vector>

namespace imgmesh {

struct InterfaceMesh {
  Geometry grid;  // the label image's (data not kept)
  std::array<std::size_t, 3> lattice{0, 0, 0};
  std::vector<std::uint64_t> corners;  // per vertex its lattice corner id, ascending
  std::vector<Vec3> points;            // per vertex, world coordinates
  enum Kind : std::uint8_t { kSurface = 0, kCurve = 1, kJunction = 2 };
  std::vector<std::uint8_t> kind;      // per vertex
  // The vertices a vertex is relaxed toward (CSR, offsets has vertices + 1
  // entries): a surface vertex's face-edge neighbours, a curve vertex's two
  // curve neighbours, none for a junction.
  std::vector<std::size_t> neighbour_offsets;
  std::vector<int> neighbours;

  std::vector<std::array<int, 4>> quads;  // per K(X) face (same order), oriented from behind into front
  std::vector<std::array<std::int32_t, 2>> labels;  // per quad: (behind, front), behind > front
  // Triangles 2f and 2f + 1 split quad f (split_quads), oriented as it.
  std::vector<std::array<int, 3>> triangles;

  // The lattice coordinates of a vertex's corner. Its cell is the cube of
  // the 8 voxel centres around it: continuous index c - 1 .. c per axis (the
  // corner itself at c - 0.5).
  std::array<std::size_t, 3> corner(std::size_t vertex) const;
  std::array<std::int32_t, 2> triangle_labels(std::size_t t) const { return labels[t / 2]; }
};

// Per vertex, its corner's world position (the unsmoothed mesh's points,
// where the untangling moves vertices back to).
std::vector<Vec3> corner_points(const InterfaceMesh& mesh);

// The unsmoothed mesh of K(X) (k = interface_complex(image)); the image is
// read for its geometry only. Throws Error when K(X) counts critical
// configurations (the partition is not well-composed: some label's faces
// would not form a 2-manifold) or beyond 2^31 vertices.
InterfaceMesh interface_mesh(const Geometry& image, const InterfaceComplex& k);

// (Re)split every quad along the diagonal whose two triangles have the
// better worst quality (4 sqrt(3) area / sum of squared edges, 1 for an
// equilateral triangle), in world coordinates; on a tie (a planar
// rectangle, before smoothing) the diagonal from its first corner.
void split_quads(InterfaceMesh& mesh);

// The closed surface of one label: the triangles with `label` on a side,
// oriented out of it (those with it in front are reversed). face_of, when
// given, receives each triangle's index in mesh.triangles.
std::vector<std::array<int, 3>> label_triangles(const InterfaceMesh& mesh, std::int32_t label,
                                                std::vector<std::size_t>* face_of = nullptr);

struct SmoothingOptions {
  int rounds = 5;        // Jacobi rounds of relaxation toward the neighbours' mean
  double margin = 0.1;   // in voxels: each vertex kept this far inside its cell (0 <= margin < 0.5)
  bool untangle = true;  // then untangle_interface_mesh (false: tests only, to see the folds)
  unsigned threads = 1;  // for the untangling's crossing search
};
// Constrained smoothing (Frisken 2022): every round moves each surface and
// curve vertex to the mean of its neighbours (positions of the previous
// round), clamped into its cell shrunk by the margin; junctions stay. The
// quads are then split again and the mesh untangled toward its corners'
// positions (corner_points): on return, with
// options.untangle, no two triangles cross and none is degenerate
// (crossing_pairs(mesh) is empty; untangle_interface_mesh). Throws Error
// on a margin outside [0, 0.5).
void smooth_interface_mesh(InterfaceMesh& mesh, const SmoothingOptions& options = {});

// The pairs of triangles of the mesh, whatever their labels, that meet
// other than in a shared edge or vertex (lib/mesh's triangles_cross, exact
// predicates; (t, t) for a degenerate triangle), each pair ascending,
// sorted. Local: each quad is tested against the quads of neighbouring
// cells only (crossings.cpp says why that finds every pair), by `threads`
// threads (the same pairs whatever their number). Throws Error when a
// vertex lies outside its cell.
std::vector<std::array<std::size_t, 2>> crossing_pairs(const InterfaceMesh& mesh, unsigned threads = 1);

// While two triangles cross (crossing_pairs), their vertices go back halfway
// to `rest` (the unsmoothed positions), onto it after a few halvings, and
// their quads are split again; after the first search only the quads at a
// moved vertex are tested again (by `threads` threads: the same result
// whatever their number). Returns the vertex moves made, once its last
// search found no pair: crossing_pairs(mesh) is then empty (untangle.cpp
// says why the searches after the first, of the moved quads only, leave
// no pair unseen).
std::size_t untangle_interface_mesh(InterfaceMesh& mesh, const std::vector<Vec3>& rest, unsigned threads = 1);

} // namespace imgmesh
