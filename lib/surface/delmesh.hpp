// DELMESH (thesis 7.6.5) on CGAL's Delaunay_triangulation_3, kept
// incremental: every insertion recomputes only the facets of the new cells
// (all incident to the new vertex) and re-checks only the vertices whose
// restricted facets changed. The only code that changes the triangulation
// (delmesh.cpp: upkeep, queues, insertion; delmesh_run.cpp: the passes past
// the queues and the run); every subroutine is a query in a file of its own:
//
//   DELMESH(S, rho_0, g):
//     check f; the cube grid, its components, bdCA(X)'s topology   cube_grid.cpp, certificate.cpp
//     W <- the seeds of every component of S                       seeds.cpp (8.1)
//     [--seed-deletion] SAMPLETOPOLOGY first: REFINE with the TOPOLOGY
//       queues alone, then delete the seeds and HandleDetection's
//       points one by one, each followed by REFINE                 delmesh.cpp (7.6.2)
//     REFINE: until no step inserts a point
//       drain the queues, by priority, each entry re-checked at pop:
//         VorEdge: a Voronoi edge meets S twice                    edge_surface.cpp (8.2)
//         TopoDisk: a vertex's restricted facets are not one disk  topo_disk.cpp (7.6.1)
//         QUALITY: a restricted facet's ratio > rho_0              criteria.cpp (7.6.3)
//         SMOOTH: an edge's roughness > g                          criteria.cpp (7.6.4)
//         --max-distance: a surface centre far from its facet      criteria.cpp
//       then (VorEdge has nothing left):
//         VoxelSides: a voxel centre next to S in a cell on the
//           other side of S (its circumcentre's)                   voxel_side_points.cpp (issue 38)
//       then, once it finds nothing, over what changed since the last pass:
//         FacetCycle: S closed inside a Voronoi facet              facet_cycle.cpp (8.2),
//           its raster of the facet                                facet_cycle_raster.cpp
//         HandleDetection: S inside a Voronoi cell not a disk      handle_detection.cpp (8.3)
//     certificate: components and Euler characteristics against
//       bdCA(X), per component and by place                        certificate.cpp
//     while a component differs (at most --fallback-rounds rounds):
//       HandleDetection on all its vertices, else the fallback;
//       REFINE; certificate again                                  handle_detection.cpp, certificate.cpp
//     the guarantees measured on the output, the voxel centres on
//       the wrong side of it counted (mesh/voxel_sides.hpp)        certificate.cpp
//
// Memory: the certificate is the run's peak, beside the triangulation. The
// surface mesher checks its intersections once the triangulation is gone
// (their boxes made that peak; no repair needs them: a failure of them
// alone leaves no component to repair), and VoxelSides' per-centre memory
// goes before each certificate (a repair round looks at every centre
// again, from another walk: a centre on a facet or edge of W, or outside
// its hull, may be found in another of its cells); the heap's free pages
// go back first (util/memory.hpp). implicit2tet, which refines on after
// the certificate, does neither.
//
// A point goes in at the surface centre x_t of the facet that asked for it
// (EdgeSurface's crossing of its Voronoi edge), with the conflict zone
// started from that facet's cells (doc/implicit2mesh.md 2, step 3).
#pragma once
#include "surface/criteria.hpp"
#include "surface/cube_grid.hpp"
#include "surface/delaunay_types.hpp"
#include "surface/edge_surface.hpp"
#include "surface/handle_detection.hpp"
#include "surface/restricted_delaunay.hpp"
#include "surface/topo_disk.hpp"
#include "surface/voxel_side_points.hpp"

#include <chrono>
#include <cstdint>
#include <functional>
#include <optional>
#include <queue>
#include <string>
#include <vector>

namespace imgmesh::surface_detail {

class DelMesh {
public:
  DelMesh(const ImplicitSurface& surface, const RestrictedDelaunayOptions& opt);

  // All of it; the result in world coordinates. Throws Error when f is not
  // sampled on a 3D grid, is not finite, touches the grid's border or has
  // no zero.
  RestrictedDelaunayResult run();

