// The multi-label certificate (issue 39): any triangle mesh whose triangles
// each carry a label pair (behind, front), oriented out of behind (ours,
// VTK's, CGAL's: vertices anywhere, not only near lattice corners), against
// the interface complex K(X) of a well-composed label image X
// (wellcomposed/interface_complex.hpp). Its checks, in order; the verdict
// names the first that fails, with its pair or label:
//
//   interfaces     per label pair {a, b} (K(X)'s and the mesh's), the mesh's
//                  patches (its triangles of the pair, either orientation,
//                  joined along edges) against K(X)'s patches of the pair:
//                  as many; each placed on one (every triangle votes for the
//                  patch of the nearest face of the pair within the place
//                  tolerance of its centroid; most votes wins, ties the
//                  lower index: tally_votes), one to one; each with its
//                  patch's Euler characteristic, boundary loops and pinched
//                  vertices, and no edge in three of its triangles.
//                  "interface 3|1: 2 patches, K(X) has 1"
//   intersections  no two triangles of the whole mesh meet other than in a
//                  shared edge or vertex (a|b against c|d too; exact
//                  predicates, mesh/embedding.hpp soup_crossing_pairs).
//                  "intersections: ... triangle 5 (2|1) and triangle 9 (3|0)"
//   labels         per label L, the triangles with L on a side, oriented out
//                  of L, pass certify_surface against bdCA({X = L}) (closed,
//                  manifold, oriented, intersections, placed, matched,
//                  topology; mesh/surface_certificate.hpp).
//                  "label 3: topology: ..."
//   voxel sides    per label, every voxel centre next to bdCA({X = L}) on its
//                  own side of L's surface (mesh/voxel_sides.hpp; counts).
// Every check is run on what it can run on; a label's voxel sides need its
// surface closed, manifold and oriented.
//
// The lattice shortcut: on a surface-nets mesh of K(X) with every vertex
// strictly inside its voxel-corner cell (checked exactly on the mesh given:
// interface_cells.cpp), the voxel sides and each label's nesting (for
// "oriented") are what the ray tests would find, and are taken from the
// lattice; any other mesh gets the rays. The verdicts are the same.
//
// Why this order: the interfaces are combinatorial and name the patch that
// is wrong (a duplicated, dropped or split patch fails there, where every
// label around it would only say "not closed"); the whole-mesh crossings
// name both triangles and their pairs (a label's own crossings are among
// them, and a|b against c|d, which no label's surface holds); a label's
// surface then fails on orientation (a flipped triangle, a pair given the
// wrong way round), placement and topology.
//
// Label 0 (the background, and beyond the grid) is certified too, as the
// surface of the foreground X != 0 (its triangles oriented into 0, outward
// from the organs), against bdCA(X != 0), which K(X) counts as bdCA(0):
// the outer surface a user sees, whose nesting, components and topology
// (the union of the organs, its cavities) no other label's surface holds.
//
// Pinches: where a K(X) patch pinches (two fans of its faces at a junction
// corner, wellcomposed/interface_complex.hpp) K(X) counts the corner once
// in V, the two loops through it as one, and the corner as a pinched
// vertex. A mesh's pinch shows the same way: one vertex where its patch's
// triangles form two fans (mesh_topology's bow-tie, counted per patch), the
// Euler characteristic counting it once, its boundary edges joined there
// into one loop. A mesh that splits the pinch into two vertices has a patch
// of Euler characteristic one more and no pinch: refused (interfaces).
//
// Cost: linear in the mesh for the interfaces (the faces near a centroid
// are looked up in K(X)'s sorted keys); per label, its own triangles
// against a crop of the image to its voxels' box and one voxel around
// (never a full grid a label), so a map of many small labels costs what its
// boxes hold; the whole-mesh test is CGAL's box intersection (or the
// caller's local search); labels and interfaces run on `threads` threads.
#pragma once
#include "image/grid.hpp"
#include "image/io.hpp"
#include "mesh/embedding.hpp"
#include "mesh/surface_certificate.hpp"
#include "mesh/voxel_sides.hpp"
#include "util/json.hpp"
#include "wellcomposed/interface_complex.hpp"

