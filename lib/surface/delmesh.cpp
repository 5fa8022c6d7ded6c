#include "surface/delmesh.hpp"

#include "surface/edge_surface.hpp"
#include "surface/facet_cycle.hpp"
#include "surface/seeds.hpp"
#include "surface/star.hpp"
#include "util/error.hpp"
#include "util/hash.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>

namespace imgmesh::surface_detail {

DelMesh::DelMesh(const ImplicitSurface& surface, const RestrictedDelaunayOptions& opt)
    : f_(surface), opt_(opt), grid_(surface.samples()), sampler_(surface, grid_), topology_only_(opt.seed_deletion) {}

void DelMesh::compute_facet(Ch c, int i) {
  FacetInfo fi = edge_surface_of(tr_, sampler_, c, i, centres_);
  fi.computed = ++computed_;
  Ch n = c->neighbor(i);
  FacetRefs::set(c->facet, i, n->facet, n->index(c), fi);
  enqueue_facet(c, i);
}

// EdgeSurface's answer queues the facet for VorEdge (two crossings),
// QUALITY and --max-distance when it fails them.
void DelMesh::enqueue_facet(Ch c, int i) {
  const FacetInfo& fi = c->facet[i];
  if (!(fi.state & kRestricted)) return;
  const auto [a, b, d] = facet_vertices(c, i);
  const auto push = [&](Kind kind) { queue_.push({fi.r2, seq_++, c, fi.computed, std::uint8_t(kind), std::uint8_t(i)}); };
  if ((fi.state & kMulti) && opt_.topology_steps) push(kQVorEdge);
  const Vec3 pa = vec(a->point()), pb = vec(b->point()), pd = vec(d->point());
  if (topology_only_) return;
  if (quality_refines(pa, pb, pd, opt_.ratio)) push(kQQuality);
  if (opt_.max_distance > 0 && (distance_refines(pa, pb, pd, Vec3{fi.x[0], fi.x[1], fi.x[2]}, opt_.max_distance) ||
                                centroid_refines(sampler_, pa, pb, pd, opt_.max_distance)))
    push(kQDistance);
}

// A vertex is queued at most once per check: the check runs on the state at
// pop time, which includes every change since it was queued. `changed`: its
// restricted facets changed (else an insertion only came near it): both
// checks are stale.
void DelMesh::enqueue_vertex(Vh v, bool changed) {
  const auto push = [&](Kind kind) { queue_.push({0, seq_++, Ch(), std::uint32_t(v->info().id), std::uint8_t(kind), 0}); };
  if (changed) v->info().queued |= kStale;
  if (!(v->info().queued & 1) && opt_.topology_steps) push(kQTopoDisk);
  v->info().queued |= 1;
  if (topology_only_) return;
  if (!(v->info().queued & 2)) push(kQSmooth);
  v->info().queued |= 2;
}

bool DelMesh::insert(const Vec3& x, Origin origin, Facet hint) {
  if (origin != kSeed && tr_.number_of_vertices() >= opt_.max_points) {  // seeds always go in
    max_hit_ = true;
    return false;
  }
  const Point p(x[0], x[1], x[2]);
  if (tr_.dimension() < 3) {
    const std::size_t before = tr_.number_of_vertices();
    Vh v = tr_.insert(p);
    if (tr_.number_of_vertices() == before) return false;
    add_vertex(v, origin, x);
    if (tr_.dimension() == 3) {  // bootstrap: one scan, incremental afterwards
      for (auto it = tr_.finite_facets_begin(); it != tr_.finite_facets_end(); ++it) compute_facet(it->first, it->second);
      for (Vh w : vertices_)
        if (w != Vh()) {
          enqueue_vertex(w);
          dirty_.add(w->info().id);
          cell_changed_.add(w->info().id);
        }
    }
    return true;
  }
  // A facet's surface centre lies in the circumball of one of the facet's two
  // cells (balls centred on its Voronoi edge are covered by the two), so the
  // conflict zone starts there without a walk (doc/implicit2mesh.md 2, step 3).
  Ch c0;
  if (hint.first != Ch()) {
    Ch n = hint.first->neighbor(hint.second);
    if (tr_.side_of_sphere(hint.first, p, true) == CGAL::ON_BOUNDED_SIDE) c0 = hint.first;
    else if (tr_.side_of_sphere(n, p, true) == CGAL::ON_BOUNDED_SIDE) c0 = n;
  }
  if (c0 == Ch()) {
    Tr::Locate_type lt;
    int li, lj;
    c0 = tr_.locate(p, lt, li, lj, hint.first);
    if (lt == Tr::VERTEX) return false;
  }
  zone_facets_.clear();
  zone_cells_.clear();
  tr_.find_conflicts(p, c0, std::back_inserter(zone_facets_), std::back_inserter(zone_cells_));
  for (const Facet& f : zone_facets_)  // x on a vertex (rounding): refuse
    for (int m = 1; m < 4; ++m) {
      const Vh w = f.first->vertex((f.second + m) & 3);  // the infinite vertex's point is (0,0,0): not a vertex
      if (!tr_.is_infinite(w) && w->point() == p) return false;
    }
  // Vertices whose restricted facets die: TopoDisk/SMOOTH re-check them.
  // Those of the facets inside the cavity changed; the cavity's boundary
  // facets stay, and compute_new_cells says which changed.
  ++stamp_;
  touched_.clear();
  for (Ch c : zone_cells_) c->tds_data().mark_in_conflict();
  for (Ch c : zone_cells_)
    for (int i = 0; i < 4; ++i) mark_restricted(c, i, c->neighbor(i)->tds_data().is_in_conflict());
  for (Ch c : zone_cells_) c->tds_data().clear();
  Vh v = tr_.insert_in_hole(p, zone_cells_.begin(), zone_cells_.end(), zone_facets_[0].first, zone_facets_[0].second);
  add_vertex(v, origin, x);
  after_insertion(v);
  progress();
  return true;
}

void DelMesh::add_vertex(Vh v, Origin origin, const Vec3& x) {
  v->info() = VInfo();
  v->info().id = int(vertices_.size());
  v->info().origin = std::uint8_t(origin);
  v->info().comp = grid_.comp_at(x);
  vertices_.push_back(v);
  walk_start_ = v;
  ++inserted_[origin];
  if (v->info().comp >= 0) ++comp_vertices_[std::size_t(v->info().comp)];
}

// Deletion (7.6.2, 8.3): the cells around v are replaced by a Delaunay
// triangulation of its link (CGAL's remove), and the facets of the new cells
// are computed anew. v's neighbours gained Voronoi volume: TopoDisk,
// FacetCycle and HandleDetection check them again. False if v had to stay.
bool DelMesh::remove_vertex(Vh v) {
  std::vector<Vh> adj;
  tr_.adjacent_vertices(v, std::back_inserter(adj));
  const Vec3 x = vec(v->point());
  const Origin origin = Origin(v->info().origin);
  vertices_[std::size_t(v->info().id)] = Vh();
  if (v->info().comp >= 0) --comp_vertices_[std::size_t(v->info().comp)];
  cells_buf_.clear();
  tr_.remove_and_give_new_cells(v, std::back_inserter(cells_buf_));
  voxel_side_points_.release();  // its cells' largest ids no longer tell them apart
  if (tr_.dimension() < 3) {  // the rest is coplanar: put it back (bootstrap)
    insert(x, origin);
    --inserted_[origin];
    return false;
  }
  centres_.assign(tr_, cells_buf_);
  compute_new_cells(Vh());
  for (Vh w : adj)
    if (!tr_.is_infinite(w)) {
      walk_start_ = w;
      grown_.push_back(w->info().id);
      cell_changed_.add(w->info().id);
    }
  return true;
}

// Deletes v, then TOPOLOGY restores the closed ball property (Lemma 7.6.3).
// A component keeps at least two vertices (doc/implicit2mesh.md 4.5): with fewer, it can
// hide inside one Voronoi cell, where no Voronoi edge sees it.
bool DelMesh::delete_and_restore(Vh v) {
  if (v->info().comp < 0 || comp_vertices_[std::size_t(v->info().comp)] <= 2 || tr_.number_of_vertices() <= 8)
    return false;
  if (!remove_vertex(v)) return false;
  requeue_grown();
  refine();
  return true;
}

// SAMPLETOPOLOGY step 2 (7.6.2): delete the seeds one by one, restoring the
// topology after each, so that every point left was placed by a subroutine
// that keeps it k d_M(p) from the others. Then HandleDetection's points,
// which need not be (8.3): each is deleted in turn, and should
// HandleDetection then find a handle again, that point goes back instead of
// a new one.
void DelMesh::delete_seeds() {
  const std::size_t seeds = vertices_.size();  // refine() adds no seeds
  for (std::size_t id = 0; id < seeds && !max_hit_; ++id) {
    const Vh v = vertices_[id];
    if (v != Vh() && v->info().origin == kSeed && delete_and_restore(v)) ++seeds_deleted_;
  }
  std::vector<int> handle_points;
  for (Vh v : vertices_)
    if (v != Vh() && v->info().origin == kHandle) handle_points.push_back(v->info().id);
  for (int id : handle_points) {
    const Vh v = vertices_[std::size_t(id)];
    if (v == Vh() || max_hit_) continue;
    handle_trial_ = vec(v->point());
    if (delete_and_restore(v)) ++handle_points_deleted_;
    handle_trial_.reset();
  }
}

// The live neighbours of deleted vertices: TopoDisk and FacetCycle again.
void DelMesh::requeue_grown() {
  std::sort(grown_.begin(), grown_.end());
  grown_.erase(std::unique(grown_.begin(), grown_.end()), grown_.end());
  for (int id : grown_) {
    const Vh w = vertices_[std::size_t(id)];
    if (w == Vh()) continue;
    enqueue_vertex(w);
    dirty_.add(id);
  }
  grown_.clear();
}

// TOPOLOGY and the other queues until they drain, then VoxelSides,
// FacetCycle and HandleDetection passes over what changed, until none
// inserts. VoxelSides goes first: its side test needs only VorEdge's
// answer (doc/implicit2mesh.md 4.9), and its passes then change the cells
// before the two costlier passes look at them once, not after each of its
// passes.
void DelMesh::refine() {
  for (;;) {
    drain();
    // The drained queue's storage, as large as at its busiest, is not held
    // through the passes and the certificate (brain label 4: 3.7 MB).
    if (queue_.empty()) std::vector<Item>().swap(queue_.c);
    if (max_hit_ || !opt_.topology_steps) break;
    if (opt_.voxel_sides && !topology_only_ && voxel_sides_pass()) continue;
    if (opt_.facet_cycle && facet_cycle_pass()) continue;
    if (!handle_vertex_pass()) break;
  }
}

// The facets of the new cells cells_buf_ (their centres in centres_),
// computed (and so queued) in the order of their vertex ids, not CGAL's
// storage order: vertex removal makes that depend on addresses, and the
// queue's ties would then differ from run to run. `inserted`: the vertex
// whose insertion made them (null after a removal, which grows Voronoi
// edges), whose cavity's boundary facets may keep an answer
// (shrunk_edge). `missed`: a new vertex whose Voronoi cell misses S
// (cell_misses_surface).
void DelMesh::compute_new_cells(Vh inserted, Vh missed) {
  for (Ch c : cells_buf_)
    for (int i = 0; i < 4; ++i) c->facet.clear(i);
  // The sorted ids + 1 (the infinite vertex's -1 becomes 0), the first two
  // packed in one word: the same order as the ids' triples, for less to
  // compare and move than std::array<int, 3> (the sort was 2% of a run).
  struct Key { std::uint64_t ab; std::uint32_t c; int i; Ch cell; };
  thread_local std::vector<Key> order;
  order.clear();
  for (Ch c : cells_buf_)
    for (int i = 0; i < 4; ++i) {
      std::array<int, 3> ids;
      for (int m = 1; m < 4; ++m) {
        const Vh w = c->vertex((i + m) & 3);
        ids[m - 1] = tr_.is_infinite(w) ? -1 : w->info().id;
      }
      // Three compare-exchanges (std::sort's call on three ints cost more).
      if (ids[1] < ids[0]) std::swap(ids[0], ids[1]);
      if (ids[2] < ids[1]) std::swap(ids[1], ids[2]);
      if (ids[1] < ids[0]) std::swap(ids[0], ids[1]);
      const auto u = [&](int k) { return std::uint32_t(ids[std::size_t(k)] + 1); };
      order.push_back({std::uint64_t(u(0)) << 32 | u(1), u(2), i, c});
    }
  std::sort(order.begin(), order.end(), [](const Key& a, const Key& b) { return a.ab != b.ab ? a.ab < b.ab : a.c < b.c; });
  // The facets at `missed` (its id, the largest, is their third): their
  // Voronoi edges are edges of its cell, which misses S.
  const std::uint32_t at_missed = missed == Vh() ? 0 : std::uint32_t(missed->info().id + 1);
  for (const Key& k : order) {
    if (k.cell->facet.computed(k.i)) continue;
    const Ch n = k.cell->neighbor(k.i);
    const int j = n->index(k.cell);
    const bool boundary = inserted != Vh() && k.cell->vertex(k.i) == inserted;  // of the cavity: it stayed
    const Shrunk shrunk = boundary ? shrunk_edge(n, j, inserted) : kRecompute;
    // A boundary facet's old answer (n's until set below): a change in it
    // makes its vertices' TopoDisk and SMOOTH checks stale.
    if (boundary && shrunk != kKeepCrossing) {
      const bool was = n->facet.restricted(j);
      const FacetInfo old = was ? n->facet[j] : FacetInfo();
      settle_facet(k.cell, k.i, n, j, shrunk, k.c == at_missed);
      if (was ? !same_answer(old, k.cell->facet[k.i]) : k.cell->facet.restricted(k.i)) mark_changed(k.cell, k.i);
      continue;
    }
    settle_facet(k.cell, k.i, n, j, shrunk, k.c == at_missed);
  }
}

// Facet i of new cell c (facet j of its neighbour n) by shrunk_edge's
// answer: its old record kept, EdgeSurface's, or not restricted (`missed`:
// a facet at a vertex whose cell misses S).
void DelMesh::settle_facet(Ch c, int i, Ch n, int j, Shrunk shrunk, bool missed) {
  if (shrunk == kKeepCrossing) {  // the old record, stamped and queued anew
    FacetInfo fi = n->facet[j];
    if (opt_.compare_missed_cells) {
      const FacetInfo now = edge_surface_of(tr_, sampler_, c, i, centres_);
      if (!(now.state & kRestricted) || (now.state & kMulti) ||
          dist2(Vec3{now.x[0], now.x[1], now.x[2]}, Vec3{fi.x[0], fi.x[1], fi.x[2]}) > 1e-18 * grid_.delta * grid_.delta)
        throw Error("a facet whose Voronoi edge shrank keeps a surface centre EdgeSurface does not find");
    }
    fi.computed = ++computed_;
    FacetRefs::set(c->facet, i, n->facet, j, fi);
    enqueue_facet(c, i);
    return;
  }
  if (!missed && shrunk != kMisses) {
    compute_facet(c, i);
    return;
  }
  FacetInfo fi;
  fi.state = kComputed;
  if (opt_.compare_missed_cells && (edge_surface_of(tr_, sampler_, c, i, centres_).state & kRestricted))
    throw Error(missed ? "a point's Voronoi cell proved to miss S has a restricted facet"
                       : "a facet whose Voronoi edge shrank away from S is restricted");
  fi.computed = ++computed_;
  FacetRefs::set(c->facet, i, n->facet, j, fi);
}

// compare_stale_checks: the restricted facets at v, by their vertices and
// answers (those sides and order TopoDisk and SMOOTH read them in aside).
std::uint64_t DelMesh::restricted_signature(Vh v) {
  std::vector<Facet> facets;
  std::vector<Ch> cells;
  restricted_around(tr_, v, facets, cells);
  std::uint64_t sum = 0;
  for (const Facet& f : facets) {
    const FacetInfo& fi = f.first->facet[f.second];
    std::uint64_t h = fi.state;
    for (const Vh w : facet_vertices(f.first, f.second)) h = mix64(h ^ std::uint64_t(w->info().id + 1));
    for (const double x : {fi.x[0], fi.x[1], fi.x[2], fi.r2, double(fi.grad[0]), double(fi.grad[1]), double(fi.grad[2])}) {
      std::uint64_t bits;
      std::memcpy(&bits, &x, 8);
      h = mix64(h ^ bits);
    }
    sum += h;
  }
  return sum;
}

// What TopoDisk and SMOOTH read of a restricted facet: all of EdgeSurface's
// answer but the computation's stamp.
bool DelMesh::same_answer(const FacetInfo& a, const FacetInfo& b) {
  return a.state == b.state && a.r2 == b.r2 && std::equal(a.x, a.x + 3, b.x) && std::equal(a.grad, a.grad + 3, b.grad);
}

// A facet of the cavity's boundary, facet j of the cell n outside it,
// keeps its answer from before v went in until compute_new_cells computes
// it. Its Voronoi edge now is a part of the old one (a new site only
// shrinks the set of points equidistant from the facet's vertices and
// nearer to them than to any other). So it misses S if the old one did,
// or if the old one met S once (not kMulti), at a surface centre x_t that
// v is nearer to than the facet's vertices are (inside the facet's
// surface Delaunay ball): x_t is on the old edge but not on the new. And
// where v is not nearer, x_t is still on the new edge and its only
// crossing: the facet keeps x_t, its ball and its gradient as they are
// (EdgeSurface on the shorter edge would find the same root, rounded
// differently). Either way EdgeSurface need not run (on the bunny, 116,000
// of 347,000 facets computed skip it as missing S, and 23,000 restricted
// ones keep their crossing).
DelMesh::Shrunk DelMesh::shrunk_edge(Ch n, int j, Vh v) const {
  if (!n->facet.computed(j)) return kRecompute;
  if (!n->facet.restricted(j)) return kMisses;
  const FacetInfo& old = n->facet[j];
  if (old.state & kMulti) return kRecompute;
  return dist2(Vec3{old.x[0], old.x[1], old.x[2]}, vec(v->point())) < old.r2 ? kMisses : kKeepCrossing;
}

// implicit2tet's point v off S (thesis 9.1): does its Voronoi cell
// provably miss S? Yes when f has no zero on the box of the cell's
// vertices (the circumcentres of the cells at v, all finite), inside the
// grid's box: each part of it lies beyond a face of the cell, meets only
// inactive cubes (F1) or has an enclosure of f that excludes 0, the box
// halved across its longest side where none holds (at most kHalvings deep,
// kEnclosures in all). Then every Voronoi edge and facet of the cell misses
// S: v's facets are not restricted (EdgeSurface would find no sign
// change), its edges' facets hold no FacetCycle (every sample takes f's one
// sign there), and the parts its neighbours' cells lost to it held no
// piece of S, so their HandleDetection answers stand.
bool DelMesh::cell_misses_surface(Vh v) {
  if (on_surface(v->info().origin) || !opt_.prove_missed_cells) return false;
  Vec3 lo{HUGE_VAL, HUGE_VAL, HUGE_VAL}, hi{-HUGE_VAL, -HUGE_VAL, -HUGE_VAL};
  for (Ch c : cells_buf_) {
    if (tr_.is_infinite(c)) return false;
    const Vec3 x = centres_(tr_, c);
    for (int i = 0; i < 3; ++i) {
      lo[i] = std::min(lo[i], x[i]);
      hi[i] = std::max(hi[i], x[i]);
    }
  }
  for (int i = 0; i < 3; ++i)
    if (!(lo[i] >= 0 && hi[i] <= grid_.hi[i])) return false;
  voronoi_cell(tr_, v, cell_faces_);
  // [a, b] lies beyond face e (clear of rounding): the corner least far along e.d.
  auto beyond = [&](const Vec3& a, const Vec3& b) {
    for (const HalfSpace& e : cell_faces_) {
      double m = 0;
      for (int i = 0; i < 3; ++i) m += e.d[i] * (e.d[i] >= 0 ? a[i] : b[i]);
      if (m - e.c > 1e-9 * grid_.delta * norm(e.d)) return true;
    }
    return false;
  };
  constexpr int kHalvings = 9, kEnclosures = 1024;
  int enclosures = 0;
  auto no_zero = [&](auto&& self, const Vec3& a, const Vec3& b, int depth) -> bool {
    if (depth > 0 && beyond(a, b)) return true;
    if (grid_.inactive_box(a, b)) return true;
    double flo, fhi;
    if (++enclosures > kEnclosures || !sampler_.range(a, b, flo, fhi)) return false;
    if (flo > 0 || fhi < 0) return true;
    if (depth == kHalvings) return false;
    const Vec3 d = sub(b, a);
    const int k = d[0] >= d[1] && d[0] >= d[2] ? 0 : d[1] >= d[2] ? 1 : 2;
    Vec3 m1 = b, m0 = a;
    m1[k] = m0[k] = (a[k] + b[k]) / 2;
    return self(self, a, m1, depth + 1) && self(self, m0, b, depth + 1);
  };
  return no_zero(no_zero, lo, hi, 0);
}

// Remember the finite vertices of facet (c, i) if it is restricted, as
// changed by the insertion under way if `changed`.
void DelMesh::mark_restricted(Ch c, int i, bool changed) {
  if (!c->facet.restricted(i)) return;
  for (int m = 1; m < 4; ++m) {
    Vh w = c->vertex((i + m) & 3);
    if (w->info().stamp != stamp_) {
      w->info().stamp = stamp_;
      touched_.push_back(w);
    }
  }
  if (changed) mark_changed(c, i);
}

// A restricted facet (c, i), before or after the insertion under way,
// that the insertion changed (its vertices are in touched_).
void DelMesh::mark_changed(Ch c, int i) {
  for (int m = 1; m < 4; ++m) c->vertex((i + m) & 3)->info().queued |= kChanged;
}

// The new cells are exactly the cells incident to v: recompute their facets
// (both sides), and re-check the vertices whose restricted facets changed.
// An edge's Voronoi facet changed only if both its ends are in the cavity.
void DelMesh::after_insertion(Vh v) {
  cells_buf_.clear();
  star_cells(tr_, v, cells_buf_);
  centres_.assign(tr_, cells_buf_);
  const bool missed = cell_misses_surface(v);
  compute_new_cells(v, missed ? v : Vh());
  for (Ch c : cells_buf_)
    for (int i = 0; i < 4; ++i) mark_restricted(c, i, c->vertex(i) != v);  // the facets at v are new
  // A vertex whose cell misses S never has a restricted facet (the cell
  // only shrinks; a deleted neighbour re-queues it, requeue_grown): TopoDisk
  // and SMOOTH would pass it.
  if (!missed) enqueue_vertex(v);
  std::sort(touched_.begin(), touched_.end(), [](Vh a, Vh b) { return a->info().id < b->info().id; });
  for (Vh w : touched_) {
    enqueue_vertex(w, w->info().queued & kChanged);
    w->info().queued &= std::uint8_t(~kChanged);
  }
  if (missed) {
    ++cells_missed_;
    return;
  }
  dirty_.add(v->info().id);
  for (Ch c : cells_buf_)
    for (int i = 0; i < 4; ++i)
      if (!tr_.is_infinite(c->vertex(i))) cell_changed_.add(c->vertex(i)->info().id);
}

// Seeds (8.1); for degenerate seed sets, more crossings until the
// triangulation is 3D.
void DelMesh::seeds() {
  phase_ = "seeds";
  Seeds seeds(sampler_);
  for (const Vec3& x : seeds.points(opt_.seed)) insert(x, kSeed);
  Vec3 x;
  while (tr_.dimension() < 3 && seeds.next_extra(x)) insert(x, kSeed);
  if (tr_.dimension() < 3) throw Error("cannot place four non-coplanar seed points on the surface");
}

// A facet entry whose facet is gone or was recomputed (never true again):
// its cell died (or was re-created at the same address, with facets
// computed anew) or the facet's record is of a later computation (O(1)).
bool DelMesh::stale(const Item& it) const {
  if (it.kind == kQTopoDisk || it.kind == kQSmooth) return false;
  if (!tr_.tds().cells().is_used(it.cell) || !it.cell->facet.restricted(it.index)) return true;
  return it.cell->facet[it.index].computed != it.stamp;
}

// Drops the stale entries; the heap order of the others is total (kind,
// priority, sequence number), so the pops that follow are the same.
void DelMesh::purge() {
  auto& v = queue_.c;
  v.erase(std::remove_if(v.begin(), v.end(), [this](const Item& it) { return stale(it); }), v.end());
  std::make_heap(v.begin(), v.end(), std::less<Item>());
  v.shrink_to_fit();
  purge_at_ = std::max<std::size_t>(1 << 16, 2 * v.size());
}

// DELMESH as one loop over prioritised queues (doc/implicit2mesh.md 4.8): VorEdge, TopoDisk,
// QUALITY, SMOOTH, max-distance; every insertion re-queues only what changed.
void DelMesh::drain() {
  const double guard2 = std::pow(1e-3 * grid_.delta, 2);  // quality/smooth minimum distance
  while (!queue_.empty() && !max_hit_) {
    if (queue_.size() > purge_at_) purge();
    const Item it = queue_.top();
    queue_.pop();
    if (it.kind == kQTopoDisk || it.kind == kQSmooth) {
      const Vh a = vertices_[it.stamp];
      if (a == Vh()) continue;  // deleted since (seed deletion)
      const bool topo = it.kind == kQTopoDisk;
      const std::uint8_t stale = topo ? kStaleTopoDisk : kStaleSmooth;
      a->info().queued &= std::uint8_t(~(topo ? 1 : 2));
      phase_ = topo ? "topology" : "smooth";
      // Not stale: its restricted facets are as they were when this check
      // last passed; it passes again (an insertion only came near).
      Facet worst;
      std::vector<std::uint64_t>& passed = passed_[topo ? 0 : 1];  // compare_stale_checks only
      if (!(a->info().queued & stale)) {
        if (opt_.compare_stale_checks && (passed.size() <= it.stamp || passed[it.stamp] != restricted_signature(a)))
          throw Error(std::string(topo ? "TopoDisk" : "SMOOTH") + " skipped at a vertex whose restricted facets changed");
        ++checks_skipped_;
        continue;
      }
      a->info().queued &= std::uint8_t(~stale);
      if (topo ? topo_disk_(tr_, a, &worst) : smooth_(tr_, a, opt_.roughness, &worst)) {
        if (opt_.compare_stale_checks) {
          if (passed.size() <= it.stamp) passed.resize(vertices_.size());
          passed[it.stamp] = restricted_signature(a);
        }
        // SMOOTH on the facets TopoDisk just listed: where it passes, a's
        // SMOOTH check is no longer stale. Every TopoDisk entry pops before
        // any SMOOTH one, and every change at a queues TopoDisk and makes
        // both checks stale again, so at its SMOOTH pop a's facets are these
        // exactly when the check is not stale (on the armadillo, every
        // SMOOTH check ran on the facets of the TopoDisk check before it;
        // this saves its walk around a).
        if (topo && !topology_only_ && (a->info().queued & kStaleSmooth) && smooth_(a, topo_disk_.facets(), opt_.roughness, &worst)) {
          a->info().queued &= std::uint8_t(~kStaleSmooth);
          if (opt_.compare_stale_checks) {
            if (passed_[1].size() <= it.stamp) passed_[1].resize(vertices_.size());
            passed_[1][it.stamp] = passed[it.stamp];
          }
        }
        continue;
      }
      a->info().queued |= stale;  // failed: checked again when next queued, as it is
      if (topo) {
        if (!insert(facet_center(worst), kTopoDisk, worst)) refuse_topology("TopoDisk", facet_center(worst));
      } else {
        if (worst.first->facet[worst.second].r2 < guard2 || !insert(facet_center(worst), kSmooth, worst)) ++refused_;
      }
      continue;
    }
    if (stale(it)) continue;  // facet destroyed or recomputed since
    const Ch c = it.cell;
    const int i = it.index;
    const FacetInfo& fi = c->facet[i];
    const Vec3 x{fi.x[0], fi.x[1], fi.x[2]};
    if (it.kind == kQVorEdge) {
      phase_ = "topology";
      if (!(fi.state & kMulti)) continue;
      if (!insert(x, kVorEdge, Facet(c, i))) refuse_topology("VorEdge", x);
    } else {
      phase_ = it.kind == kQQuality ? "quality" : "max-distance";
      if (fi.r2 < guard2 || !insert(x, it.kind == kQQuality ? kQuality : kDistance, Facet(c, i))) ++refused_;
    }
  }
}

void DelMesh::progress() {
  if (opt_.progress && vertices_.size() >= last_progress_ + 5000) {
    last_progress_ = vertices_.size();
    opt_.progress(std::string(phase_) + ": " + std::to_string(tr_.number_of_vertices()) + " points");
  }
}

// Points found on one state of W, inserted one after the other: a point
// goes in only while it is still at least half its clearance (its distance
// to W when it was found) away from W, so two points found for neighbouring
// features do not both go in and make a tiny, unrefinable triangle. Such a
// point is deferred, not lost: the pass runs again after any insertion, and
// the certificate judges the end. A point that cannot go in (a vertex
// already) is a refused TOPOLOGY insertion.
bool DelMesh::insert_batch(const Candidates& pts, Origin origin) {
  bool any = false;
  for (const auto& [x, clearance2] : pts) {
    Vh nv = nearest_vertex(tr_, Point(x[0], x[1], x[2]), walk_start_->cell());
    if (dist2(x, vec(nv->point())) < clearance2 / 4) {
      ++refused_;
      continue;
    }
    if (insert(x, origin)) any = true;
    else if (!max_hit_) refuse_topology(kOriginName[origin], x);
  }
  return any;
}

// A TOPOLOGY step asked for a point that cannot go in (rounding put it on a
// vertex): what it would have repaired may stay wrong, so the run reports
// it as a failed guarantee (max_hit_ is reported on its own).
void DelMesh::refuse_topology(const char* step, const Vec3& x) {
  if (max_hit_) return;
  if (topology_refused_++ == 0)
    topology_refused_first_ = std::string(step) + " at (" + std::to_string(x[0]) + ", " + std::to_string(x[1]) + ", " +
                              std::to_string(x[2]) + ")";
}

} // namespace imgmesh::surface_detail