  // The steps run() takes, for tests: the checks of f and the cube grid's
  // components (throws as run()), then the seeds, then REFINE.
  void prepare();
  void seeds();
  void refine();
  // Inserts x (a point of S) into W unless --max-points is reached or x is a
  // vertex already; `hint`: the facet that asked for it.
  bool insert(const Vec3& x, Origin origin, Facet hint = Facet(Ch(), 0));

  // implicit2tet's entry (lib/volume): once the certificate holds, called
  // with REFINE after each call that inserts points (true), until one
  // inserts none; then the certificate again if any did, so the surface
  // guarantees hold on the final triangulation.
  void set_after_certificate(std::function<bool(DelMesh&)> step) { after_certificate_ = std::move(step); }

  const Tr& triangulation() const { return tr_; }
  // A finite cell's circumcentre, kept for the cells the last insertion or
  // removal made (implicit2tet's quality test on them), else computed.
  Vec3 new_cell_centre(Ch c) const { return centres_(tr_, c); }
  // The cells at the vertex the last insertion made (incident_cells' order).
  const std::vector<Ch>& new_cells() const { return cells_buf_; }
  const CubeGrid& grid() const { return grid_; }
  const SurfaceSampler& sampler() const { return sampler_; }
  const std::vector<Vh>& vertices() const { return vertices_; }  // by id; null where deleted
  long long inserted(Origin origin) const { return inserted_[origin]; }
  // Points off S whose Voronoi cell was proved to miss S when inserted.
  long long cells_missed() const { return cells_missed_; }
  // TopoDisk and SMOOTH checks not run: not stale (they would pass).
  long long checks_skipped() const { return checks_skipped_; }

private:
  using Clock = std::chrono::steady_clock;
  enum Kind { kQVorEdge, kQTopoDisk, kQQuality, kQSmooth, kQDistance };
  // VInfo::queued past its two queued bits: a check is stale while the
  // vertex's restricted facets changed since it last passed (or it failed);
  // kChanged: by the insertion under way.
  static constexpr std::uint8_t kStaleTopoDisk = 4, kStaleSmooth = 8, kStale = 12, kChanged = 16;
  // 32 bytes (the queue holds a few entries a facet): a facet entry names
  // its facet by (cell, index) and the computation it queued, which no other
  // facet's record ever carries (every computation is stamped anew, and a
  // record lives on one facet); a vertex entry names its vertex by id.
  struct Item {
    double prio;
    std::uint64_t seq;
    Ch cell;
    std::uint32_t stamp;  // a facet's FacetInfo::computed when queued; a vertex's id
    std::uint8_t kind;
    std::uint8_t index;
    bool operator<(const Item& o) const {  // std::priority_queue pops the largest
      if (kind != o.kind) return kind > o.kind;
      if (prio != o.prio) return prio < o.prio;
      return seq > o.seq;
    }
  };
  static_assert(sizeof(Item) == 32, "a queue entry: 32 bytes");

  void compute_facet(Ch c, int i);
  void enqueue_facet(Ch c, int i);
  void enqueue_vertex(Vh v, bool changed = true);
  void after_insertion(Vh v);
  void compute_new_cells(Vh inserted, Vh missed = Vh());
  enum Shrunk { kRecompute, kMisses, kKeepCrossing };
  Shrunk shrunk_edge(Ch n, int j, Vh v) const;
  bool cell_misses_surface(Vh v);
  void add_vertex(Vh v, Origin origin, const Vec3& x);
  bool remove_vertex(Vh v);
  bool delete_and_restore(Vh v);
  void delete_seeds();
  void requeue_grown();
  void settle_facet(Ch c, int i, Ch n, int j, Shrunk shrunk, bool missed);
  static bool same_answer(const FacetInfo& a, const FacetInfo& b);
  std::uint64_t restricted_signature(Vh v);
  void mark_restricted(Ch c, int i, bool changed);
  void mark_changed(Ch c, int i);
  void drain();
  bool stale(const Item& it) const;
  void purge();
  bool insert_batch(const Candidates& pts, Origin origin);
  bool facet_cycle_pass();
  bool handle_vertex_pass();
  bool voxel_sides_pass();
  bool handle_pass(const std::vector<int>& bad_components);
  bool fallback(const std::vector<int>& bad_components);
  void refuse_topology(const char* step, const Vec3& x);
  void progress();

