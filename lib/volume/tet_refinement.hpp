// implicit2tet's library (thesis 9.1, after Oudot-Rineau-Yvinec 2005): the
// surface mesher's Delaunay triangulation, refined inside S = f^-1(0) until
// its tetrahedra are well shaped, with the surface kept certified:
//
//   DELMESH and its certificate (lib/surface, delmesh.hpp)
//   once the certificate holds, rounds until one inserts nothing:  tet_refinement.cpp
//     restricted facets with a vertex off S: insert their surface centre
//     cells with circumcentre c inside (f(c) < 0) and radius-edge ratio
//     above R or circumradius above S, largest ratio first, then slivers
//     (a dihedral angle below --sliver-angle, Delaunay refinement of
//     slivers instead of exudation: the boundary is refined and certified
//     again rather than kept):
//       c in a restricted facet's surface Delaunay ball: insert that
//       facet's surface centre instead (the facet is refined)
//       else insert c
//     a round that inserted: REFINE, then the next round
//   the certificate again if any round inserted (and so on, should it fail)
//   the output: the cells whose circumcentre lies inside; their boundary is
//   checked to be the restricted Delaunay surface, face for face
#pragma once
#include "mesh/surface_certificate.hpp"
#include "mesh/tet_mesh.hpp"
#include "mesh/topology.hpp"
#include "surface/restricted_delaunay.hpp"

#include <string>

namespace imgmesh {

struct TetRefinementOptions {
  RestrictedDelaunayOptions surface;
  double cell_ratio = 2;  // R: radius-edge ratio bound of the tetrahedra
  double cell_size = 0;   // S > 0: circumradius bound (world units); 0: none
  int max_rounds = 100;   // rounds of cell refinement (each followed by the surface steps)
  // Slivers: an inside tetrahedron with a dihedral angle below this
  // (degrees) is refined as a bad one, after them (not guaranteed to
  // terminate in theory, hence after every bound that is; the rounds and
  // --max-points bound it). 0: off.
  double sliver_angle = 10;
  // Also the outside of S up to the image box B, as region 2
  // (box_refinement.hpp).
  bool outside = false;
  // Cap on the points cell refinement inserts (cells, encroached facets,
  // box): a guarantee reported failed, never a hang.
  long long max_cell_points = 1000000;
};

struct TetRefinementResult {
  RestrictedDelaunayResult surface;  // the certified surface: the tetrahedra's boundary
  // World coordinates; region 1 inside S, region 2 (--outside) between S
  // and B; triangles: region 1's boundary (the surface) with region 1, then
  // (--outside) the box's faces with region 2, all outward.
  TetMesh mesh;
  TetQualityReport quality;
  TetConformity conformity;
  // Region 1's boundary (the surface) certified against bdCA(X), as
  // meshinfo --image certifies it; its topology.
  SurfaceCertificate boundary_certificate;
  bool boundary_is_surface = false;       // boundary faces = restricted facets
  long long volume_points = 0, facet_points = 0, off_surface_facet_points = 0, refused = 0;
  long long sliver_points = 0;  // circumcentres of slivers inserted
  // Points off S whose Voronoi cell was proved to miss S when they went in:
  // the surface steps skipped them (DelMesh::cell_misses_surface).
  long long proved_off_surface = 0;
  long long slivers_left = 0;   // output tetrahedra with a dihedral angle below sliver_angle
  bool outside = false;
  long long box_points = 0, box_refused = 0;  // box splits inserted, refused (insertion floor)
  double box_volume = 0;
  bool box_filled = true, box_covered = true;  // --outside: volume = B's; box triangles on B, of B's area
  long long max_cell_points = 0;
  bool cell_points_exhausted = false;
  double sliver_angle = 0;
  int rounds = 0;
  bool rounds_exhausted = false;
  double cell_ratio = 0, cell_size = 0;
  bool ratio_ok = false, size_ok = false;
  double seconds_cells = 0;
  Json to_json() const;
  std::string failed_guarantee() const;
};

// Throws Error as restricted_delaunay_mesh, UsageError on bad bounds.
TetRefinementResult tetrahedral_mesh(const ImplicitSurface& surface, const TetRefinementOptions& options);

} // namespace imgmesh