#include <array>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

namespace imgmesh {

struct InterfaceCertificateOptions {
  // World units; 0: one voxel diagonal. Each label's (certify_surface: every
  // vertex within it of its bdCA component) and each interface triangle's
  // (its centroid within it of a face of its pair to vote).
  double place_tolerance = 0;
  std::size_t intersections_cap = 1000;  // intersecting pairs counted at most, per label and over the mesh
  // The whole mesh's crossing pairs (soup_crossing_pairs' semantics) from a
  // search the caller knows complete for its mesh: surface nets'
  // crossing_pairs on the lattice (complete because every vertex stays in
  // its cell, which it checks). Empty: CGAL's box intersection over every
  // triangle, for any mesh.
  std::function<std::vector<std::array<std::size_t, 2>>()> crossings;
  // false: the whole mesh's crossings not searched (intersections "not
  // checked": the certificate does not hold), for a caller that wants
  // failing_places, which does not read them (the conforming mesher's
  // rounds), and adds them (add_crossings) to the one certificate it keeps.
  bool check_crossings = true;
  unsigned threads = 1;  // labels and interfaces certified at once (the same certificate whatever the number)
  // Each label's nesting and voxel sides from the lattice when the mesh is
  // a surface-nets mesh of K(X) with every vertex strictly inside its cell
  // (interface_cells.cpp: why they are then known; the structure is checked
  // here); false: by rays always (the reference the tests compare with).
  bool lattice = true;
};

struct InterfaceCertificate {
  enum Check : int { kInterfaces, kIntersections, kLabels, kSides, kChecks };
  static const char* name(int check);  // "interfaces", "intersections", "labels", "voxel sides"

  // A mesh patch: the triangles of one pair joined along edges.
  struct Patch {
    std::size_t first_triangle = 0;  // its least triangle id: a name a user can find it by
    std::size_t triangles = 0, vertices = 0, edges = 0;
    long long euler = 0;
    std::size_t boundary_loops = 0;
    std::size_t pinched_vertices = 0;   // vertices where its triangles form two fans or more
    std::size_t nonmanifold_edges = 0;  // edges in three of its triangles or more
    std::size_t placed = 0;             // triangles within the place tolerance of a face of the pair
    long long complex_patch = -1;       // the K(X) patch it is placed on (InterfaceComplex::patches), -1 none
    // "ok", "unplaced", "matched twice", "not a surface", "euler differs",
    // "loops differ", "pinches differ".
    std::string verdict;
  };
  struct Interface {
    std::int32_t behind = 0, front = 0;      // as K(X): behind > front
    std::size_t triangles = 0;
    std::size_t reversed = 0;                // of those, given as (front, behind): oriented the other way
    std::vector<Patch> patches;              // the mesh's, in the order of their first triangles
    std::vector<std::size_t> complex_patches;  // K(X)'s patches of the pair, ascending
    std::string why;                         // the first failure, empty when it holds
    std::string name() const;                // "3|1"
  };
  struct Label {
    std::int32_t label = 0;
    bool in_image = true;
    std::size_t triangles = 0;
    double area = 0;                  // world units
    double volume = 0;                // enclosed (the components' signed volumes summed; 0 when not closed)
    std::size_t voxels = 0;           // of {X = L}; label 0: of X != 0
    double voxel_volume = 0;          // voxels times a voxel's volume
    SurfaceCertificate surface;       // of its triangles oriented out of it, against bdCA({X = L})
    bool sides_checked = false;
    VoxelSides sides;
  };

