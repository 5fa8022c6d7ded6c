#include "conforming/mesher.hpp"

#include "implicit/parallel.hpp"
#include "mesh/located_cells.hpp"
#include "mesh/star_walk.hpp"
#include "util/error.hpp"
#include "util/memory.hpp"

#include <algorithm>
#include <cmath>
#include <string>

namespace imgmesh {
namespace conforming_detail {

const char* const kStepName[kSteps] = {"seed",        "vor_edge", "topo_disk",  "patch_fan", "quality",    "max_distance",
                                       "voxel_side",  "certificate", "cell",     "cell_facet", "off_surface"};
static_assert(kSteps == std::tuple_size<decltype(ConformingSurface::inserted)>::value, "one count a step");

// The point at t of the segment [a, b].
static Vec3 on_edge(const Vec3& a, const Vec3& b, double t) {
  return {a[0] + t * (b[0] - a[0]), a[1] + t * (b[1] - a[1]), a[2] + t * (b[2] - a[2])};
}

// Circumradius over shortest edge.
double radius_edge_ratio(const Vec3& a, const Vec3& b, const Vec3& c) {
  const double ab = dist2(a, b), bc = dist2(b, c), ca = dist2(c, a);
  const Vec3 n = cross(sub(b, a), sub(c, a));
  const double area2 = dot(n, n);  // (2 area)^2
  if (!(area2 > 0)) return INFINITY;
  const double r2 = ab * bc * ca / (4 * area2);
  return std::sqrt(r2 / std::min({ab, bc, ca}));
}

ConformingSurface Mesher::run() {
  tr_.infinite_vertex()->info() = -2;
  bounding_box();
  seeds();
  refine();
  if (!o_.tets.on) return certified_rounds();
  // seg2tet: the cells, then the certificate's rounds (once, on the surface
  // the cells leave: their encroached facets' points change it), and the
  // cells again if those rounds inserted.
  ConformingSurface out;
  for (int again = 0; again < 3; ++again) {
    const std::size_t before = points_;
    if (!max_hit_) refine_cells();
    if (again > 0 && points_ == before) break;
    const int r = rounds_;
    out = certified_rounds();
    if (rounds_ == r) break;
  }
  tets_output(out);
  return out;
}

void Mesher::known(Ch c) {
  if (c->info().label != kUnknown) return;
  c->info().centre = vec(c->circumcenter());
  c->info().label = f_.label(c->info().centre);
}

// Eight corners two voxels and a half beyond the grid's box: every
// restricted facet's Voronoi edge is then finite (the cells around the
// corners lie outside, in 0).
void Mesher::bounding_box() {
  if (o_.tets.on && o_.tets.outside) {  // seg2tet --outside: B's corners instead, the hull B
    box_.emplace(outside_box());
    for (int c = 0; c < 8; ++c) tr_.insert(pt(box_->corners()[std::size_t(c)]))->info() = -3 - c;
    return;
  }
  for (int c = 0; c < 8; ++c) {
    const double i = (c & 1) ? double(x_.size[0]) + 2.5 : -3.5;
    const double j = (c & 2) ? double(x_.size[1]) + 2.5 : -3.5;
    const double k = (c & 4) ? double(x_.size[2]) + 2.5 : -3.5;
    Vh v = tr_.insert(pt(x_.world(i, j, k)));
    v->info() = -1;
    corners_[std::size_t(c)] = reinterpret_cast<std::intptr_t>(&*v);
  }
}

// start: a cell near p where the caller knows one (the walk starts there;
// the triangulation is the same whatever the start); near: see locate_from.
bool Mesher::insert(const Vec3& p, int step, Ch start, double gap2, Ch near) {
  if (points_ >= o_.max_points) {
    max_hit_ = true;
    return false;
  }
  Tr::Locate_type lt;
  int li, lj;
  Ch c = locate_from(tr_, pt(p), lt, li, lj, start != Ch() ? start : hint_, near);
  if (lt == Tr::VERTEX) {
    ++refused_;
    return false;
  }
  // Far inside the cell that holds p (rounding aside, which is far less
  // than the floor) no vertex is within the floor: no search for the
  // nearest.
  const double floor2 = std::max(gap2, 1e-12 * voxel_ * voxel_);
  if (!(lt == Tr::CELL && inner_distance2({vec(c->vertex(0)->point()), vec(c->vertex(1)->point()),
                                           vec(c->vertex(2)->point()), vec(c->vertex(3)->point())},
                                          p) > 4 * floor2) &&
      dist2(vec(tr_.nearest_vertex(pt(p), c)->point()), p) < floor2) {
    ++refused_;
    return false;
  }
  Vh v = tr_.insert(pt(p), lt, c, li, lj);
  v->info() = int(points_++);
  on_surface_.push_back(step != kCell);
  new_vertices_.push_back(v);
  hint_ = v->cell();
  ++inserted_[step];
  return true;
}

// v's cells, in incident_cells' order (CGAL's depth-first walk from
// v->cell(), its marks), without its allocations: the same candidates;
// the walk stops at the first of stop_a, stop_b it reaches, returned.
Ch Mesher::star(Vh v, std::vector<Ch>& out, Ch stop_a, Ch stop_b) {
  out.clear();
  return star_walk(v, out, stack_, [&](Ch n) {
    // n's neighbours asked for now, while the walk goes on elsewhere:
    // their first reads were the walk's cost (a chain of cache misses).
    for (int k = 0; k < 4; ++k) prefetch_cell(n->neighbor(k));
    return n == stop_a || n == stop_b;
  });
}

// The two voxels of a face of K(X), and lambda's change between their centres.
bool Mesher::face_point(std::uint64_t key, Vec3& p) const {
  const auto q = k_.corner(InterfaceComplex::face_corner(key));
  const int a = InterfaceComplex::face_axis(key);
  std::array<std::ptrdiff_t, 3> v1{std::ptrdiff_t(q[0]), std::ptrdiff_t(q[1]), std::ptrdiff_t(q[2])}, v0 = v1;
  v0[a] -= 1;
  // Off the planes of voxel centres (a seed on the segment between two
  // centres lies in two of them: three such seeds made triangles through
  // voxel centres): both ends moved by (0.13, 0.07) voxel across it.
  const double u = 0.13, w = 0.07;
  std::array<double, 3> o{0, 0, 0};
  o[(a + 1) % 3] = u, o[(a + 2) % 3] = w;
  const Vec3 p0 = x_.world(double(v0[0]) + o[0], double(v0[1]) + o[1], double(v0[2]) + o[2]);
  const Vec3 p1 = x_.world(double(v1[0]) + o[0], double(v1[1]) + o[1], double(v1[2]) + o[2]);
  if (f_.label(p0) == voxel_label(v0[0], v0[1], v0[2]) && f_.label(p1) == voxel_label(v1[0], v1[1], v1[2]))
    return f_.first_change(p0, p1, p, o_.step);
  return f_.first_change(voxel_centre(v0[0], v0[1], v0[2]), voxel_centre(v1[0], v1[1], v1[2]), p, o_.step);
}

// Per patch its faces at ranks 0, n/4, n/2, 3n/4, and every face whose
// corner lies on a lattice of seed_spacing in the face's plane.
void Mesher::seeds() {
  std::vector<std::size_t> count(k_.patches.size(), 0), seen(k_.patches.size(), 0);
  for (std::uint32_t p : k_.face_patch) ++count[p];
  const long s = std::max(1L, std::lround(o_.seed_spacing));
  std::vector<Vec3> pts;
  for (std::size_t i = 0; i < k_.faces.size(); ++i) {
    const std::uint32_t p = k_.face_patch[i];
    const std::size_t r = seen[p]++, n = count[p];
    bool take = r == 0 || r == n / 4 || r == n / 2 || r == 3 * n / 4;
    if (!take) {
      const auto q = k_.corner(InterfaceComplex::face_corner(k_.faces[i]));
      const int a = InterfaceComplex::face_axis(k_.faces[i]);
      take = long(q[(a + 1) % 3]) % s == 0 && long(q[(a + 2) % 3]) % s == 0;
    }
    Vec3 x;
    if (take && face_point(k_.faces[i], x)) pts.push_back(x);
  }
  for (const Vec3& x : pts) insert(x, kSeed);
}

// The facet's surface centre and ball radius, when restricted (one change).
bool Mesher::surface_centre(Ch c, int i, Vec3& x) {
  Ch n = c->neighbor(i);
  if (tr_.is_infinite(c) || tr_.is_infinite(n)) return false;
  const std::int32_t ends[2] = {label(c), label(n)};
  if (ends[0] == ends[1]) return false;
  f_.changes(centre(c), centre(n), changes_, o_.step, 0, ends);
  if (changes_.size() != 1) return false;
  const Vec3 a = centre(c), b = centre(n);
  for (int m = 0; m < 3; ++m) x[m] = a[m] + changes_[0].t * (b[m] - a[m]);
  return true;
}

// The facets of a pass and lambda's changes along their Voronoi edges: the
// walks (most of a pass's lambda) in parallel, the cells' labels first
// (each cell by one thread), each walk into its own slot; the candidates
// then made from them in the facets' order, as one thread makes them.
void Mesher::walk_facets() {
  // The new cells (seg2tet's cell stage knows some already) and the older
  // neighbours not yet known, each once.
  pending_.clear();
  for (Ch c : fresh_)
    if (c->info().label == kUnknown) pending_.push_back(c);
  const auto older = std::ptrdiff_t(pending_.size());
  for (const FacetWalk& w : walks_) {
    Ch n = w.c->neighbor(w.i);
    if (!tr_.is_infinite(n) && !is_fresh(n) && n->info().label == kUnknown) pending_.push_back(n);
  }
  std::sort(pending_.begin() + older, pending_.end());
  pending_.erase(std::unique(pending_.begin() + older, pending_.end()), pending_.end());
  const unsigned threads = implicit_detail::resolve_threads(o_.threads);
  implicit_detail::parallel_for(long(pending_.size()), threads, [&](long lo, long hi, unsigned) {
    for (long j = lo; j < hi; ++j) {
      // As the walks below: the cell eight ahead, its vertices four ahead.
      if (j + 8 < hi) prefetch_cell(pending_[std::size_t(j + 8)]);
      if (j + 4 < hi)
        for (int q = 0; q < 4; ++q) __builtin_prefetch(&*pending_[std::size_t(j + 4)]->vertex(q));
      known(pending_[std::size_t(j)]);
    }
  });
  walk_brackets_.resize(threads);
  implicit_detail::parallel_for(long(walks_.size()), threads, [&](long lo, long hi, unsigned t) {
    std::vector<LabelFunction::Bracket>& br = walk_brackets_[t];
    for (long j = lo; j < hi; ++j) {
      // The cells and vertices of walks ahead fetched while this one walks
      // (their first reads, misses, were a sixth of the walks' time): the
      // cell eight ahead, then four ahead its neighbour and the facet's
      // vertices (the corner test).
      if (j + 8 < hi) prefetch_cell(walks_[std::size_t(j + 8)].c);
      if (j + 4 < hi) {
        const FacetWalk& a = walks_[std::size_t(j + 4)];
        prefetch_cell(a.c->neighbor(a.i));
        for (int q = 1; q < 4; ++q) __builtin_prefetch(&*a.c->vertex((a.i + q) & 3));
      }
      FacetWalk& w = walks_[std::size_t(j)];
      w.step = kSteps;
      Ch c = w.c, n = c->neighbor(w.i);
      if (tr_.is_infinite(c) || tr_.is_infinite(n)) continue;
      bool corner = false;  // a bounding-box corner: outside, in 0
      for (int q = 1; q < 4; ++q) corner = corner || c->vertex((w.i + q) & 3)->info() < 0;
      if (corner) continue;
      const std::int32_t ends[2] = {c->info().label, n->info().label};
      const Vec3 &a = c->info().centre, &b = n->info().centre;
      f_.brackets(a, b, br, o_.step, 0, ends);
      if (br.empty()) continue;
      if (br.size() >= 2 || ends[0] == ends[1]) {
        w.step = kVorEdge;
        w.first = f_.place(a, b, br.front()), w.last = f_.place(a, b, br.back());
        continue;
      }
      // One change: placed (the bisection) only when the facet needs its
      // surface centre wherever between the two samples it lies.
      w.step = facet_step(c, w.i, on_edge(a, b, br[0].t0), on_edge(a, b, br[0].t1));
      if (w.step == kSteps) continue;
      w.first = w.last = f_.place(a, b, br[0]);
      if (w.step == kDistance) w.step = facet_step(c, w.i, on_edge(a, b, w.first), on_edge(a, b, w.first));
    }
  });
  for (const FacetWalk& w : walks_)
    if (w.step != kSteps) check_facet(w);
}

// What a restricted facet (c, i) whose Voronoi edge lambda changes along
// once needs, its surface centre given as x0 = x1, or as two points of the
// edge that it lies between (each coordinate of on_edge() is monotone in
// t): kOffSurface, kQuality, kDistance (the bound fails somewhere between
// them), kSteps (nothing, anywhere between them).
int Mesher::facet_step(Ch c, int i, const Vec3& x0, const Vec3& x1) const {
  const auto v = facet_vertices(c, i);
  // A vertex off the interfaces (a cell's circumcentre, seg2tet): the
  // facet's surface centre goes in, so every surface vertex lies on one.
  if (!on_surface_[std::size_t(v[0]->info())] || !on_surface_[std::size_t(v[1]->info())] ||
      !on_surface_[std::size_t(v[2]->info())])
    return kOffSurface;
  const Vec3 p0 = vec(v[0]->point()), p1 = vec(v[1]->point()), p2 = vec(v[2]->point());
  if (radius_edge_ratio(p0, p1, p2) > o_.ratio) return kQuality;
  return beyond_distance(p0, p1, p2, x0, x1, o_.max_distance) ? kDistance : kSteps;
}

// The candidate of a facet that needs one (walk_facets): VorEdge its
// change farthest from the facet's first vertex, else its surface centre.
void Mesher::check_facet(const FacetWalk& w) {
  Ch c = w.c, n = c->neighbor(w.i);
  const Vec3 a = centre(c), b = centre(n);
  const Vec3 p0 = vec(facet_vertices(c, w.i)[0]->point());
  Candidate cand;
  cand.cell = c, cand.facet = w.i;
  cand.cells = {c->info().uid, n->info().uid};
  cand.step = w.step;
  if (w.step == kVorEdge) {
    const Vec3 first = on_edge(a, b, w.first), last = on_edge(a, b, w.last);
    cand.x = dist2(first, p0) >= dist2(last, p0) ? first : last;
    cand.priority = dist2(cand.x, p0);
    topology_.push_back(cand);
    return;
  }
  cand.x = on_edge(a, b, w.first);
  cand.priority = dist2(cand.x, p0);
  quality_.push_back(cand);
}

// TopoDisk per label at v: for each label around v (not all one), the
// facets between its cells and the others' form one cycle in v's link.
void Mesher::check_vertex(Vh v) {
  star(v, cells_);
  labels_.clear();  // each label once (a few, not a sort of every cell's)
  for (Ch c : cells_)
    if (std::find(labels_.begin(), labels_.end(), label(c)) == labels_.end()) labels_.push_back(label(c));
  const bool one = labels_.size() == 1;
  if (v->info() >= 0) inner_[std::size_t(v->info())] = one ? labels_[0] : kUnknown;
  if (one) return;
  std::sort(labels_.begin(), labels_.end());
  for (std::int32_t l : labels_) {
    link_.clear();
    other_.clear();
    for (Ch c : cells_) {
      if (label(c) != l) continue;
      const int iv = c->index(v);
      for (int j = 0; j < 4; ++j) {
        if (j == iv || label(c->neighbor(j)) == l) continue;
        LinkEdge e;
        int m = 0;
        for (int q = 0; q < 4; ++q)
          if (q != j && q != iv) e[std::size_t(m++)] = link_name(reinterpret_cast<std::intptr_t>(&*c->vertex(q)), corners_);
        link_.push_back(e);
        other_.push_back(label(c->neighbor(j)));
      }
    }
    // Each label's facets around v one disk, and within it each pair's
    // facets one fan: a patch that comes back to v after other patches
    // is two fans there (the mesh's patch pinched or split where K(X)'s
    // is not, on a tiny patch: the curves sampled too coarsely).
    const bool cycle = one_cycle(link_, at_);
    // Two labels: one pair, so one fan (split_pair has nothing to find);
    // the other label's facets around v are these.
    if (cycle && labels_.size() == 2) return;
    std::int32_t pair = kUnknown;
    if (cycle && (pair = split_pair(link_, other_, at_, seq_)) == kUnknown) continue;
    // The surface centre of v's largest restricted facet with l on a side
    // (of the pair l|pair when that is what failed).
    Candidate best;
    best.priority = -1;
    for (Ch c : cells_) {
      if (label(c) != l) continue;
      const int iv = c->index(v);
      for (int j = 0; j < 4; ++j) {
        if (j == iv || label(c->neighbor(j)) == l) continue;
        if (pair != kUnknown && label(c->neighbor(j)) != pair) continue;
        // The ball's radius along the Voronoi edge at most the larger of
        // its ends' (both circumballs through v): no larger one, no walk.
        const Ch n = c->neighbor(j);
        if (tr_.is_infinite(c) || tr_.is_infinite(n)) continue;
        const Vec3 p = vec(v->point());
        if (std::max(dist2(centre(c), p), dist2(centre(n), p)) * (1 + 1e-9) < best.priority) continue;
        Vec3 x;
        if (!surface_centre(c, j, x)) continue;
        const double r2 = dist2(x, p);
        if (r2 > best.priority) {
          best.x = x, best.priority = r2, best.cell = c, best.facet = j;
          best.cells = {c->info().uid, c->neighbor(j)->info().uid};
        }
      }
    }
    if (best.priority >= 0) {
      best.step = pair == kUnknown ? kTopoDisk : kPatchFan;
      topology_.push_back(best);
    }
    return;
  }
}

// Each link vertex in two link edges, the edges one closed walk. at: per
// link vertex its two (vertex, edge) entries, sorted (split_pair's too).
bool Mesher::one_cycle(const std::vector<LinkEdge>& link, std::vector<LinkEdge>& at) {
  if (link.size() < 3) return false;
  at.clear();
  for (std::size_t e = 0; e < link.size(); ++e)
    for (int s = 0; s < 2; ++s) at.push_back({link[e][std::size_t(s)], std::intptr_t(e)});
  std::sort(at.begin(), at.end());
  for (std::size_t i = 0; i < at.size(); i += 2)
    if (at[i + 1][0] != at[i][0] || (i + 2 < at.size() && at[i + 2][0] == at[i][0])) return false;
  // The walk from link[0][0] along link[0], each step to the vertex's other
  // neighbour, back to link[0][0] after every edge.
  std::intptr_t prev = link[0][0], cur = link[0][1];
  std::size_t steps = 1;
  while (cur != link[0][0]) {
    const LinkEdge* a = &*std::lower_bound(at.begin(), at.end(), LinkEdge{cur, -1});
    auto other_end = [&](std::intptr_t e) { return link[std::size_t(e)][0] == cur ? link[std::size_t(e)][1] : link[std::size_t(e)][0]; };
    const std::intptr_t n0 = other_end(a[0][1]), n1 = other_end(a[1][1]);
    const std::intptr_t next = n0 == prev ? n1 : n0;
    prev = cur, cur = next;
    if (++steps > link.size()) return false;
  }
  return steps == link.size();
}

// The link's edges (one cycle: one_cycle's `at`) in cyclic order: a label
// of `other` (the label across each edge's facet) in two runs or more (the
// smallest such), else kUnknown.
std::int32_t Mesher::split_pair(const std::vector<LinkEdge>& link, const std::vector<std::int32_t>& other,
                                const std::vector<LinkEdge>& at, std::vector<std::int32_t>& seq) {
  seq.clear();
  std::size_t e = 0;
  std::intptr_t cur = link[0][1];
  for (std::size_t n = 0; n < link.size(); ++n) {
    seq.push_back(other[e]);
    const LinkEdge* a = &*std::lower_bound(at.begin(), at.end(), LinkEdge{cur, -1});
    e = std::size_t(a[0][1]) == e ? std::size_t(a[1][1]) : std::size_t(a[0][1]);
    cur = link[e][0] == cur ? link[e][1] : link[e][0];
  }
  std::vector<std::int32_t>& starts = seq;  // in place: each run's label once
  std::size_t m = 0;
  const std::int32_t last = seq.back();
  for (std::size_t i = 0; i < seq.size(); ++i)
    if (seq[i] != (i == 0 ? last : seq[i - 1])) starts[m++] = seq[i];
  starts.resize(m);
  std::sort(starts.begin(), starts.end());
  for (std::size_t i = 1; i < starts.size(); ++i)
    if (starts[i] == starts[i - 1]) return starts[i];
  return kUnknown;
}

// Still the facet it was found on (the same two cells)? Its cell still in
// use with its uid (uids are never reused; a freed cell keeps its info, a
// reused one is 0 until numbered) and the same neighbour across it: a
// stale one without a walk. cell: the one of its two cells is_facet finds,
// the insertion's start (a point on a facet, a flat patch's, gets its
// cells in an order that depends on it).
bool Mesher::current(const Candidate& c, Ch& cell) {
  cell = Ch();
  if (c.step == kVoxelSide) return true;
  if (!tr_.tds().cells().is_used(c.cell) || c.cell->info().uid != c.cells[0] ||
      c.cell->neighbor(c.facet)->info().uid != c.cells[1])
    return false;
  // is_facet(v[0], v[1], v[2])'s cell: the first of the two that v[0]'s
  // incident cells (their walk, star's) reach, the walk stopped there.
  cell = star(facet_vertices(c.cell, c.facet)[0], cells_, c.cell, c.cell->neighbor(c.facet));
  return true;
}

bool Mesher::insert_all(std::vector<Candidate>& cands) {
  std::stable_sort(cands.begin(), cands.end(),
                   [](const Candidate& a, const Candidate& b) { return a.priority > b.priority; });
  bool any = false;
  for (const Candidate& c : cands) {
    Ch near;
    const double gap = c.step == kTopoDisk || c.step == kPatchFan ? kTopologyGap * voxel_ : 0;
    if (current(c, near) && insert(c.x, c.step, near, gap * gap)) any = true;
  }
  cands.clear();
  return any;
}

void Mesher::refine() {
  for (;;) {
    ++passes_;
    // The cells made since the last pass (numbered now, from
    // fresh_first_ on); their facets, each once, and their vertices.
    // Every cell made since is incident to a vertex inserted since (an
    // insertion makes only cells at its vertex); the first pass takes all.
    fresh_first_ = uid_ + 1;
    fresh_.clear();
    auto take = [&](Ch c) {
      if (c->info().uid != 0) return;
      c->info().uid = ++uid_;
      if (!tr_.is_infinite(c)) fresh_.push_back(c);
    };
    if (passes_ == 1) {
      for (auto c = tr_.all_cells_begin(); c != tr_.all_cells_end(); ++c) take(c);
    } else {
      for (Vh v : new_vertices_) {
        star(v, cells_);
        for (Ch c : cells_) take(c);
      }
    }
    new_vertices_.clear();
    touched_.clear();
    touched_mark_.resize(points_, 0);
    walks_.clear();
    for (Ch c : fresh_) {
      for (int i = 0; i < 4; ++i) {
        Ch n = c->neighbor(i);
        if (is_fresh(n) && n->info().uid < c->info().uid) continue;
        walks_.push_back({c, i, kSteps, 0, 0});
      }
      for (int i = 0; i < 4; ++i) {
        const int id = c->vertex(i)->info();
        if (id < 0 || touched_mark_[std::size_t(id)]) continue;
        touched_mark_[std::size_t(id)] = 1;  // each vertex once (the first pass: all)
        touched_.push_back({id, c->vertex(i)});
      }
    }
    walk_facets();
    // A vertex whose cells were all of one label at its last check, its
    // new cells (the fresh ones at it) of that label too: still one label,
    // nothing for check_vertex to do (seg2tet's cells inside a label).
    inner_.resize(points_, kUnknown);
    for (Ch c : fresh_)
      for (int i = 0; i < 4; ++i) {
        const int id = c->vertex(i)->info();
        if (id >= 0 && inner_[std::size_t(id)] != c->info().label) inner_[std::size_t(id)] = kUnknown;
      }
    // Checked in the order found (around each new vertex in turn: a
    // vertex's cells mostly the last ones walked, in cache; by id they were
    // cache misses), each check on its own; their candidates (one at most
    // a vertex) then put in the order of their vertices' ids: the same
    // candidates in the same order every run.
    const std::size_t first = topology_.size();
    candidate_ids_.clear();
    for (std::size_t k = 0; k < touched_.size(); ++k) {
      const auto& t = touched_[k];
      // The next vertices' first cells asked for ahead (their stars' walks
      // start there).
      if (k + 2 < touched_.size()) __builtin_prefetch(&*touched_[k + 2].second);
      if (k + 1 < touched_.size()) prefetch_cell(touched_[k + 1].second->cell());
      touched_mark_[std::size_t(t.first)] = 0;
      if (inner_[std::size_t(t.first)] != kUnknown) continue;
      check_vertex(t.second);
      if (topology_.size() > first + candidate_ids_.size()) candidate_ids_.push_back({t.first, candidate_ids_.size()});
    }
    order_by_id(topology_, first, candidate_ids_, by_id_);
    if (o_.progress)
      o_.progress("pass " + std::to_string(passes_) + ": " + std::to_string(points_) + " points; candidates: " +
                  std::to_string(topology_.size()) + " topology, " + std::to_string(quality_.size()) + " quality");
    if (max_hit_) break;
    // QUALITY's candidates wait while TOPOLOGY inserts: each was found
    // once (its facet fresh) and is dropped only when stale.
    if (!topology_.empty() && insert_all(topology_)) continue;
    if (!quality_.empty() && insert_all(quality_)) continue;
    if (!o_.voxel_sides) break;
    voxel_sides();
    if (sides_.empty() || !insert_all(sides_)) break;
  }
  if (!keep_lists_) return release_lists();
  for (auto* cands : {&topology_, &quality_, &sides_}) cands->clear();
}

// The first pass's lists (every cell's) and the candidates' (empty now,
// or past the point cap) not kept past REFINE, their pages given back
// before the certificate's.
void Mesher::release_lists() {
  std::vector<FacetWalk>().swap(walks_);
  std::vector<Ch>().swap(pending_);
  std::vector<Ch>().swap(fresh_);
  for (auto* cands : {&topology_, &quality_, &sides_}) std::vector<Candidate>().swap(*cands);
  release_free_memory();
}

// The facets in the order of their sorted vertex ids, the vertices
// numbered by first use: CGAL's storage order depends on addresses.
ConformingSurface Mesher::output() {
  ConformingSurface out;
  // Per vertex id its point's index (-1: none yet); the ids below 0 (the
  // bounding box's corners, one id for all; seg2tet --outside's) apart.
  std::vector<int> id(points_, -1);
  std::vector<std::pair<int, int>> negative;
  auto index = [&](Vh v) {
    const int i = v->info();
    int* at = nullptr;
    if (i >= 0) {
      at = &id[std::size_t(i)];
    } else {
      auto it = std::find_if(negative.begin(), negative.end(), [&](const std::pair<int, int>& e) { return e.first == i; });
      if (it == negative.end()) it = negative.insert(negative.end(), {i, -1});
      at = &it->second;
    }
    if (*at < 0) {
      *at = int(out.points.size());
      out.points.push_back(vec(v->point()));
    }
    return *at;
  };
  struct Face {
    std::array<int, 3> key;  // sorted ids
    std::array<Vh, 3> v;     // oriented
    std::array<std::int32_t, 2> pair;
  };
  std::vector<Face> faces;
  const auto orient = GT().orientation_3_object();
  for (auto f = tr_.finite_facets_begin(); f != tr_.finite_facets_end(); ++f) {
    Ch c = f->first;
    const int i = f->second;
    Ch n = c->neighbor(i);
    const std::int32_t lc = label(c), ln = label(n);
    if (lc == ln) continue;
    auto v = facet_vertices(c, i);
    // Out of behind (the higher label): the normal points away from the
    // behind cell's vertex opposite the facet.
    Ch behind = lc > ln ? c : n;
    Vh opposite = behind == c ? c->vertex(i) : n->vertex(n->index(c));
    if (orient(v[0]->point(), v[1]->point(), v[2]->point(), opposite->point()) == CGAL::POSITIVE)
      std::swap(v[1], v[2]);
    std::array<int, 3> key{v[0]->info(), v[1]->info(), v[2]->info()};
    std::sort(key.begin(), key.end());
    faces.push_back({key, v, {std::max(lc, ln), std::min(lc, ln)}});
  }
  std::sort(faces.begin(), faces.end(), [](const Face& a, const Face& b) { return a.key < b.key; });
  for (const Face& f : faces) {
    out.triangles.push_back({index(f.v[0]), index(f.v[1]), index(f.v[2])});
    out.pairs.push_back(f.pair);
  }
  std::copy(inserted_.begin(), inserted_.end(), out.inserted.begin());
  out.refused = refused_;
  out.passes = passes_;
  out.certificate_rounds = rounds_;
  out.max_points_hit = max_hit_;
  return out;
}

} // namespace conforming_detail

Json ConformingSurface::to_json() const {
  Json j = Json::object();
  j["points"] = points.size();
  j["triangles"] = triangles.size();
  Json ins = Json::object();
  for (int s = 0; s < conforming_detail::kSteps; ++s) ins[conforming_detail::kStepName[s]] = inserted[std::size_t(s)];
  j["points_inserted"] = ins;
  j["points_refused"] = refused;
  j["passes"] = passes;
  j["certificate_rounds"] = certificate_rounds;
  j["max_points_hit"] = max_points_hit;
  if (!tets.tets.empty()) {
    j["cell_rounds"] = cell_rounds;
    j["cell_rounds_exhausted"] = cell_rounds_exhausted;
    j["cell_points_exhausted"] = cell_points_exhausted;
    j["sliver_points"] = sliver_points;
    j["voxel_centres_checked"] = centres_checked;
    j["voxel_centres_wrong"] = centres_wrong;
  }
  if (box_volume > 0) {
    j["box_volume"] = box_volume;
    j["box_points"] = box_points;
    j["box_refused"] = box_refused;
    j["box_covered"] = box_covered;
  }
  return j;
}

ConformingSurface conforming_surface(const LabelFunction& lambda, const NarrowLabelImage& x, const InterfaceComplex& k,
                                     const ConformingOptions& options) {
  const Geometry& g = x.geometry();
  if (k.dimension != 3 || k.lattice != std::array<std::size_t, 3>{g.size[0] + 1, g.size[1] + 1, g.size[2] + 1})
    throw Error("internal: the interface complex is not the label image's");
  return conforming_detail::Mesher(lambda, x, k, options).run();
}

} // namespace imgmesh