  const ImplicitSurface& f_;
  RestrictedDelaunayOptions opt_;
  CubeGrid grid_;
  SurfaceSampler sampler_;
  Tr tr_;
  std::vector<Vh> vertices_;  // by id; null where a vertex was deleted
  Vh walk_start_;             // a live vertex near the last change
  // The heap's vector is reachable for purge(): entries of facets destroyed
  // or recomputed since they were queued pile up (every insertion queues
  // the new facets and destroys the old ones) and would hold most of the
  // memory; purging them changes no pop.
  struct Queue : std::priority_queue<Item> {
    using std::priority_queue<Item>::c;
  };
  Queue queue_;
  std::size_t purge_at_ = 1 << 16;
  std::uint64_t seq_ = 0;
  std::uint32_t computed_ = 0;  // facet computations so far
  long long inserted_[kOrigins] = {};
  long long refused_ = 0;            // QUALITY/SMOOTH guards and deferred batch points
  long long topology_refused_ = 0;   // TOPOLOGY points that could not go in
  std::string topology_refused_first_;
  bool max_hit_ = false;
  std::size_t last_progress_ = 0;
  const char* phase_ = "seeds";  // for progress(); a literal (drain() sets it at every pop)
  TopoDisk topo_disk_;
  Smooth smooth_;
  // FacetCycle: vertices inserted since the last pass. Insertions create
  // only edges at the new vertex and only shrink the other Voronoi facets,
  // and a cycle inside a shrunken facet was inside it before
  // (doc/implicit2mesh.md 2.7).
  IdSet dirty_;
  // HandleDetection: vertices whose Voronoi cell changed since their check.
  IdSet cell_changed_;
  // SAMPLETOPOLOGY (7.6.2): only the topology queues run, so that seeds can
  // be deleted with no QUALITY/SMOOTH entry pointing at them.
  bool topology_only_ = false;
  long long seeds_deleted_ = 0;
  long long cells_missed_ = 0;
  long long checks_skipped_ = 0;
  // compare_stale_checks: per vertex id, restricted_signature when its
  // TopoDisk (0) and SMOOTH (1) checks last passed.
  std::vector<std::uint64_t> passed_[2];
  std::vector<int> comp_vertices_;  // vertices per S component
  long long facet_cycle_checks_ = 0, facet_cycle_passes_ = 0;
  long long facet_cycle_skipped_ = 0;  // edges the last FacetCycle pass could not rasterise
  HandleChecks handle_checks_;
  // The HandleDetection point being deleted (8.3): it goes back if
  // HandleDetection finds a handle again.
  std::optional<Vec3> handle_trial_;
  long long handle_points_deleted_ = 0, handle_points_restored_ = 0;
  std::vector<int> grown_;  // ids of the neighbours of deleted vertices
  // Insertion scratch: the conflict zone and the vertices around it.
  std::vector<Facet> zone_facets_;
  std::vector<Ch> zone_cells_, cells_buf_;
  CellCentres centres_;  // of the cells the last insertion or removal made
  std::vector<HalfSpace> cell_faces_;  // cell_misses_surface's scratch
  std::vector<Vh> touched_;
  std::uint32_t stamp_ = 0;
  std::function<bool(DelMesh&)> after_certificate_;
  VoxelSidePoints voxel_side_points_;
  long long voxel_sides_wrong_ = 0;  // wrong centres found, over all passes
};

// DelMesh(surface, options).run(), for restricted_delaunay_mesh().
RestrictedDelaunayResult delmesh(const ImplicitSurface& surface, const RestrictedDelaunayOptions& options);

} // namespace imgmesh::surface_detail
