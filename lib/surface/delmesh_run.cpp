// DELMESH's decisions past the queues (delmesh.hpp's pseudocode): the
// VoxelSides, FacetCycle and HandleDetection passes, the fallback, and the
// run (seeds, REFINE, the certificate and its rounds). The triangulation
// changes only through delmesh.cpp (insert, insert_batch).
#include "surface/delmesh.hpp"

#include "surface/certificate.hpp"
#include "surface/facet_cycle.hpp"
#include "surface/star.hpp"
#include "util/error.hpp"
#include "util/memory.hpp"

#include <algorithm>
#include <cmath>

namespace imgmesh::surface_detail {

// One FacetCycle pass over the edges whose Voronoi facet may have changed
// since the last pass; inserts the cycle points found. True if any went in.
bool DelMesh::facet_cycle_pass() {
  ++facet_cycle_passes_;
  phase_ = "facet cycle";
  std::vector<int> skipped;
  const Candidates pts = facet_cycle_points(tr_, sampler_, vertices_, dirty_, stamp_, opt_.threads, facet_cycle_checks_, skipped,
                                             opt_.compare_facet_walks ? FacetWalk::kCompare : FacetWalk::kSpans);
  dirty_.clear();
  // Skipped facets are not answers: their edges are checked again in the
  // next pass (after later insertions); what the last pass skipped is counted.
  for (int id : skipped) dirty_.add(id);
  facet_cycle_skipped_ = static_cast<long long>(skipped.size());
  return insert_batch(pts, kFacetCycle);
}

// HandleDetection (8.3) in TOPOLOGY, after TopoDisk and FacetCycle: every
// vertex whose Voronoi cell changed since its last check. True if a point
// went in.
bool DelMesh::handle_vertex_pass() {
  std::vector<Vh> todo;
  // HandleDetection is about the sample P on S: implicit2tet's points off
  // S are not checked (their cells hold no piece of S to test).
  cell_changed_.for_each([&](int id) {
    const Vh v = vertices_[std::size_t(id)];
    if (v != Vh() && on_surface(v->info().origin)) todo.push_back(v);
  });
  cell_changed_.clear();
  const Candidates pts = handle_points(tr_, sampler_, todo, opt_.threads, handle_checks_);
  if (handle_trial_ && !pts.empty()) {  // the deleted handle point goes back
    const Vec3 x = *handle_trial_;
    handle_trial_.reset();
    ++handle_points_restored_;
    if (!insert(x, kHandle)) refuse_topology("HandleDetection", x);
    return true;
  }
  return insert_batch(pts, kHandle);
}

// VoxelSides (issue 38), once the queues have drained (VorEdge has
// nothing left): a point of S for every voxel centre whose cell lies on
// the other side. Each goes in at least half the centre's distance to W
// from W (doc/implicit2mesh.md 4.9), and at least QUALITY's guard. True if
// one went in.
bool DelMesh::voxel_sides_pass() {
  phase_ = "voxel sides";
  const Candidates pts = voxel_side_points_(tr_, sampler_, vertices_, walk_start_, 1e-3 * grid_.delta, voxel_sides_wrong_, refused_);
  // A point waits for the next pass once one of this pass went in nearer
  // to it than W was: one point often puts a run of centres right (fewer
  // points, and fewer for QUALITY to repair around them).
  bool any = false;
  for (const auto& [x, clearance2] : pts) {
    const Vh nv = nearest_vertex(tr_, Point(x[0], x[1], x[2]), walk_start_->cell());
    if (any && dist2(x, vec(nv->point())) < 0.99 * clearance2) continue;
    if (insert(x, kVoxelSide)) any = true;
    else refused_ += !max_hit_;
  }
  return any;
}

// HandleDetection on every vertex of the S components whose mesh has the
// wrong topology (the certificate says which), before the blunter fallback.
bool DelMesh::handle_pass(const std::vector<int>& bad) {
  Candidates pts;
  if (!handle_component_points(tr_, sampler_, vertices_, bad, opt_.threads, handle_checks_, pts)) return false;
  return insert_batch(pts, kHandle);
}

// Beyond HandleDetection: when the certificate still (or again) finds a
// component of S whose mesh has the wrong topology, refine it there. Each
// component's points are found on the triangulation as it is then (the
// insertions for the one before destroyed cells).
bool DelMesh::fallback(const std::vector<int>& bad) {
  bool any = false;
  for (int comp : bad) any = insert_batch(fallback_points(tr_, sampler_, comp), kFallback) || any;
  return any;
}

void DelMesh::prepare() {
  const SampleGrid& g = f_.samples();
  if (g.dimension != 3 || g.size[0] < 2 || g.size[1] < 2 || g.size[2] < 2)
    throw Error("the implicit function must be sampled on a 3D grid of at least 2x2x2 voxels");
  if (!g.finite()) throw Error("the implicit function has non-finite samples");
  // S must be closed inside the grid: no inside sample on the border.
  for (long z = 0; z < grid_.n[2]; ++z)
    for (long y = 0; y < grid_.n[1]; ++y)
      for (long x = 0; x < grid_.n[0]; ++x) {
        const bool border = x == 0 || y == 0 || z == 0 || x == grid_.n[0] - 1 || y == grid_.n[1] - 1 || z == grid_.n[2] - 1;
        if (border && grid_.neg(x, y, z))
          throw Error("the surface touches the border of the grid (the foreground must be padded by background)");
        if (!border) x = grid_.n[0] - 2;  // only the border faces
      }
  grid_.label();
  if (grid_.components == 0) throw Error("the surface is empty (no sign change in the implicit function)");
  comp_vertices_.assign(std::size_t(grid_.components), 0);
}

RestrictedDelaunayResult DelMesh::run() {
  RestrictedDelaunayResult res;
  const auto t_start = Clock::now();
  auto secs = [](Clock::time_point a) { return std::chrono::duration<double>(Clock::now() - a).count(); };
  prepare();
  ExpectedTopology expected = expected_topology(grid_);

  seeds();
  const double t_seeds = secs(t_start);
  const auto t_refine = Clock::now();
  // DELMESH. With seed_deletion, SAMPLETOPOLOGY first as published: TOPOLOGY
  // alone, then the seeds deleted one by one (7.6.2); by default every
  // queue runs from the start (measured: as many points, half the time).
  if (opt_.seed_deletion) {
    refine();
    delete_seeds();
    topology_only_ = false;
    for (auto it = tr_.finite_facets_begin(); it != tr_.finite_facets_end(); ++it) enqueue_facet(it->first, it->second);
    for (Vh v : vertices_)
      if (v != Vh()) enqueue_vertex(v);
  }
  refine();

  // Certificate (certify_surface): closed, manifold, outward, no
  // self-intersection, components placed on bdCA(X)'s and matched one to
  // one, chi per pair. On a failure (TOPOLOGY should leave none), HandleDetection
  // on the failing S components, else the fallback, and DELMESH's queues
  // again. Termination: at most opt_.fallback_rounds rounds, each of which
  // inserts at least one point (else the loop stops) and ends with REFINE,
  // which terminates on its own (and at --max-points).
  // implicit2tet (after_certificate_): once the certificate holds, its
  // rounds, each followed by REFINE, until one inserts nothing; then the
  // certificate once more, on that final triangulation (not after every
  // round: measured on brain label 3, 5 certificates of 0.5 s each).
  int rounds = 0;
  Certificate cert;
  std::uint32_t settled = 0;  // computed_ when the last round inserted nothing
  const bool late = !after_certificate_;  // delmesh.hpp: memory
  for (;;) {
    cert = Certificate();  // the last round's, not held while the next is built
    dirty_.release();      // the certificate is the run's peak
    cell_changed_.release();
    if (late) voxel_side_points_.release();
    release_free_memory();
    cert = certify(tr_, vertices_.size(), grid_, expected, !late);
    if (cert.ok && !max_hit_ && after_certificate_ && computed_ != settled) {
      bool any = false;
      while (!max_hit_ && after_certificate_(*this)) {
        refine();
        any = true;
      }
      settled = computed_;
      if (any) continue;
    }
    if (cert.ok || max_hit_ || rounds >= opt_.fallback_rounds || cert.bad.empty()) break;
    ++rounds;
    phase_ = "handle detection";
    if (!opt_.topology_steps || !handle_pass(cert.bad)) {
      phase_ = "topology fallback";
      if (!fallback(cert.bad)) break;
    }
    refine();
  }
  const double t_refine_s = secs(t_refine);
  const auto t_final = Clock::now();
  res.expected = std::move(expected.topology);  // moved, not copied at the start: held through the run's peak
  res.expected_boundary = std::move(expected.boundary);

  // Guarantees, measured on the output.
  const MeasuredGuarantees m = measure_guarantees(tr_, sampler_, cert);
  if (late) {  // the triangulation's last use: its pages back first
    tr_.clear();
    release_free_memory();
    check_surface_intersections(cert.check, cert.mesh.points, cert.mesh.triangles);
    cert.ok = cert.check.ok();
  }
  res.topology = cert.check.topology;
  res.topology_ok = cert.ok;
  res.topology_failure = cert.check.failure();
  res.ratio_ok = m.quality.largest_radius_edge_ratio() <= opt_.ratio * (1 + 1e-9);
  res.roughness_ok = m.max_roughness <= opt_.roughness + 1e-9;
  res.distance_ok = opt_.max_distance <= 0 || m.max_distance_to_plane <= opt_.max_distance * (1 + 1e-9);
  res.max_points_hit = max_hit_;
  res.quality = m.quality;
  res.max_roughness = m.max_roughness;
  res.max_distance_to_plane = m.max_distance_to_plane;
  res.max_abs_f_at_vertices = m.max_abs_f_at_vertices;
  res.max_abs_f_at_centroids = m.max_abs_f_at_centroids;
  res.restricted_delaunay_violations = m.restricted_delaunay_violations;
  res.voxel_sides_on = opt_.voxel_sides && opt_.topology_steps;  // VoxelSides runs only with TOPOLOGY
  res.voxel_sides_counted = count_voxel_sides(cert, grid_, res.voxel_sides);
  res.ratio_bound = opt_.ratio;
  res.roughness_bound = opt_.roughness;
  res.max_distance_bound = opt_.max_distance;
  res.max_points = opt_.max_points;

  // World coordinates; a reflecting direction matrix flips orientation.
  SurfaceMesh mesh = std::move(cert.mesh);
  std::vector<Vec3> centers = std::move(cert.centers);
  for (Vec3& p : mesh.points) p = f_.to_world(p);
  for (Vec3& x : centers) x = f_.to_world(x);
  if (f_.reflects())
    for (auto& t : mesh.triangles) std::swap(t[1], t[2]);
  res.mesh = std::move(mesh);
  res.centers = std::move(centers);

  for (int o = 0; o < kOrigins; ++o) res.points_inserted.emplace_back(kOriginName[o], inserted_[o]);
  res.points_refused = refused_;
  res.topology_insertions_refused = topology_refused_;
  res.topology_insertion_refused_first = topology_refused_first_;
  res.seeds_deleted = seeds_deleted_;
  res.handle_points_deleted = handle_points_deleted_;
  res.handle_points_restored = handle_points_restored_;
  res.topology_fallback_rounds = rounds;
  res.facet_cycle_checks = facet_cycle_checks_;
  res.facet_cycle_passes = facet_cycle_passes_;
  res.facet_cycle_skipped = facet_cycle_skipped_;
  res.handle_detection_checks = handle_checks_.full;
  res.handle_detection_certified = handle_checks_.certified;
  res.handle_detection_undecided = handle_checks_.undecided;
  res.handle_detection_unresolved = handle_checks_.unresolved;
  res.function_evaluations = sampler_.evaluations();
  res.seconds_seeds = t_seeds;
  res.seconds_refinement = t_refine_s;
  res.seconds_verification = secs(t_final);
  return res;
}

RestrictedDelaunayResult delmesh(const ImplicitSurface& surface, const RestrictedDelaunayOptions& options) {
  return DelMesh(surface, options).run();
}

} // namespace imgmesh::surface_detail