  std::vector<Interface> interfaces;  // by (behind, front) ascending
  std::vector<Label> labels;          // ascending
  SelfIntersections intersections;    // over the whole mesh
  std::array<int, kChecks> state{};   // 1 held, 0 failed, -1 not run
  std::array<std::string, kChecks> why;  // per failed check, naming the pair or label
  double place_tolerance = 0;
  bool on_lattice = false;  // the nesting and voxel sides came from the lattice (InterfaceCertificateOptions::lattice)

  int first_failed() const;  // kChecks when every check holds
  bool ok() const { return first_failed() == kChecks; }
  std::string failure() const;  // the first failed check's why; empty when ok
  std::string failed_guarantee() const { return failure(); }
  // "interface certificate holds: 5 labels, 7 interfaces (8 patches), 0
  // crossings, 0 of 1234 voxel centres on the wrong side", or "interface
  // certificate fails: WHY".
  std::string summary() const;
  // Where it fails, for a mesher to refine near (conforming/
  // conforming_surface.hpp), world points: of a failed interface, every
  // triangle of each stray piece (of the mesh patches placed on one K(X)
  // patch, all but the largest; one triangle of a piece over 4096 of them);
  // a triangle of each mesh patch wrong as a whole (its Euler
  // characteristic, loops or pinches differ from its K(X) patch's, or no
  // mesh patch on a K(X) patch) and, for a K(X) patch of up to 256 faces,
  // all its faces; for a larger one whose Euler characteristic or loops
  // differ, the curve edges of its boundary loops that share their nearest
  // mesh loop with another (a strip between two holes cut) or have none
  // near; of a label whose surface or voxel sides fail, the same for each
  // of its patches. points, triangles, pairs: the mesh certified; k, grid:
  // K(X) and its image's.
  std::vector<Vec3> failing_places(const std::vector<Vec3>& points, const std::vector<std::array<int, 3>>& triangles,
                                   const std::vector<std::array<std::int32_t, 2>>& pairs, const InterfaceComplex& k,
                                   const Geometry& grid) const;
  Json to_json() const;
};

// points, triangles: the mesh in the world coordinates of `image`; pairs:
// per triangle (behind, front), the triangle oriented out of behind (either
// label may be the higher). k = interface_complex(image). Throws Error on a
// 2D image, on K(X) not of `image` or counting critical configurations (not
// well-composed: certify against img2wc --labels' output), on pairs not one
// a triangle, on a triangle with an id out of range or a repeated corner,
// on a vertex of a triangle with a coordinate that is not finite, and
// beyond 2^32 triangles.
InterfaceCertificate certify_interface_mesh(const std::vector<Vec3>& points,
                                            const std::vector<std::array<int, 3>>& triangles,
                                            const std::vector<std::array<std::int32_t, 2>>& pairs,
                                            const LabelImage& image, const InterfaceComplex& k,
                                            const InterfaceCertificateOptions& options = {});
// The same on the image held narrower (image/narrow_labels.hpp): the same
// certificate.
InterfaceCertificate certify_interface_mesh(const std::vector<Vec3>& points,
                                            const std::vector<std::array<int, 3>>& triangles,
                                            const std::vector<std::array<std::int32_t, 2>>& pairs,
                                            const NarrowLabelImage& image, const InterfaceComplex& k,
                                            const InterfaceCertificateOptions& options = {});
// The whole mesh's crossings (the intersections check) added to a
// certificate made without them (check_crossings false) of this mesh: the
// certificate certify_interface_mesh with them gives.
void add_crossings(InterfaceCertificate& c, const std::vector<Vec3>& points,
                   const std::vector<std::array<int, 3>>& triangles,
                   const std::vector<std::array<std::int32_t, 2>>& pairs, const InterfaceCertificateOptions& options = {});
// The same, K(X) built here.
InterfaceCertificate certify_interface_mesh(const std::vector<Vec3>& points,
                                            const std::vector<std::array<int, 3>>& triangles,
                                            const std::vector<std::array<std::int32_t, 2>>& pairs,
                                            const LabelImage& image, const InterfaceCertificateOptions& options = {});

} // namespace imgmesh
