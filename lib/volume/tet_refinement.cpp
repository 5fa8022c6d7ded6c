#include "volume/tet_refinement.hpp"

#include "surface/delmesh.hpp"
#include "mesh/box_refinement.hpp"
#include "surface/mesher_options.hpp"
#include "util/error.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <optional>
#include <queue>

namespace imgmesh {

using namespace surface_detail;

namespace {

struct VertexId {
  int operator()(Vh v) const { return v->info().id; }
};
using Box = BoxRefinement<Tr, VertexId>;

double d2(const Point& a, const Point& b) { return CGAL::to_double(CGAL::squared_distance(a, b)); }

// One round of cell refinement, run by DELMESH once the certificate holds,
// round after round with REFINE between (DelMesh::set_after_certificate).
class CellRefinement {
public:
  CellRefinement(const SurfaceSampler& f, const TetRefinementOptions& opt, const Box* box)
      : f_(f), opt_(opt), box_(box), guard_(1e-3 * f.grid().delta) {}

  // Which side of S a local point is on (SurfaceSampler::inside_at).
  bool inside(const Point& p) const { return f_.inside_at(vec(p)); }

  // How far a finite cell is beyond the bounds (0: within them); slivers
  // (only a small dihedral angle) come after every other bad cell.
  double badness(Ch c, const Point& cc, bool& sliver) const {
    std::array<std::array<double, 3>, 4> p;
    for (int i = 0; i < 4; ++i) p[std::size_t(i)] = vec(c->vertex(i)->point());
    // Slivers under 1e-3 voxel are left: their circumcentres have no other
    // floor (box_refinement.hpp, termination).
    const double bad = refinement_badness(p, d2(cc, c->vertex(0)->point()), opt_.cell_ratio, opt_.cell_size,
                                          opt_.sliver_angle, guard_, sliver);
    if (bad == 0) return 0;
    // --outside: every cell is meshed.
    if (box_) return bad;
    return inside(cc) ? bad : 0;
  }

  bool operator()(DelMesh& dm) {
    if (box_ && !corners_in_) {  // once the surface is certified: the hull becomes B
      corners_in_ = true;
      bool any = false;
      for (const Vec3& x : box_->corners())
        if (dm.insert(x, kBox)) {
          ++box_points;
          any = true;
        }
      return any;
    }
    if (points_exhausted) return false;
    if (rounds >= opt_.max_rounds) {
      exhausted = true;
      return false;
    }
    ++rounds;
    const auto t0 = std::chrono::steady_clock::now();
    const bool any = off_surface_facets(dm) | refine_cells(dm);
    seconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    return any;
  }

  int rounds = 0;
  bool exhausted = false, points_exhausted = false, corners_in_ = false;
  long long volume_points = 0, facet_points = 0, off_surface_points = 0, refused = 0, sliver_points = 0;
  long long box_points = 0, box_refused = 0;
  long long points() const { return volume_points + facet_points + off_surface_points + box_points; }
  double seconds = 0;

private:
  struct Entry {
    double bad;
    std::uint64_t seq;
    Ch c;
    std::array<Vh, 4> v;
    Point cc;  // c's circumcentre (a cell keeps none)
    bool sliver;
    bool operator<(const Entry& o) const { return bad != o.bad ? bad < o.bad : seq > o.seq; }
  };

  void push_if_bad(const Tr& tr, Ch c) {
    if (!tr.is_infinite(c)) push_if_bad(c, c->circumcenter());
  }
  void push_if_bad(Ch c, const Point& cc) {
    bool sliver;
    const double bad = badness(c, cc, sliver);
    if (bad > 0) queue_.push({bad, seq_++, c, {c->vertex(0), c->vertex(1), c->vertex(2), c->vertex(3)}, cc, sliver});
  }
  // The entry's cell is still in the triangulation.
  static bool alive(const Tr& tr, const Entry& e) {
    if (!tr.tds().cells().is_used(e.c)) return false;
    for (int i = 0; i < 4; ++i)
      if (e.c->vertex(i) != e.v[std::size_t(i)]) return false;
    return true;
  }
  // The cells at the vertex just inserted, and their centres: DELMESH's.
  void push_around(const DelMesh& dm) {
    for (Ch c : dm.new_cells())
      if (!dm.triangulation().is_infinite(c)) {
        const Vec3 x = dm.new_cell_centre(c);
        push_if_bad(c, Point(x[0], x[1], x[2]));
      }
  }

