// seg2tet's cell stage of the mesher (tets.on): the labelled cells
// refined to the radius-edge, size and sliver bounds without crossing the
// surface, and the tetrahedra with their interfaces written out.
#include "conforming/mesher.hpp"

#include "mesh/located_cells.hpp"
#include "mesh/tet_mesh.hpp"
#include "util/hash.hpp"

#include <cmath>
#include <unordered_map>

namespace imgmesh {
namespace conforming_detail {

// How far a labelled cell is beyond R and S (0: within); slivers (only a
// small dihedral angle, none under 1e-3 voxel) below every other bad cell.
double Mesher::badness(Ch c, bool& sliver) {
  std::array<Vec3, 4> p;
  for (int i = 0; i < 4; ++i) p[std::size_t(i)] = vec(c->vertex(i)->point());
  const ConformingTetOptions& t = o_.tets;
  return refinement_badness(p, dist2(centre(c), p[0]), t.cell_ratio, t.size_of(label(c)), t.sliver_angle, 1e-3 * voxel_,
                            sliver);
}

// Still the cell it was (uids are never reused; a cell made since is 0
// until REFINE numbers it).
bool Mesher::alive(const BadCell& e) const {
  return tr_.tds().cells().is_used(e.c) && e.c->info().uid == e.uid;
}

// A sliver's encroached facet (c, i: surface centre x, ball radius^2 r2):
// x moved an eighth of the radius along the facet, in a direction drawn from
// the sliver's vertex ids, and back onto the interface along the facet's
// normal (the same two labels, one change, still in the ball); else x
// unchanged. Surface centres of a flat patch's lattice of seeds (four
// cocircular, a flat sliver) make a lattice half as fine, cocircular again:
// the centre refined each sliver into smaller ones down to the insertion
// floor (head2 at 128^3: 34,434 under 10 degrees in one voxel); off the
// centre the points are no lattice, and at least r/2 from every vertex
// (the ball is empty), the insertion radius the rounds' floor counts on.
void Mesher::off_centre(const std::array<Vh, 4>& v, Ch c, int i, double r2, Vec3& x) {
  const auto f = facet_vertices(c, i);
  const Vec3 p0 = vec(f[0]->point()), p1 = vec(f[1]->point()), p2 = vec(f[2]->point());
  Vec3 n = cross(sub(p1, p0), sub(p2, p0)), u = sub(p1, p0);
  const double nn = std::sqrt(dot(n, n)), uu = std::sqrt(dot(u, u));
  if (!(nn > 0) || !(uu > 0)) return;
  for (int m = 0; m < 3; ++m) n[m] /= nn, u[m] /= uu;
  const Vec3 w = cross(n, u);
  std::array<int, 4> id{v[0]->info(), v[1]->info(), v[2]->info(), v[3]->info()};
  std::sort(id.begin(), id.end());
  std::uint64_t h = 0x9e3779b97f4a7c15ull;  // splitmix64 over the ids
  for (int k : id) h = splitmix64(h + std::uint64_t(std::uint32_t(k)));
  const double angle = 2 * M_PI * unit01(h), r = std::sqrt(r2);
  Vec3 a, b;
  for (int m = 0; m < 3; ++m) {
    const double y = x[m] + r / 8 * (std::cos(angle) * u[m] + std::sin(angle) * w[m]);
    a[m] = y - r / 2 * n[m], b[m] = y + r / 2 * n[m];
  }
  const std::int32_t la = label(c), lb = label(c->neighbor(i));
  f_.changes(a, b, changes_, o_.step);
  if (changes_.size() != 1) return;
  const LabelFunction::Change& ch = changes_[0];
  if (!((ch.before == la && ch.after == lb) || (ch.before == lb && ch.after == la))) return;
  Vec3 y;
  for (int m = 0; m < 3; ++m) y[m] = a[m] + ch.t * (b[m] - a[m]);
  if (dist2(y, x) < r2 / 4) x = y;
}

// seg2tet --outside: B, the voxels' extent (half a voxel beyond the
// centres; an image whose axes are not the world's: the world box around
// it). X's outer layer is background (the repair grows the grid where a
// label touches its side), so every interface lies at least half a voxel
// inside B: implicit2tet's termination argument (mesh/box_refinement.hpp),
// and its insertion floor, an eighth of that.
Box Mesher::outside_box() const {
  Vec3 lo, hi;
  for (int c = 0; c < 8; ++c) {
    const Vec3 p = x_.world((c & 1) ? double(x_.size[0]) - 0.5 : -0.5, (c & 2) ? double(x_.size[1]) - 0.5 : -0.5,
                            (c & 4) ? double(x_.size[2]) - 0.5 : -0.5);
    for (int m = 0; m < 3; ++m) {
      lo[m] = c == 0 ? p[m] : std::min(lo[m], p[m]);
      hi[m] = c == 0 ? p[m] : std::max(hi[m], p[m]);
    }
  }
  return Box(lo, hi, voxel_ / 16);
}

// Shewchuk's boundary rule for a bad cell (tets.outside), given the
// conflict zone (zone_) of its circumcentre cc or, cc beyond B, of cc's
// projection onto B: cc beyond B, or encroaching a box subsegment or
// subfacet of the zone, splits the box instead (implicit2tet's rule,
// box_refinement.hpp). False when cc stays (in B, encroaching nothing);
// else inserted says whether the split went in.
bool Mesher::box_split(const Point& cc, bool beyond, bool& inserted) {
  inserted = false;
  const Box::Split s = box_->split_for(tr_, cc, zone_);
  if (!beyond && s.kind == Box::kNone) return false;
  // As a cell's point (off the interfaces: REFINE gives a restricted facet
  // at it its surface centre), counted as a box point.
  if ((s.kind == Box::kSegment || s.kind == Box::kFacet) && insert(s.x, kCell, s.near)) {
    --inserted_[kCell];
    ++box_points_;
    inserted = true;
  } else {
    ++box_refused_;
  }
  return true;
}

// Rounds of cell refinement (tets.on), REFINE after each: the bad
// labelled cells, worst first, each its circumcentre c or, when c lies in
// the surface Delaunay ball of a restricted facet (such a ball lies in
// the circumballs of the facet's cells, so the facet is one of c's
// conflict zone), that facet's surface centre: the surface is refined,
// never crossed.
void Mesher::refine_cells() {
  const ConformingTetOptions& t = o_.tets;
  const double floor2 = 1e-6 * voxel_ * voxel_;
  std::vector<BadCell> bad, left;
  // A cell's badness is its vertices' (its label and centre too): the bad
  // cells of a round are the last round's still there and those made since
  // (numbered after `seen`: REFINE numbers every cell); every cell is
  // numbered when the stage starts.
  std::uint32_t seen = 0;
  keep_lists_ = true;  // REFINE's lists kept between the rounds
  for (;;) {
    bad.clear();
    for (const BadCell& e : left)
      if (alive(e)) bad.push_back(e);
    for (auto c = tr_.finite_cells_begin(); c != tr_.finite_cells_end(); ++c) {
      if (c->info().uid <= seen || (label(c) == 0 && !box_)) continue;
      bool sliver;
      const double b = badness(c, sliver);
      if (b > 0) {
        BadCell e{b, c, c->info().uid, {c->vertex(0), c->vertex(1), c->vertex(2), c->vertex(3)}, {}, sliver};
        for (int i = 0; i < 4; ++i) e.id[std::size_t(i)] = e.v[std::size_t(i)]->info();
        std::sort(e.id.begin(), e.id.end());
        bad.push_back(e);
      }
    }
    seen = uid_;
    if (bad.empty() || cell_rounds_ >= t.max_rounds) {
      cell_rounds_exhausted_ = !bad.empty();
      break;
    }
    ++cell_rounds_;
    // Worst first; ties by the sorted vertex ids (not by address: the same
    // order every run).
    std::sort(bad.begin(), bad.end(),
              [](const BadCell& a, const BadCell& b) { return a.bad != b.bad ? a.bad > b.bad : a.id < b.id; });
    left.clear();
    bool any = false;
    for (const BadCell& e : bad) {
      if (cell_points_ >= t.max_cell_points) {
        cell_points_exhausted_ = true;
        break;
      }
      if (max_hit_) break;
      if (!alive(e)) continue;
      left.push_back(e);  // dropped next round unless it survives
      const Vec3 cc = centre(e.c);
      // --outside: cc beyond B, its projection's zone (cc's own would hold
      // every hull triangle cc sees).
      const bool beyond = box_ && !box_->contains(pt(cc));
      const Point q = beyond ? box_->project(pt(cc)) : pt(cc);
      Tr::Locate_type lt;
      int li, lj;
      const Ch at = locate_from(tr_, q, lt, li, lj, e.c);
      zone_.clear();
      if (lt == Tr::VERTEX) {
        if (!beyond) continue;
        tr_.incident_cells(at->vertex(li), std::back_inserter(zone_));
      } else {
        tr_.find_conflicts(q, at, CGAL::Emptyset_iterator(), std::back_inserter(zone_));
      }
      bool split;
      if (box_ && box_split(pt(cc), beyond, split)) {
        if (split) any = true, ++cell_points_;
        continue;
      }
      // A facet inside the zone once, from the cell of the smaller centre.
      in_zone_ = zone_;
      std::sort(in_zone_.begin(), in_zone_.end());
      double worst = 0;
      Vec3 wx{0, 0, 0};
      Ch wc;
      int wi = 0;
      for (Ch z : zone_)
        for (int i = 0; i < 4; ++i) {
          const Ch n = z->neighbor(i);
          if (label(z) == label(n) || tr_.is_infinite(z) || tr_.is_infinite(n)) continue;
          if (centre(n) < centre(z) && std::binary_search(in_zone_.begin(), in_zone_.end(), n)) continue;
          // The surface ball no larger than the larger circumball (both
          // through the facet's vertices): a smaller one than the worst
          // so far without the walk.
          const Vec3 p = vec(z->vertex((i + 1) & 3)->point());
          if (std::max(dist2(centre(z), p), dist2(centre(n), p)) * (1 + 1e-9) < worst) continue;
          Vec3 x;
          if (!surface_centre(z, i, x)) continue;
          const double r2 = dist2(x, p);
          if (r2 > worst && dist2(cc, x) < r2) worst = r2, wx = x, wc = z, wi = i;
        }
      bool ok;
      if (worst > 0) {
        if (e.sliver && worst >= floor2) off_centre(e.v, wc, wi, worst, wx);
        ok = worst >= floor2 && insert(wx, kCellFacet, wc);
      } else {
        ok = insert(cc, kCell, at);
        sliver_points_ += ok && e.sliver;
      }
      if (ok) {
        any = true;
        ++cell_points_;
      }
    }
    if (!any || max_hit_ || cell_points_exhausted_) break;
    refine();
  }
  keep_lists_ = false;
  release_lists();
}

// The labelled cells and the interfaces (tets.on), and every voxel
// centre located: those in a cell of another label.
void Mesher::tets_output(ConformingSurface& out) {
  std::unordered_map<int, int> id;
  TetMesh& m = out.tets;
  auto index = [&](Vh v) {
    auto [it, added] = id.try_emplace(v->info(), int(m.points.size()));
    if (added) m.points.push_back(vec(v->point()));
    return it->second;
  };
  // Cells by label, then by their sorted vertex ids; the interfaces
  // likewise (CGAL's storage order depends on addresses).
  auto key = [](std::int32_t l, std::array<Vh, 4> v, int n) {
    std::array<int, 5> k{int(l), 0, 0, 0, 0};
    for (int i = 0; i < n; ++i) k[std::size_t(i + 1)] = v[std::size_t(i)]->info();
    std::sort(k.begin() + 1, k.begin() + 1 + n);
    return k;
  };
  std::vector<std::pair<std::array<int, 5>, std::array<Vh, 4>>> cells, faces;
  for (auto c = tr_.finite_cells_begin(); c != tr_.finite_cells_end(); ++c) {
    if (label(c) == 0 && !box_) continue;
    const std::array<Vh, 4> v{c->vertex(0), c->vertex(1), c->vertex(2), c->vertex(3)};  // positively oriented
    cells.emplace_back(key(label(c), v, 4), v);
  }
  const auto orient = GT().orientation_3_object();
  for (auto f = tr_.finite_facets_begin(); f != tr_.finite_facets_end(); ++f) {
    const Ch c = f->first, n = c->neighbor(f->second);
    if (box_ && (tr_.is_infinite(c) || tr_.is_infinite(n))) {  // on B: a box face of region 0
      const Ch side = tr_.is_infinite(c) ? n : c;
      const int i = side == c ? f->second : n->index(c);
      std::array<Vh, 4> v{side->vertex((i + 1) & 3), side->vertex((i + 2) & 3), side->vertex((i + 3) & 3), Vh()};
      if (orient(v[0]->point(), v[1]->point(), v[2]->point(), side->vertex(i)->point()) == CGAL::POSITIVE)
        std::swap(v[1], v[2]);
      faces.emplace_back(key(label(side), v, 3), v);  // front 0: {0, 0}, B's
      continue;
    }
    if (label(c) == label(n)) continue;
    // Once, of the higher label (never 0), oriented out of it: the normal
    // points away from its vertex opposite the facet.
    const Ch side = label(c) > label(n) ? c : n;
    const int i = side == c ? f->second : n->index(c);
    std::array<Vh, 4> v{side->vertex((i + 1) & 3), side->vertex((i + 2) & 3), side->vertex((i + 3) & 3), Vh()};
    if (orient(v[0]->point(), v[1]->point(), v[2]->point(), side->vertex(i)->point()) == CGAL::POSITIVE)
      std::swap(v[1], v[2]);
    auto k = key(label(side), v, 3);
    k[4] = int(std::min(label(c), label(n)));  // the front label, after the ids
    faces.emplace_back(k, v);
  }
  auto by_key = [](const auto& a, const auto& b) { return a.first < b.first; };
  std::sort(cells.begin(), cells.end(), by_key);
  std::sort(faces.begin(), faces.end(), by_key);
  for (const auto& [k, v] : cells) {
    m.tets.push_back({index(v[0]), index(v[1]), index(v[2]), index(v[3])});
    m.tet_region.push_back(k[0]);
  }
  for (const auto& [k, v] : faces) {
    m.triangles.push_back({index(v[0]), index(v[1]), index(v[2])});
    m.triangle_region.push_back(k[0]);
    m.triangle_pair.push_back({k[0], k[4]});
  }
  out.cell_rounds = cell_rounds_;
  out.cell_rounds_exhausted = cell_rounds_exhausted_;
  out.cell_points_exhausted = cell_points_exhausted_;
  out.sliver_points = sliver_points_;
  out.max_points_hit = max_hit_;  // the cap may refuse a cell's point after the last output()
  if (box_) box_output(out);
  // Every voxel centre: in a cell of its voxel's label (on a facet, edge
  // or vertex of the triangulation: every cell there).
  // Each walk starts at the cell of the centre before it, a row's first at
  // the previous row's first, a slice's at the previous slice's.
  Ch slice = hint_, row, hint;
  for (std::size_t k = 0; k < x_.size[2]; ++k)
    for (std::size_t j = 0; j < x_.size[1]; ++j)
      for (std::size_t i = 0; i < x_.size[0]; ++i) {
        const std::int32_t own = voxel_label(std::ptrdiff_t(i), std::ptrdiff_t(j), std::ptrdiff_t(k));
        Tr::Locate_type lt;
        int li, lj;
        const Ch start = i > 0 ? hint : j > 0 ? row : slice;
        const Ch c = locate_from(tr_, pt(voxel_centre(std::ptrdiff_t(i), std::ptrdiff_t(j), std::ptrdiff_t(k))), lt, li, lj, start);
        hint = c;
        if (i == 0) {
          row = c;
          if (j == 0) slice = c;
        }
        located_cells(tr_, c, lt, li, lj, cells_);
        bool wrong = false;
        for (Ch n : cells_) wrong = wrong || label(n) != own;
        ++out.centres_checked;
        out.centres_wrong += wrong;
      }
}

// tets.outside: B's volume and points, and whether the box triangles (the
// region-0 triangles with pair {0, 0}) lie on B's faces (exactly: box
// points carry B's coordinates) and add up to its area.
void Mesher::box_output(ConformingSurface& out) {
  const Vec3 &lo = box_->lo(), &hi = box_->hi();
  const double a = hi[0] - lo[0], b = hi[1] - lo[1], c = hi[2] - lo[2];
  out.box_volume = a * b * c;
  out.box_points = box_points_;
  out.box_refused = box_refused_;
  const TetMesh& m = out.tets;
  double area = 0;
  bool on = true;
  for (std::size_t t = 0; t < m.triangles.size(); ++t) {
    if (m.triangle_pair[t] != std::array<int, 2>{0, 0}) continue;
    const Vec3 &p = m.points[std::size_t(m.triangles[t][0])], &q = m.points[std::size_t(m.triangles[t][1])],
               &r = m.points[std::size_t(m.triangles[t][2])];
    on = on && box_->on_face(p, q, r);
    const Vec3 n = cross(sub(q, p), sub(r, p));
    area += std::sqrt(dot(n, n)) / 2;
  }
  out.box_covered = on && std::abs(area - 2 * (a * b + b * c + c * a)) <= 1e-9 * area;
}

} // namespace conforming_detail
} // namespace imgmesh
