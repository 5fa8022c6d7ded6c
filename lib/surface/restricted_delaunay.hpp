// implicit2mesh's library: the restricted Delaunay surface of S = f^-1(0)
// after the thesis's simplification of Cheng-Dey-Ramos-Ray (ch. 7-8):
// seeds from the components of bdCA(X) (8.1), TOPOLOGY (VorEdge with
// EdgeSurface on the cube grid, TopoDisk, FacetCycle, HandleDetection),
// QUALITY(rho_0) and SMOOTH(g) as in DELMESH, plus --max-distance, then a
// certificate (certify_surface, as meshinfo --image): where it fails,
// HandleDetection on all the failing component's samples and then a
// fallback refine.
#pragma once
#include "mesh/surface_io.hpp"
#include "mesh/voxel_sides.hpp"
#include "surface/implicit_surface.hpp"
#include "mesh/topology.hpp"
#include "mesh/triangle_quality.hpp"
#include "util/json.hpp"

#include <cstdint>
#include <functional>
#include <string>
#include <utility>
#include <vector>

namespace imgmesh {

// Termination limits of DELMESH (k = 0.06): rho_0 > (1+k)^2 and
// g > 2 (arcsin k + arcsin(2k/sqrt 3)) (thesis 7.6.3-7.6.4; doc/thesis-errata.md).
double min_ratio_bound();
double min_roughness_bound();

struct RestrictedDelaunayOptions {
  double ratio = 2.0;           // rho_0: radius-edge ratio bound
  double roughness = 1.0471975511965976;  // g (radians), pi/3
  double max_distance = 0;      // E > 0: surface Delaunay ball centre within E of the facet's plane, |f| at its centroid within 2E
  std::size_t max_points = 2000000;
  std::uint64_t seed = 0;       // order of seed insertion
  int threads = 1;
  bool facet_cycle = true;      // FacetCycle (8.2) on the Voronoi facets of Delaunay edges
  // Tests only: FacetCycle walks every facet both by spans and in full and
  // throws Error where their runs differ (the same mesh otherwise).
  bool compare_facet_walks = false;
  // false (tests only): implicit2tet's points off S go through EdgeSurface,
  // FacetCycle and HandleDetection even where their Voronoi cell provably
  // misses S (the same mesh either way). compare_missed_cells (tests only):
  // EdgeSurface runs on the facets of a point so proved all the same, and
  // on the cavity's boundary facets whose Voronoi edge shrank away from S
  // (DelMesh::shrunk_edge), and throws Error if one is restricted, or if a
  // facet that keeps its crossing has another (or none, or one farther
  // than 1e-9 voxel from the kept one).
  bool prove_missed_cells = true;
  bool compare_missed_cells = false;
  // Tests only: a TopoDisk or SMOOTH check that is not stale (the vertex's
  // restricted facets unchanged since it last passed) runs all the same,
  // and throws Error if it fails.
  bool compare_stale_checks = false;
  bool seed_deletion = false;   // SAMPLETOPOLOGY as published: TOPOLOGY alone, then delete the seeds (7.6.2)
  // VoxelSides (issue 38): refine until every voxel centre next to a sign
  // change of g lies on its own side of the surface (delmesh.hpp); the
  // certificate counts those that do not either way, and fails on one when on.
  bool voxel_sides = true;
  // The certificate's repairs: at most this many rounds of HandleDetection
  // or the fallback (a counted last resort: TOPOLOGY should leave nothing).
  int fallback_rounds = 40;
  // false (tests only): no VorEdge, TopoDisk, FacetCycle or HandleDetection,
  // so that the certificate fails and the fallback must act; nor VoxelSides
  // (it needs the closed ball property), whose count is then reported only.
  bool topology_steps = true;
  // Called now and then with the phase and the number of points so far.
  std::function<void(const std::string&)> progress;
};

struct RestrictedDelaunayResult {
  SurfaceMesh mesh;                 // world coordinates, outward, normals empty
  std::vector<Vec3> centers;        // per triangle: its surface Delaunay ball centre (world)
  MeshTopology topology;            // of mesh
  MeshTopology expected;            // of bdCA(X)
  VoxelBoundary expected_boundary;  // bdCA(X)'s corners and faces bits (its quads dropped), for certify_surface
  bool topology_ok = false;         // certify_surface holds (mesh/surface_certificate.hpp)
  std::string topology_failure;     // when not: its first failed check and why
  bool ratio_ok = false, roughness_ok = false, distance_ok = false;
  bool max_points_hit = false;

  // What DELMESH did: points inserted per subroutine (seed, vor_edge,
  // topo_disk, facet_cycle, handle_detection, quality, smooth, max_distance,
  // topology_fallback, voxel_side), points refused (too close to W),
  // deletions.
  std::vector<std::pair<std::string, long long>> points_inserted;
  long long points_refused = 0, seeds_deleted = 0, handle_points_deleted = 0, handle_points_restored = 0;
  int topology_fallback_rounds = 0;  // certificate rounds that repaired a component
  // TOPOLOGY points that could not go in (a vertex already): a failed
  // guarantee, the first one described.
  long long topology_insertions_refused = 0;
  std::string topology_insertion_refused_first;
  long long facet_cycle_checks = 0, facet_cycle_passes = 0;
  long long facet_cycle_skipped = 0;  // edges whose facet the last pass could not rasterise (too large)
  long long handle_detection_checks = 0, handle_detection_certified = 0;  // full tests; settled by the cube grid
  // Full tests without an answer (refined at p instead), and of those the
  // ones with nothing to refine: a failed guarantee.
  long long handle_detection_undecided = 0, handle_detection_unresolved = 0;
  long long function_evaluations = 0;
  // Measured on the output.
  TriangleQualityReport quality;
  double max_roughness = 0;             // radians
  double max_distance_to_plane = 0;     // surface centre to its triangle's plane
  double max_abs_f_at_vertices = 0, max_abs_f_at_centroids = 0;
  long long restricted_delaunay_violations = 0;  // surface centres whose ball holds a vertex
  // The voxel centres next to bdCA(X) on the wrong side of the mesh
  // (mesh/voxel_sides.hpp), counted when the mesh is closed, manifold and
  // oriented; a failed guarantee when voxel_sides_on.
  VoxelSides voxel_sides;
  bool voxel_sides_counted = false, voxel_sides_on = false;
  // The bounds asked.
  double ratio_bound = 0, roughness_bound = 0, max_distance_bound = 0;
  std::size_t max_points = 0;
  double seconds_seeds = 0, seconds_refinement = 0, seconds_verification = 0;

  long long inserted(const std::string& subroutine) const;  // 0 for an unknown name
  Json to_json() const;
  // Which guarantees failed, "; "-separated; empty if none.
  std::string failed_guarantee() const;
};

// Throws Error when S is empty, UsageError when the options are out of
// range (check_options, mesher_options.hpp).
RestrictedDelaunayResult restricted_delaunay_mesh(const ImplicitSurface& surface,
                                                  const RestrictedDelaunayOptions& options);

// Per-vertex unit normals from grad f (world coordinates).
void add_normals(const ImplicitSurface& surface, SurfaceMesh& mesh);

} // namespace imgmesh