  // A restricted facet with a vertex inserted off S (a cell or box point
  // whose Voronoi cell reached S): its surface centre goes in, so that
  // every vertex of the surface lies on S. Points within half their facet's
  // radius of one inserted in this pass wait for the next; balls under
  // 1e-3 voxel are left (the insertion floor of box_refinement.hpp).
  bool off_surface_facets(DelMesh& dm) {
    const Tr& tr = dm.triangulation();
    const double guard2 = guard_ * guard_;
    std::vector<std::pair<double, Vec3>> todo;
    for (auto it = tr.finite_facets_begin(); it != tr.finite_facets_end(); ++it) {
      const FacetInfo& fi = it->first->facet[it->second];
      if (!(fi.state & kRestricted) || fi.r2 < guard2) continue;
      for (int m = 1; m < 4; ++m)
        if (!on_surface(it->first->vertex((it->second + m) & 3)->info().origin)) {
          todo.emplace_back(fi.r2, Vec3{fi.x[0], fi.x[1], fi.x[2]});
          break;
        }
    }
    std::sort(todo.begin(), todo.end(), [](const auto& a, const auto& b) { return a.first > b.first; });
    bool any = false;
    for (const auto& [r2, x] : todo) {
      if (cap_reached()) break;
      const Point p(x[0], x[1], x[2]);
      const Vh nv = tr.nearest_vertex(p);
      if (d2(p, nv->point()) < r2 / 4) continue;
      if (dm.insert(x, kQuality)) {
        ++off_surface_points;
        any = true;
      } else ++refused;
    }
    return any;
  }

