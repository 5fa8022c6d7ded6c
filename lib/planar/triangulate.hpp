// Constrained Delaunay refinement of a planar straight-line graph (PSLG), the
// job Triangle did in the thesis (section 3.3.3), done with CGAL's
// Constrained_Delaunay_triangulation_2 and Delaunay_mesher_2 (Ruppert /
// Shewchuk refinement with clusters at small input angles).
#pragma once
#include "planar/triangle_io.hpp"
#include "util/json.hpp"

#include <cstddef>
#include <functional>
#include <string>

namespace imgmesh {

struct TriangulateOptions {
  // Smallest angle wanted, degrees; 20.7 is the bound B = sqrt(2) for which
  // refinement provably terminates (CGAL's shape bound 0.125 = sin^2 20.7).
  // 0 = no quality refinement (plain constrained Delaunay triangulation).
  double min_angle = 20.7;
  double max_area = 0;  // > 0: no triangle larger
  double max_edge = 0;  // > 0: no edge longer
  // > 0: before refinement, Steiner points on an equilateral-triangle
  // lattice of this side fill the domain, at least half a side from every
  // segment and input vertex. Two equilateral triangles make a 60-degree
  // rhombus (Joe's mu 30) whichever edge tri2quad pairs them across, where
  // Delaunay refinement's own points give quads of mean mu 28 or less.
  double lattice = 0;
  // With lattice > 0: a square lattice of that side instead. Its right
  // triangles pair into squares (Joe's mu 45) across their hypotenuses,
  // which tri2quad's --pair-above merges first.
  bool square_lattice = false;
  // With square_lattice: the lattice coarsens away from the segments, so
  // that the size follows the geometry: the size field is the least, over
  // the segments, of the segment's length (clamped to [lattice, max_side])
  // plus grading times the distance to it; a node stays where it is a node
  // of the lattice of side 2^k lattice, the largest 2^k lattice within the
  // field (the lattices are nested: with grading <= 0.5 neighbouring cells
  // differ by at most 2x). 0: a uniform lattice.
  double grading = 0;
  double max_side = 0;  // > 0: the coarsest lattice side (default: no bound)
  // With square_lattice and grading > 0: where the domain is narrower than
  // the field asks for, between two of its sides, the field is at most that
  // width, down to half the lattice side (one level finer there).
  bool narrow = false;
  // A lattice whose points alone exceed max_vertices is left out (the
  // refinement then stops at the limit) rather than refused as a usage
  // error: poly2tri's default lattice, which the user did not ask for.
  bool lattice_optional = false;
  // Stop refining beyond this many vertices (the result is then reported as
  // not meeting the bounds).
  std::size_t max_vertices = 50'000'000;
  std::function<void(std::size_t)> progress;  // called now and then with the vertex count
};

struct TriangulateResult {
  // Points, CCW triangles with one attribute each (the region attribute:
  // Triangle's -A semantics, flood fill from the regional points across
  // unconstrained edges; 0 where no regional point reaches), point markers
  // (input marker, else the marker of the segment a vertex lies on), the
  // input segments subdivided into mesh edges with their markers, the holes.
  PlanarMesh mesh;
  std::size_t input_vertices = 0, input_segments = 0, steiner_points = 0;
  std::size_t holes = 0, regions = 0;  // hole and regional points of the input
  double min_angle_bound = 0;          // opt.min_angle
  std::size_t lattice_points = 0;      // of the Steiner points, those of opt.lattice
  std::size_t small_input_angles = 0;  // input vertices where segments meet at < 60 degrees
  double smallest_input_angle = 180;   // degrees, between segments at a vertex
  double min_angle = 0;                // smallest triangle angle, degrees
  // Smallest angle among triangles away from small input angles: with no
  // vertex in the disc around an apex where two segments meet at < 60
  // degrees, of radius the shorter of the two (the bound is promised there).
  double min_angle_away_from_small_input_angles = 0;
  std::size_t below_bound_near_small_angles = 0;  // triangles below the bound, all near small input angles
  std::size_t regions_outside_domain = 0;        // regional points in a hole or outside
  bool limit_reached = false;                     // max_vertices stopped the refinement

  Json to_json() const;
  // The vertex limit stopped refinement, or an angle away from small input
  // angles is below the bound.
  std::string failed_guarantee() const;
};

// The lattice side poly2tri uses by default, from the curves' own sampling:
// half the median length of the input segments, at least twice their 10th
// percentile and 1/2048 of the bounding box.
double default_lattice_side(const PlanarMesh& pslg);
// The coarsest side poly2tri allows by default: a tenth of the shorter side
// of the input's bounding box.
double default_max_side(const PlanarMesh& pslg);

// Throws Error on a bad PSLG: intersecting or overlapping segments, a
// zero-length segment, no enclosed area, non-finite coordinates.
TriangulateResult triangulate_pslg(const PlanarMesh& pslg, const TriangulateOptions& opt = {});

} // namespace imgmesh
