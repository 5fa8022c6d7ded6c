// Post-processing of strictly convex quad meshes (thesis 3.2.3): angle-based
// smoothing (Zhou and Shimada, 2000) with a guard, and topological clean-up
// (Canann, Muthukrishnan and Phillips, 1998): diagonal swaps (for the worst
// mu, and valence-driven), pair splits around a new point, doublet removal
// and quad collapse. Nothing ever makes a quad non-convex: every move and
// every operation is checked with exact orientation predicates first.
//
// smooth_quad_mesh(mesh, opt), in the files of lib/quadsmooth that do each step
// (the state and the operations are declared in smooth_mesh.hpp):
//
//   check the input, build the stars                    smooth_mesh.cpp
//   QuadMesh: quads, stars, fixed and sliding vertices,
//     feature edges, sin(mu) of every quad              smooth_mesh.cpp
//   for pass = 0 .. iterations-1:
//     if cleanup and pass > 0 and pass % 3 == 0:
//       for each quad q1 not plain, each edge (u, w) of q1:
//         swap the diagonal of the pair across (u, w)
//         for a better worst mu, else split a poor
//         pair into 3 or 4 quads, else swap for more
//         regular valences (relaxed, undone if worse)  smooth_swap.cpp,
//                                                       smooth_split.cpp
//       for each quad, each diagonal: collapse a
//         squashed quad or two facing valence-3
//         vertices (undone if worse)                    smooth_collapse.cpp
//       for each free vertex of valence 2: remove the
//         doublet (merge its two quads); of valence 3
//         splitting a sharp fixed corner: its three
//         quads become two (undone if not better)       smooth_doublet.cpp
//       for each poor quad with two flat free corners:
//         move them together (compass search)          smooth_angle.cpp
//       colour again if the topology changed
//     for each colour class (on the threads), each
//       active vertex: move it to its angle-based
//       position if no quad around gets non-convex or
//       below the worst mu around; from the second
//       pass, also climb on the worst mu (compass)      smooth_angle.cpp
//     with slide_boundary: slide vertices along their
//       straight segment, same guard                    smooth_angle.cpp
//   if cleanup: swaps, then doublets, once more          smooth_swap.cpp,
//                                                       smooth_doublet.cpp
//   if cleanup: sharp corners split by a valence-3
//     vertex, also by joining it to the hexagon's other
//     corners, else by the split whose quads are not yet
//     convex, its doublets merged and its corners placed
//     (after the passes: the clean-up's course stays as
//     it was)                                            smooth_doublet.cpp
//   if cleanup: each quad under 12 degrees collapsed
//     along a diagonal, the doublet it leaves merged,
//     its patch placed, relaxed and climbed              smooth_doublet.cpp
//   if cleanup: pair splits once more on each quad
//     under 10 degrees                                   smooth_split.cpp
//   if cleanup: each sharp corner held by two or three
//     quads where it wants one, one under 12 degrees:
//     the quads around re-quadded around new points
//     (a fan, a chain: the strip along a wedge's two
//     sides, a ring), placed, relaxed and climbed,
//     the best taken if the sorted mu rose             smooth_tip.cpp
//   4 times: each free vertex next to a quad under 12
//     degrees climbs on the two worst mu around it
//     (max-min)                                          smooth_angle.cpp
//   mean_rounds times: each free vertex next to a quad
//     under 40 degrees climbs on the sum of sin(mu)
//     around it, the worst mu around never lowered       smooth_angle.cpp
//   if cleanup and grading: pairs of neighbouring quads
//     whose sizes differ by over `grading`: their free
//     corners climb on the ratio, else the smaller quad
//     collapses or the larger splits with a neighbour,
//     no quad going under 10 degrees (4 rounds)          smooth_grade.cpp
//     then half the mean rounds again, no size ratio
//     around a vertex raised past `grading`              smooth_angle.cpp
//   compact removed vertices and quads into mesh        smooth_mesh.cpp
#pragma once
#include "planar/triangle_io.hpp"
#include "quad/quality.hpp"
#include "util/json.hpp"

#include <cstddef>
#include <functional>
#include <string>

