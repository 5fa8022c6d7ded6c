// The certificate of a triangle surface against the voxel boundary bdCA(X)
// of a well-composed image: the one check that meshinfo --image runs on any
// mesh and implicit2mesh, implicit2tet and seg2mesh run on their own. Its
// checks, in order; the verdict names the first that fails:
//
//   closed        every edge in two triangles
//   manifold      every edge in at most two triangles, every vertex one fan
//   oriented      neighbours cross their shared edge in opposite directions,
//                 and outward: a component's signed volume is positive when
//                 an even number of the others enclose it, negative when an
//                 odd number do (a hollow ball's inner surface points in)
//   intersections no two triangles meet other than in a shared edge or
//                 vertex, of one component or two (exact predicates), and
//                 none is degenerate
//   placed        every vertex within the place tolerance of the bdCA(X)
//                 component its component is placed on (match_components)
//   matched       placed without a tie, one to one, and each pair oriented
//                 alike (an outer surface on an outer surface, a cavity's on
//                 a cavity's: the nesting of the voxel components)
//   topology      each matched pair with the same Euler characteristic
//
// The geometric checks (oriented's outward half, intersections, matched's
// orientation) need a closed, manifold, consistently oriented surface: when
// the checks before fail they are not run.
//
// Not checked: that bdCA(X) lies near the mesh (the other way). The
// meshers' guarantees do not bound it: a coarse mesh of S (--ratio 2,
// --max-distance 0.5 on the bunny) leaves voxel corners three tolerances
// from its triangles. meshinfo reports the voxel centres on the wrong side
// of the mesh instead (voxel_sides.hpp, issue 38).
#pragma once
#include "mesh/embedding.hpp"
#include "mesh/topology.hpp"
#include "util/json.hpp"

#include <array>
#include <functional>
#include <string>
#include <vector>

namespace imgmesh {

struct CertificateOptions {
  // World units; 0: one voxel diagonal of the grid, sqrt(sx^2 + sy^2 + sz^2).
  double place_tolerance = 0;
  std::size_t intersections_cap = 1000;  // intersecting pairs counted at most
  // false: the caller tests the crossings of a larger triangle set holding
  // these (the multi-label certificate tests the whole mesh once); the
  // check then holds here and the caller's test decides.
  bool intersections = true;
  // Per component of the surface (mesh_topology's), how many of the others
  // enclose it, from a caller that knows it exactly (the multi-label
  // certificate on a surface-nets mesh, whose vertices stay in their
  // cells); empty, or an empty answer: ray tests (SurfaceGeometry).
  std::function<std::vector<int>(const MeshTopology&)> nesting;
};

// The default place tolerance of a grid: one voxel diagonal.
double default_place_tolerance(const Geometry& grid);

struct SurfaceCertificate {
  enum Check : int { kClosed, kManifold, kOriented, kIntersections, kPlaced, kMatched, kTopology, kChecks };
  static const char* name(int check);  // "closed", "manifold", ...

  MeshTopology topology;                   // of the surface
  ComponentCorrespondence correspondence;  // with bdCA(X)'s components
  std::vector<double> volume;              // per component: signed volume (empty when not closed)
  std::vector<int> depth;                  // per component: components enclosing it (empty when not measured)
  SelfIntersections intersections;
  std::array<int, kChecks> state{};        // 1 held, 0 failed, -1 not run
  std::array<std::string, kChecks> why;    // per failed check
  // Per surface component: no check fails on it (the mesher repairs those that fail).
  std::vector<char> component_ok;

  int first_failed() const;  // kChecks when every check holds
  bool ok() const { return first_failed() == kChecks; }
  std::string failure() const;  // "CHECK: why" of the first failed; empty when ok
  Json to_json() const;
};

// points and triangles: the surface in the world coordinates of `grid`,
// whose voxel corners are the lattice of `boundary` (its faces are read; its
// quads may have been dropped); boundary_topology = mesh_topology(boundary).
// Throws Error on a triangle with an id out of range or a repeated corner,
// and on a vertex of a triangle with a coordinate that is not finite.
SurfaceCertificate certify_surface(const std::vector<Vec3>& points, const std::vector<std::array<int, 3>>& triangles,
                                   const Geometry& grid, const VoxelBoundary& boundary,
                                   const MeshTopology& boundary_topology, const CertificateOptions& options = {});
// The intersections check of a certificate made with options.intersections
// false, for a caller that runs it later (the mesher, once its
// triangulation is gone: the boxes would stack on it at the run's peak).
// Only where certify_surface ran the geometric checks (the state is -1
// where it did not); the same points and triangles.
void check_surface_intersections(SurfaceCertificate& c, const std::vector<Vec3>& points,
                                 const std::vector<std::array<int, 3>>& triangles,
                                 std::size_t cap = CertificateOptions().intersections_cap);


} // namespace imgmesh