  // The first round scans every cell; a later one only the cells made
  // since the last round's queue ran dry (each at a vertex inserted since:
  // the others were not bad then) and the cells that round passed over.
  bool refine_cells(DelMesh& dm) {
    const Tr& tr = dm.triangulation();
    if (scanned_ == 0) {
      for (auto c = tr.finite_cells_begin(); c != tr.finite_cells_end(); ++c) push_if_bad(tr, c);
    } else {
      const int first = int(scanned_);
      for (std::size_t id = scanned_; id < dm.vertices().size(); ++id) {
        if (dm.vertices()[id] == Vh()) continue;
        cells_.clear();
        tr.incident_cells(dm.vertices()[id], std::back_inserter(cells_));
        for (Ch c : cells_) {  // once, from its first new vertex
          bool first_new = true;
          for (int i = 0; i < 4; ++i) {
            const Vh w = c->vertex(i);
            first_new = first_new && (tr.is_infinite(w) || w->info().id < first || w->info().id >= int(id));
          }
          if (first_new) push_if_bad(tr, c);
        }
      }
      for (const Entry& e : passed_) queue_.push(e);
      passed_.clear();
    }
    const double guard2 = guard_ * guard_;
    bool any = false;
    while (!queue_.empty() && !cap_reached()) {
      const Entry e = queue_.top();
      queue_.pop();
      if (!alive(tr, e)) continue;
      const Point cc = e.cc;
      Tr::Locate_type lt;
      int li, lj;
      // --outside, c beyond B: the box is split near c's projection onto B
      // (c's own conflict zone would hold every hull triangle c sees).
      const bool beyond = box_ && !box_->contains(cc);
      const Point q = beyond ? box_->project(cc) : cc;
      const Ch at = tr.locate(q, lt, li, lj, e.c);
      zone_.clear();
      if (lt == Tr::VERTEX) {
        if (!beyond) {
          passed_.push_back(e);
          continue;
        }
        tr.incident_cells(at->vertex(li), std::back_inserter(zone_));
      } else {
        // The facets whose surface Delaunay ball holds cc are facets of
        // cells in conflict with cc (such a ball lies in the circumballs of
        // the facet's two cells).
        tr.find_conflicts(q, at, CGAL::Emptyset_iterator(), std::back_inserter(zone_));
      }
      // --outside: c outside B or encroaching the box: the box is split
      // instead (box_refinement.hpp), for slivers too (measured on the
      // bunny at a quarter voxel: 154 slivers left, all in region 2 and
      // mostly at the box, when they did not; none when they do).
      if (box_) {
        const Box::Split split = box_->split_for(tr, cc, zone_);
        if (beyond || split.kind != Box::kNone) {
          if (split.kind != Box::kSegment && split.kind != Box::kFacet) {
            ++box_refused;
            passed_.push_back(e);
            continue;
          }
          if (!dm.insert(split.x, kBox, Facet(split.near, 0))) {
            ++refused;
            passed_.push_back(e);
            if (tr.number_of_vertices() >= opt_.surface.max_points) break;
            continue;
          }
          ++box_points;
          any = true;
          push_around(dm);
          // A split off the cell's circumball leaves it: it asks again.
          if (alive(tr, e)) push_if_bad(e.c, e.cc);
          continue;
        }
      }
      Facet worst(Ch(), 0);
      double worst_r2 = 0;
      for (Ch c : zone_)
        for (int i = 0; i < 4; ++i) {
          const FacetInfo& fi = c->facet[i];
          if (!(fi.state & kRestricted) || fi.r2 <= worst_r2) continue;
          if (d2(cc, Point(fi.x[0], fi.x[1], fi.x[2])) < fi.r2) {
            worst = Facet(c, i);
            worst_r2 = fi.r2;
          }
        }
      bool ok;
      if (worst.first != Ch()) {
        const FacetInfo& fi = worst.first->facet[worst.second];
        ok = fi.r2 >= guard2 && dm.insert(Vec3{fi.x[0], fi.x[1], fi.x[2]}, kQuality, worst);
        facet_points += ok;
      } else {
        ok = dm.insert(vec(cc), kVolume, Facet(at, 0));
        volume_points += ok;
        sliver_points += ok && e.sliver;
      }
      if (!ok) {
        ++refused;
        passed_.push_back(e);
        if (tr.number_of_vertices() >= opt_.surface.max_points) break;
        continue;
      }
      any = true;
      push_around(dm);
      // So does one left by its encroached facet's surface centre.
      if (alive(tr, e)) push_if_bad(e.c, e.cc);
    }
    scanned_ = dm.vertices().size();
    return any;
  }

  // --max-cell-points: the cap on the points of cell refinement.
  bool cap_reached() {
    if (points() >= opt_.max_cell_points) points_exhausted = true;
    return points_exhausted;
  }