namespace imgmesh {

struct SmoothOptions {
  int iterations = 10;          // smoothing passes
  bool cleanup = true;          // swaps, doublets, collapses
  bool slide_boundary = false;  // boundary/constrained vertices may slide along their own straight segment
  int threads = 1;              // smoothing threads; the result does not depend on it
  // Pair splits are tried on quads with mu below this (degrees): higher
  // values give better angles and more quads. 25: 1.07-1.09 times the
  // quads of 15 on the bundled images' default chain, for 0.1-0.7 degrees
  // more mean mu (the bar of 30), at about twice the time.
  double split_below = 25;
  // Beyond the thesis: rounds of a pass that raises the mean mu vertex by
  // vertex (a compass search on the sum of sin(mu) around each, the worst
  // mu around never lowered), after the smoothing passes; 0: none. 6
  // rather than 3: 0.15 degrees more mean mu on the brain slice and a
  // random blob's default chain, for 13% more quadsmooth CPU.
  int mean_rounds = 6;
  // Beyond the thesis: the neighbour size ratio (larger over smaller
  // quad, sizes the square roots of the areas) the grading pass brings the
  // pairs above it down to, where it can without a quad under 10 degrees;
  // 0: no pass. sqrt(6): a triangle's three quads beside two triangles of
  // its size paired into one, which tri2quad makes in every mesh (a lower
  // aim fights the conversion everywhere).
  double grading = 2.449489742783178;
  // Called after each pass with (pass, passes) for progress reports; may be empty.
  std::function<void(int, int)> progress;
};

struct SmoothStats {
  QualityReport before, after;
  std::size_t moves = 0;       // accepted vertex moves (interior)
  std::size_t slides = 0;      // accepted boundary slides
  std::size_t rejected = 0;    // moves the guard refused
  std::size_t optimized = 0;   // guarded climbs on the worst mu around a vertex
  std::size_t edge_moves = 0;  // guarded climbs moving both free, flat ends of an edge of a poor quad
  std::size_t mean_climbs = 0; // vertices the mean pass moved
  std::size_t worst_climbs = 0; // vertices the max-min pass moved
  std::size_t swaps = 0, doublets = 0, collapses = 0;
  std::size_t sharp_corners = 0;      // valence-3 vertices removed to leave a sharp corner one quad
  std::size_t wedge_tips = 0;         // sharp corners in two or three quads whose patch was re-quadded (open_wedge_tip)
  std::size_t valence_swaps = 0;      // of the swaps, those taken to make valences regular
  std::size_t valence_collapses = 0;  // of the collapses, those of two valence-3 vertices
  std::size_t splits = 0;      // quad pairs split into three around a new point, or into four around two
  std::size_t splits_four = 0; // of the splits, those into four
  // The grading pass: vertex moves, small quads collapsed, large ones split
  // with a neighbour (not counted with the collapses and splits above).
  std::size_t grading_moves = 0, grading_collapses = 0, grading_splits = 0;
  int passes = 0;
  std::size_t fixed_vertices = 0;  // boundary, constrained or region-boundary vertices
  Json to_json() const;
  // Empty when every quad is strictly convex after; else how many are not,
  // and whether they came in that way or were made so.
  std::string failed_guarantee() const;
};

// Smooths and cleans the quad mesh in place. Element attributes, point
// attributes/markers and segments (with markers) are kept; removed vertices
// and quads are compacted away and segment ids renumbered; points added by
// pair splits come last, strictly inside a region, with zero attributes and
// marker, and their quads carry the region's attributes. Vertices on the
// boundary, on a segment, on an edge between regions of different attribute
// or on a non-quad element stay fixed (or, with slide_boundary, slide along
// their own straight segment); so do vertices with a nonzero point marker
// that lie on no such edge (input points). Throws Error when the
// input is not a conforming mesh (see check_quad_mesh); quads that come in
// non-convex are counted in the reports and only moves that make them
// strictly convex touch them.
SmoothStats smooth_quad_mesh(PlanarMesh& mesh, const SmoothOptions& opt);

// Checks the input contract of smooth_quad_mesh: ids in range, no repeated id
// in an element, every edge in at most two elements with opposite
// orientations, positive area. Throws Error (naming the first
// offending element) otherwise; `path` is used in the message.
void check_quad_mesh(const PlanarMesh& mesh, const std::string& path = {});

} // namespace imgmesh
