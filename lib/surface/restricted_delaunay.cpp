// implicit2mesh's entry point: the options checked (mesher_options.cpp),
// DELMESH run (delmesh.hpp gives its steps and the file of each), the
// result reported. No CGAL here; doc/implicit2mesh.md describes the CGAL
// calls the mesher follows.
#include "surface/restricted_delaunay.hpp"

#include "surface/mesher_options.hpp"
#include "surface/vec3.hpp"

#include <algorithm>
#include <cmath>

namespace imgmesh {

namespace surface_detail {
// DELMESH and the certificate, in delmesh.cpp (which holds CGAL).
RestrictedDelaunayResult delmesh(const ImplicitSurface& surface, const RestrictedDelaunayOptions& options);
} // namespace surface_detail

long long RestrictedDelaunayResult::inserted(const std::string& subroutine) const {
  for (const auto& [name, count] : points_inserted)
    if (name == subroutine) return count;
  return 0;
}

Json RestrictedDelaunayResult::to_json() const {
  Json st = Json::object();
  Json pts = Json::object();
  for (const auto& [name, count] : points_inserted) pts[name] = count;
  st["points_inserted"] = pts;
  st["points_refused"] = points_refused;
  st["seeds_deleted"] = seeds_deleted;
  st["handle_points_deleted"] = handle_points_deleted;
  st["handle_points_restored"] = handle_points_restored;
  st["topology_fallback_rounds"] = topology_fallback_rounds;
  st["topology_insertions_refused"] = topology_insertions_refused;
  st["topology_fallback_points"] = inserted("topology_fallback");
  st["facet_cycle_checks"] = facet_cycle_checks;
  st["facet_cycle_passes"] = facet_cycle_passes;
  st["facet_cycle_skipped"] = facet_cycle_skipped;
  st["handle_detection_checks"] = handle_detection_checks;
  st["handle_detection_certified"] = handle_detection_certified;
  st["handle_detection_undecided"] = handle_detection_undecided;
  st["handle_detection_unresolved"] = handle_detection_unresolved;
  st["vertices"] = mesh.points.size();
  st["triangles"] = mesh.triangles.size();
  Json comps = Json::array();
  for (long long e : topology.sorted_euler()) comps.push_back(e);
  st["components_euler"] = comps;
  Json ex = Json::array();
  for (long long e : expected.sorted_euler()) ex.push_back(e);
  st["voxel_boundary_euler"] = ex;
  st["closed_manifold"] = topology.closed && topology.manifold;
  st["oriented"] = topology.oriented;
  st["topology_matches"] = topology_ok;
  if (!topology_ok) st["topology_failure"] = topology_failure;
  st["min_angle_degrees"] = quality.smallest_angle();
  st["max_radius_edge_ratio"] = quality.largest_radius_edge_ratio();
  st["ratio_bound"] = ratio_bound;
  st["max_roughness_degrees"] = max_roughness * 180 / M_PI;
  st["roughness_bound_degrees"] = roughness_bound * 180 / M_PI;
  st["max_distance_to_plane"] = max_distance_to_plane;
  st["max_distance_bound"] = max_distance_bound;
  st["max_abs_f_at_vertices"] = max_abs_f_at_vertices;
  st["max_abs_f_at_centroids"] = max_abs_f_at_centroids;
  st["restricted_delaunay_violations"] = restricted_delaunay_violations;
  if (voxel_sides_counted) st["voxel_sides"] = voxel_sides.to_json();
  st["function_evaluations"] = function_evaluations;
  Json times = Json::object();
  times["seeds"] = seconds_seeds;
  times["refinement"] = seconds_refinement;
  times["verification"] = seconds_verification;
  st["phase_seconds"] = times;
  return st;
}

std::string RestrictedDelaunayResult::failed_guarantee() const {
  std::string failure;
  if (max_points_hit) failure = "--max-points reached (" + std::to_string(max_points) + " points); ";
  if (!topology_ok) failure += "the certificate against the voxel boundary bdCA(X) fails (" + topology_failure + "); ";
  if (topology_insertions_refused)
    failure += std::to_string(topology_insertions_refused) + " TOPOLOGY insertion(s) refused, the first " +
               topology_insertion_refused_first + "; ";
  if (facet_cycle_skipped)
    failure += std::to_string(facet_cycle_skipped) + " Voronoi facet(s) too large for FacetCycle to check; ";
  if (handle_detection_unresolved)
    failure += std::to_string(handle_detection_unresolved) + " HandleDetection check(s) undecided with nothing to refine; ";
  if (!ratio_ok) failure += "radius-edge ratio above the bound; ";
  if (!roughness_ok) failure += "roughness above the bound; ";
  if (!distance_ok) failure += "distance to the surface above --max-distance; ";
  if (restricted_delaunay_violations) failure += "restricted Delaunay property violated; ";
  if (voxel_sides_on && voxel_sides_counted && voxel_sides.wrong())
    failure += std::to_string(voxel_sides.wrong()) + " voxel centre(s) on the wrong side of the surface; ";
  if (!failure.empty()) failure.resize(failure.size() - 2);
  return failure;
}

RestrictedDelaunayResult restricted_delaunay_mesh(const ImplicitSurface& surface, const RestrictedDelaunayOptions& options) {
  check_options(options);
  return surface_detail::delmesh(surface, options);
}

void add_normals(const ImplicitSurface& surface, SurfaceMesh& mesh) {
  mesh.normals.resize(mesh.points.size());
  for (std::size_t k = 0; k < mesh.points.size(); ++k) {
    Vec3 q = surface.to_local(mesh.points[k]), gr;
    const Geometry& g = surface.samples();
    for (int i = 0; i < 3; ++i) q[i] = std::clamp(q[i], 0.0, double(g.size[i] - 1) * g.spacing[i]);
    surface.value_gradient(q, gr);
    Vec3 w = surface.vector_to_world(gr);
    const double l = surface_detail::norm(w);
    mesh.normals[k] = l > 0 ? Vec3{w[0] / l, w[1] / l, w[2] / l} : Vec3{0, 0, 0};
  }
}

} // namespace imgmesh