  const SurfaceSampler& f_;
  const TetRefinementOptions& opt_;
  const Box* box_;
  // No sliver or facet point below 1e-3 voxel (the insertion floor of
  // box_refinement.hpp's termination argument).
  const double guard_;
  std::priority_queue<Entry> queue_;
  std::uint64_t seq_ = 0;
  std::size_t scanned_ = 0;    // vertices when the last round's queue ran dry
  std::vector<Entry> passed_;  // cells the last round passed over (refused)
  std::vector<Ch> cells_, zone_;
};

// The cells whose circumcentre lies inside (region 1) and, with --outside,
// every other finite cell (region 2), positively oriented in world
// coordinates; the boundary triangles: region 1's, then (--outside) the
// box's; whether region 1's boundary is the set of restricted facets and
// the box's lies on B.
void extract(const DelMesh& dm, const CellRefinement& inside, const Box* box, const ImplicitSurface& surface,
             TetRefinementResult& r) {
  const Tr& tr = dm.triangulation();
  std::vector<int> index(dm.vertices().size(), -1);
  std::vector<int> id_of;  // output vertex -> triangulation id
  auto out = [&](Vh v) {
    int& k = index[std::size_t(v->info().id)];
    if (k < 0) {
      k = int(id_of.size());
      id_of.push_back(v->info().id);
      r.mesh.points.push_back(surface.to_world(vec(v->point())));
    }
    return k;
  };
  // Cells by region, then in the order of their sorted vertex ids (CGAL's
  // storage order depends on addresses; the files keep regions in blocks).
  struct Cell {
    int region;
    std::array<int, 4> sorted, ids;  // the sort key; the ids in CGAL's (positive) order
  };
  std::vector<Cell> cells;
  for (auto c = tr.finite_cells_begin(); c != tr.finite_cells_end(); ++c) {
    const int region = inside.inside(c->circumcenter()) ? 1 : 2;
    if (region == 2 && !box) continue;
    const std::array<int, 4> ids{c->vertex(0)->info().id, c->vertex(1)->info().id, c->vertex(2)->info().id, c->vertex(3)->info().id};
    std::array<int, 4> sorted = ids;
    std::sort(sorted.begin(), sorted.end());
    cells.push_back({region, sorted, ids});
  }
  std::sort(cells.begin(), cells.end(), [](const Cell& a, const Cell& b) {
    return a.region != b.region ? a.region < b.region : a.sorted < b.sorted;
  });
  const bool flip = surface.reflects();
  for (const auto& [region, sorted, ids] : cells) {
    std::array<int, 4> t;
    for (int i = 0; i < 4; ++i) t[std::size_t(i)] = out(dm.vertices()[std::size_t(ids[std::size_t(i)])]);
    if (flip) std::swap(t[2], t[3]);
    r.mesh.tets.push_back(t);
    r.mesh.tet_region.push_back(region);
  }
  r.mesh.triangles = tet_boundary(r.mesh, 1);
  const std::size_t surface_triangles = r.mesh.triangles.size();
  r.mesh.triangle_region.assign(surface_triangles, 1);
  if (box) {
    // The box faces: on B, and their areas add up to B's.
    const Vec3 &lo = box->lo(), &hi = box->hi();
    double area = 0;
    r.box_covered = true;
    for (const auto& t : tet_boundary(r.mesh)) {
      r.mesh.triangles.push_back(t);
      r.mesh.triangle_region.push_back(2);
      Vec3 p[3];
      for (int k = 0; k < 3; ++k) p[k] = vec(dm.vertices()[std::size_t(id_of[std::size_t(t[std::size_t(k)])])]->point());
      bool on_face = false;
      for (int i = 0; i < 3; ++i)
        for (double b : {lo[i], hi[i]}) on_face = on_face || (p[0][i] == b && p[1][i] == b && p[2][i] == b);
      r.box_covered = r.box_covered && on_face;
      const Vec3 u{p[1][0] - p[0][0], p[1][1] - p[0][1], p[1][2] - p[0][2]}, v{p[2][0] - p[0][0], p[2][1] - p[0][1], p[2][2] - p[0][2]};
      area += std::sqrt(std::pow(u[1] * v[2] - u[2] * v[1], 2) + std::pow(u[2] * v[0] - u[0] * v[2], 2) +
                        std::pow(u[0] * v[1] - u[1] * v[0], 2)) / 2;
    }
    const double a = hi[0] - lo[0], b = hi[1] - lo[1], c = hi[2] - lo[2];
    r.box_volume = a * b * c;
    r.box_covered = r.box_covered && std::abs(area - 2 * (a * b + b * c + c * a)) <= 1e-9 * area;
  }

  std::vector<std::array<int, 3>> restricted, boundary;
  for (auto it = tr.finite_facets_begin(); it != tr.finite_facets_end(); ++it)
    if (it->first->facet.restricted(it->second)) {
      std::array<int, 3> k;
      for (int m = 1; m < 4; ++m) k[std::size_t(m - 1)] = it->first->vertex((it->second + m) & 3)->info().id;
      std::sort(k.begin(), k.end());
      restricted.push_back(k);
    }
  for (std::size_t i = 0; i < surface_triangles; ++i) {
    const auto& t = r.mesh.triangles[i];
    std::array<int, 3> k{id_of[std::size_t(t[0])], id_of[std::size_t(t[1])], id_of[std::size_t(t[2])]};
    std::sort(k.begin(), k.end());
    boundary.push_back(k);
  }
  // As sets (each list is free of repeats: a facet is visited once, and
  // tet_boundary lists a face once).
  std::sort(restricted.begin(), restricted.end());
  std::sort(boundary.begin(), boundary.end());
  r.boundary_is_surface = restricted == boundary;
}

} // namespace

TetRefinementResult tetrahedral_mesh(const ImplicitSurface& surface, const TetRefinementOptions& opt) {
  check_options(opt.surface);
  // Shewchuk's and Oudot-Rineau-Yvinec's termination needs R >= 2 (below,
  // refinement can cascade without end); 1 would not be a bound at all.
  if (!(opt.cell_ratio >= 2) || !std::isfinite(opt.cell_ratio)) throw UsageError("--cell-ratio must be at least 2");
  if (!(opt.cell_size >= 0) || !std::isfinite(opt.cell_size)) throw UsageError("--cell-size must be >= 0");
  if (!(opt.sliver_angle >= 0 && opt.sliver_angle < 30)) throw UsageError("--sliver-angle must be in [0, 30) degrees");

  if (opt.max_cell_points < 1) throw UsageError("--max-cell-points must be at least 1");

  DelMesh dm(surface, opt.surface);
  // --outside: B is the image extent, the voxels' boxes around the samples
  // (box_refinement.hpp says why it is half a voxel from S at least).
  std::optional<Box> box;
  if (opt.outside) {
    const CubeGrid& g = dm.grid();
    const double gap = std::min({g.s[0], g.s[1], g.s[2]}) / 2;
    box.emplace(Vec3{-g.s[0] / 2, -g.s[1] / 2, -g.s[2] / 2}, Vec3{g.hi[0] + g.s[0] / 2, g.hi[1] + g.s[1] / 2, g.hi[2] + g.s[2] / 2},
                gap / 8);
  }
  CellRefinement cells(dm.sampler(), opt, box ? &*box : nullptr);
  dm.set_after_certificate([&](DelMesh& m) { return cells(m); });
  TetRefinementResult r;
  r.surface = dm.run();
  r.outside = opt.outside;
  extract(dm, cells, box ? &*box : nullptr, surface, r);
  const std::vector<std::array<int, 3>> region1(r.mesh.triangles.begin(),
                                                r.mesh.triangles.begin() + std::count(r.mesh.triangle_region.begin(), r.mesh.triangle_region.end(), 1));

  r.quality = tet_quality(r.mesh);
  r.conformity = tet_conformity(r.mesh);
  r.boundary_certificate =
      certify_surface(r.mesh.points, region1, surface.samples(), r.surface.expected_boundary, r.surface.expected);
  r.volume_points = cells.volume_points;
  r.facet_points = cells.facet_points;
  r.off_surface_facet_points = cells.off_surface_points;
  r.refused = cells.refused;
  r.sliver_points = cells.sliver_points;
  r.proved_off_surface = dm.cells_missed();
  r.sliver_angle = opt.sliver_angle;
  r.box_points = cells.box_points;
  r.box_refused = cells.box_refused;
  r.box_filled = !opt.outside || std::abs(r.quality.total_volume - r.box_volume) <= 1e-9 * r.box_volume;
  r.max_cell_points = opt.max_cell_points;
  r.cell_points_exhausted = cells.points_exhausted;
  r.rounds = cells.rounds;
  r.rounds_exhausted = cells.exhausted;
  r.seconds_cells = cells.seconds;
  r.cell_ratio = opt.cell_ratio;
  r.cell_size = opt.cell_size;
  r.ratio_ok = r.quality.max_radius_edge_ratio <= opt.cell_ratio * (1 + 1e-9);
  for (const auto& t : r.mesh.tets) {
    const auto& p = r.mesh.points;
    r.slivers_left += smallest_dihedral_below(p[std::size_t(t[0])], p[std::size_t(t[1])], p[std::size_t(t[2])], p[std::size_t(t[3])],
                                              opt.sliver_angle) < opt.sliver_angle;
  }
  r.size_ok = opt.cell_size <= 0 || r.quality.max_circumradius <= opt.cell_size * (1 + 1e-9);
  return r;
}

Json TetRefinementResult::to_json() const {
  Json j = Json::object();
  j["vertices"] = mesh.points.size();
  j["tetrahedra"] = mesh.tets.size();
  j["boundary_triangles"] = mesh.triangles.size();
  Json comps = Json::array();
  const MeshTopology& boundary_topology = boundary_certificate.topology;
  for (long long e : boundary_topology.sorted_euler()) comps.push_back(e);
  j["components_euler"] = comps;
  Json ex = Json::array();
  for (long long e : surface.expected.sorted_euler()) ex.push_back(e);
  j["voxel_boundary_euler"] = ex;
  j["boundary_closed_manifold"] = boundary_topology.closed && boundary_topology.manifold;
  j["boundary_oriented"] = boundary_topology.oriented;
  j["boundary_matches_voxel_boundary"] = boundary_certificate.ok();
  j["boundary_is_restricted_surface"] = boundary_is_surface;
  j["topology_matches"] = surface.topology_ok && boundary_certificate.ok() && boundary_is_surface;
  j["conforming"] = conformity.ok();
  j["cell_ratio_bound"] = cell_ratio;
  j["cell_size_bound"] = cell_size;
  j["quality"] = quality.to_json();
  j["max_radius_edge_ratio"] = quality.max_radius_edge_ratio;
  j["min_dihedral_degrees"] = quality.min_dihedral;
  j["share_dihedral_under_10"] = quality.share_under_10();
  j["volume"] = quality.total_volume;
  j["conformity"] = conformity.to_json();
  Json pts = Json::object();
  pts["volume"] = volume_points;
  pts["encroached_facet"] = facet_points;
  pts["off_surface_facet"] = off_surface_facet_points;
  pts["sliver"] = sliver_points;
  pts["refused"] = refused;
  pts["proved_off_surface"] = proved_off_surface;
  j["sliver_angle_bound"] = sliver_angle;
  j["slivers_left"] = slivers_left;
  pts["box"] = box_points;
  pts["box_refused"] = box_refused;
  j["cell_refinement_points"] = pts;
  j["cell_refinement_rounds"] = rounds;
  j["outside"] = outside;
  if (outside) {
    j["box_volume"] = box_volume;
    j["box_filled"] = box_filled;
    j["box_covered"] = box_covered;
  }
  j["cell_refinement_seconds"] = seconds_cells;
  j["surface"] = surface.to_json();
  return j;
}

std::string TetRefinementResult::failed_guarantee() const {
  std::string f = surface.failed_guarantee();
  auto add = [&f](const std::string& s) { f += (f.empty() ? "" : "; ") + s; };
  if (mesh.tets.empty()) add("no tetrahedron inside the surface");
  if (outside && !box_filled) add("--outside: the tetrahedra do not fill the box (volume differs)");
  if (outside && !box_covered) add("--outside: the boundary triangles do not cover the box's faces");
  if (cell_points_exhausted) add("cell refinement stopped at --max-cell-points (" + std::to_string(max_cell_points) + ")");
  if (!conformity.ok()) add("tetrahedra not positively oriented or not conforming");
  if (!boundary_is_surface) add("the tetrahedra's boundary is not the restricted Delaunay surface");
  if (!boundary_certificate.ok())
    add("the tetrahedra's boundary is not certified against the voxel boundary bdCA(X): " + boundary_certificate.failure());
  if (!ratio_ok) add("a tetrahedron's radius-edge ratio is above --cell-ratio");
  if (!size_ok) add("a tetrahedron's circumradius is above --cell-size");
  if (rounds_exhausted) add("cell refinement stopped after " + std::to_string(rounds) + " rounds");
  return f;
}

} // namespace imgmesh
