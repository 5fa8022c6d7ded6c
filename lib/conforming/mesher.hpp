// The restricted Delaunay mesher of a label map's partition (private to
// lib/conforming): the triangulation and its state, shared by the surface
// stage (conforming_surface.cpp: seeds, REFINE, the surface output;
// conforming_rounds.cpp: VoxelSides, the certificate's rounds) and seg2tet's
// cell stage (conforming_cells.cpp: the labelled cells refined, the
// tetrahedra output). One CGAL header set.
#pragma once

#include "conforming/conforming_surface.hpp"
#include "mesh/box_refinement.hpp"

#include <CGAL/Delaunay_triangulation_3.h>
#include <CGAL/Delaunay_triangulation_cell_base_3.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Robust_weighted_circumcenter_filtered_traits_3.h>
#include <CGAL/Triangulation_cell_base_with_info_3.h>
#include <CGAL/Triangulation_vertex_base_with_info_3.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <optional>
#include <utility>
#include <vector>

namespace imgmesh {
namespace conforming_detail {

using K0 = CGAL::Exact_predicates_inexact_constructions_kernel;
using GT = CGAL::Robust_circumcenter_filtered_traits_3<K0>;
using Point = GT::Point_3;
constexpr std::int32_t kUnknown = std::numeric_limits<std::int32_t>::min();
struct CInfo {
  Vec3 centre{0, 0, 0};           // the circumcentre, with the label
  std::int32_t label = kUnknown;  // lambda at the circumcentre
  std::uint32_t uid = 0;          // 0: made since the last pass
};
using Vb = CGAL::Triangulation_vertex_base_with_info_3<int, GT>;  // id; -1: a corner of the bounding box (-3 - k: B's corner k)
using Cb = CGAL::Triangulation_cell_base_with_info_3<CInfo, GT, CGAL::Delaunay_triangulation_cell_base_3<GT>>;
using Tds = CGAL::Triangulation_data_structure_3<Vb, Cb>;
using Tr = CGAL::Delaunay_triangulation_3<GT, Tds>;
using Vh = Tr::Vertex_handle;
using Ch = Tr::Cell_handle;
struct VertexId {
  int operator()(Vh v) const { return v->info(); }
};
using Box = BoxRefinement<Tr, VertexId>;

// TopoDisk's and PatchFan's points go in at least this many voxels (the
// smallest spacing) from every vertex, else are refused: a packing, so the
// topology steps end. Where lambda's region is pinched (a noisy map at 7:1
// anisotropy) they converged on one spot, 30,000 points 1e-4 world apart
// and no end; the certificate then says the topology is wrong (exit 3).
// The nearest the bundled brain's go is 0.058 voxel.
constexpr double kTopologyGap = 0.01;

enum Step { kSeed, kVorEdge, kTopoDisk, kPatchFan, kQuality, kDistance, kVoxelSide, kCertificate, kCell, kCellFacet, kOffSurface, kSteps };

// A cell's memory asked for ahead of its use (cells are scattered: a
// walk over many reads each first from memory).
inline void prefetch_cell(Ch c) {
  const char* p = reinterpret_cast<const char*>(&*c);
  __builtin_prefetch(p);
  __builtin_prefetch(p + 64);
  __builtin_prefetch(p + sizeof(*c) - 1);
}
inline Vec3 vec(const Point& p) { return {p.x(), p.y(), p.z()}; }
inline Point pt(const Vec3& v) { return Point(v[0], v[1], v[2]); }
inline Vec3 sub(const Vec3& a, const Vec3& b) { return {a[0] - b[0], a[1] - b[1], a[2] - b[2]}; }
inline double dot(const Vec3& a, const Vec3& b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }
inline Vec3 cross(const Vec3& a, const Vec3& b) {
  return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
}
inline double dist2(const Vec3& a, const Vec3& b) { return dot(sub(a, b), sub(a, b)); }

// For p strictly inside the cell v: the least squared distance from p to
// the planes of its facets. A ball about p of that radius lies in the
// cell, so in its circumball, which holds no vertex: no vertex of a
// Delaunay triangulation is nearer to p. 0 when a facet is nearly a
// segment (sin of an angle under 1e-6: its plane's rounding unbounded).
inline double inner_distance2(const std::array<Vec3, 4>& v, const Vec3& p) {
  double d2 = std::numeric_limits<double>::infinity();
  for (int i = 0; i < 4; ++i) {
    const Vec3 &a = v[std::size_t((i + 1) & 3)], &b = v[std::size_t((i + 2) & 3)], &c = v[std::size_t((i + 3) & 3)];
    const Vec3 ab = sub(b, a), ac = sub(c, a), n = cross(ab, ac);
    const double nn = dot(n, n), h = dot(n, sub(p, a));
    if (!(nn > 1e-12 * dot(ab, ab) * dot(ac, ac))) return 0;
    d2 = std::min(d2, h * h / nn);
  }
  return d2;
}

// The distance bound: a surface centre x farther than e from the plane of
// the facet (p0, p1, p2), (nrm . (x - p0))^2 > e^2 |nrm|^2 with nrm = (p1 -
// p0) x (p2 - p0). x0 = x1: at x = x0. Else at some x whose coordinates
// each lie between x0's and x1's: false only when false at every such x
// (each rounded term nrm_m (x_m - p0_m) is monotone in x_m, the rounded
// sums in their terms: h = nrm . (x - p0) lies between its values at two
// corners, and h * h grows with |h|).
inline bool beyond_distance(const Vec3& p0, const Vec3& p1, const Vec3& p2, const Vec3& x0, const Vec3& x1,
                            double e) {
  const Vec3 nrm = cross(sub(p1, p0), sub(p2, p0)), y0 = sub(x0, p0), y1 = sub(x1, p0);
  Vec3 lo, hi;
  for (int m = 0; m < 3; ++m) {
    const bool up = nrm[m] >= 0;
    lo[m] = up ? std::min(y0[m], y1[m]) : std::max(y0[m], y1[m]);
    hi[m] = up ? std::max(y0[m], y1[m]) : std::min(y0[m], y1[m]);
  }
  const double nn = dot(nrm, nrm), h = std::max(std::fabs(dot(nrm, lo)), std::fabs(dot(nrm, hi)));
  return nn > 0 && h * h > e * e * nn;
}

// A vertex of a link as check_vertex names it: its address (a name without
// reading the vertex, which was a cache miss a link vertex); the bounding
// box's eight corners (their addresses; 0 when there are none), which share
// the id -1, one name, as their id made them.
inline std::intptr_t link_name(std::intptr_t address, const std::array<std::intptr_t, 8>& corners) {
  return std::find(corners.begin(), corners.end(), address) != corners.end() ? corners[0] : address;
}

// The list's entries from `first` on (one a vertex; ids: each one's vertex
// id and its rank among them) put in the order of their vertices' ids.
template <class T>
void order_by_id(std::vector<T>& list, std::size_t first, std::vector<std::pair<int, std::size_t>>& ids,
                 std::vector<T>& scratch) {
  std::sort(ids.begin(), ids.end());
  scratch.clear();
  for (const auto& [id, k] : ids) scratch.push_back(list[first + k]);
  std::copy(scratch.begin(), scratch.end(), list.begin() + std::ptrdiff_t(first));
}

// A point to insert, from a facet (cell, facet: the facet as found, cells:
// the uids of its two cells then: it is stale once either changed) or a
// voxel centre.
struct Candidate {
  Vec3 x;
  double priority = 0;  // the surface ball's squared radius: larger first
  int step = kQuality;
  int facet = 0;
  Ch cell;
  std::array<std::uint32_t, 2> cells{0, 0};
};

class Mesher {
public:
  Mesher(const LabelFunction& lambda, const NarrowLabelImage& x, const InterfaceComplex& k, const ConformingOptions& o)
      : f_(lambda), x_(x.geometry()), image_(x), k_(k), o_(o) {
    voxel_ = std::min({x_.spacing[0], x_.spacing[1], x_.spacing[2]});
    if (!(o_.max_distance > 0)) o_.max_distance = 0.3 * voxel_;
  }
  ConformingSurface run();

private:
  // A cell's label (lambda at its circumcentre; 0 outside) and circumcentre,
  // computed once.
  std::int32_t label(Ch c) {
    if (c->info().label != kUnknown) return c->info().label;  // never set on an infinite cell
    if (tr_.is_infinite(c)) return 0;
    known(c);
    return c->info().label;
  }
  Vec3 centre(Ch c) {
    known(c);
    return c->info().centre;
  }
  void known(Ch c);
  Vec3 voxel_centre(std::ptrdiff_t i, std::ptrdiff_t j, std::ptrdiff_t k) const {
    return x_.world(double(i), double(j), double(k));
  }
  std::int32_t voxel_label(std::ptrdiff_t i, std::ptrdiff_t j, std::ptrdiff_t k) const { return image_.at(i, j, k); }
  std::array<Vh, 3> facet_vertices(Ch c, int i) const {  // sorted by id
    std::array<Vh, 3> v{c->vertex((i + 1) & 3), c->vertex((i + 2) & 3), c->vertex((i + 3) & 3)};
    std::sort(v.begin(), v.end(), [](Vh a, Vh b) { return a->info() < b->info(); });
    return v;
  }
  // p unless within sqrt(gap2) (at least 1e-6 voxel) of a vertex.
  // near: a cell nearer p than start (locate_from).
  bool insert(const Vec3& p, int step, Ch start = Ch(), double gap2 = 0, Ch near = Ch());
  // Ch() when no stop cell was reached (all of v's cells gathered).
  Ch star(Vh v, std::vector<Ch>& out, Ch stop_a = Ch(), Ch stop_b = Ch());
  bool surface_centre(Ch c, int i, Vec3& x);

  // The surface stage (conforming_surface.cpp).
  void bounding_box();
  bool face_point(std::uint64_t key, Vec3& p) const;
  void seeds();
  void refine();
  void release_lists();
  bool keep_lists_ = false;  // seg2tet's cell rounds: REFINE's lists kept for the next
  bool is_fresh(Ch c) const { return c->info().uid >= fresh_first_; }
  // A facet of the pass, what it needs (kVorEdge, kOffSurface, kQuality,
  // kDistance; kSteps: nothing, also for a facet not walked) and the t of
  // lambda's first and last change along its Voronoi edge (where it needs
  // them).
  struct FacetWalk {
    Ch c;
    int i;
    int step;
    double first, last;
  };
  void walk_facets();
  int facet_step(Ch c, int i, const Vec3& x0, const Vec3& x1) const;
  void check_facet(const FacetWalk& w);
  void check_vertex(Vh v);
  using LinkEdge = std::array<std::intptr_t, 2>;  // two link_name()s
  static bool one_cycle(const std::vector<LinkEdge>& link, std::vector<LinkEdge>& at);
  static std::int32_t split_pair(const std::vector<LinkEdge>& link, const std::vector<std::int32_t>& other,
                                 const std::vector<LinkEdge>& at, std::vector<std::int32_t>& seq);
  bool current(const Candidate& c, Ch& cell);
  bool insert_all(std::vector<Candidate>& cands);
  ConformingSurface output();
  // VoxelSides and the certificate's rounds (conforming_rounds.cpp).
  void voxel_sides();
  ConformingSurface certified_rounds();
  bool refine_near(const std::vector<Vec3>& places);

  // The cell stage (conforming_cells.cpp).
  struct BadCell {
    double bad;
    Ch c;
    std::uint32_t uid;
    std::array<Vh, 4> v;
    std::array<int, 4> id;  // the vertices' ids, sorted
    bool sliver;
  };
  double badness(Ch c, bool& sliver);
  bool alive(const BadCell& e) const;
  void off_centre(const std::array<Vh, 4>& v, Ch c, int i, double r2, Vec3& x);
  Box outside_box() const;
  bool box_split(const Point& cc, bool beyond, bool& inserted);
  void refine_cells();
  void tets_output(ConformingSurface& out);
  void box_output(ConformingSurface& out);

  const LabelFunction& f_;
  const Geometry& x_;  // X's grid
  const NarrowLabelImage& image_;  // X
  const InterfaceComplex& k_;
  ConformingOptions o_;
  double voxel_ = 1;
  Tr tr_;
  Ch hint_;
  std::size_t points_ = 0;
  std::array<long long, kSteps> inserted_{};
  long long refused_ = 0, passes_ = 0;
  int rounds_ = 0;
  std::size_t places_ = std::size_t(-1);  // the last certificate's failing places
  bool max_hit_ = false;
  std::uint32_t uid_ = 0, fresh_first_ = 0;
  std::vector<Ch> fresh_, cells_, pending_, stack_;
  std::vector<FacetWalk> walks_;
  std::vector<std::vector<LabelFunction::Bracket>> walk_brackets_;  // per thread
  std::vector<Vh> new_vertices_;
  std::vector<std::pair<int, Vh>> touched_;  // (id, vertex), each once
  std::vector<char> touched_mark_;           // per vertex id: in touched_
  std::vector<std::int32_t> inner_;          // per vertex id: its cells' one label, else kUnknown
  std::vector<std::pair<int, std::size_t>> candidate_ids_;  // (vertex id, its candidate's rank in the pass's checks)
  std::vector<Candidate> by_id_;
  std::vector<std::int32_t> labels_;
  std::vector<LinkEdge> link_;
  std::vector<std::int32_t> other_, seq_;
  std::vector<LinkEdge> at_;
  std::array<std::intptr_t, 8> corners_{};  // the bounding box's corners' addresses (seg2tet --outside: none, 0)
  std::vector<LabelFunction::Change> changes_;
  std::vector<Candidate> topology_, quality_, sides_;
  std::vector<char> on_surface_;  // per vertex id: on an interface (not a cell's circumcentre)
  std::vector<Ch> zone_, in_zone_;  // a conflict zone; sorted by address (membership only)
  // voxel_sides' voxels (their index in X), each with the cell that held
  // its centre (and that cell's uid) at the last call; Ch() when on a face
  // of the triangulation. 16 bytes.
  struct SideVoxel {
    Ch cell;
    std::uint32_t uid;
    std::uint32_t voxel;
  };
  std::vector<SideVoxel> side_voxels_;
  long long cell_points_ = 0, sliver_points_ = 0;
  int cell_rounds_ = 0;
  bool cell_rounds_exhausted_ = false, cell_points_exhausted_ = false;
  std::optional<Box> box_;  // tets.outside: B, the triangulation's hull
  long long box_points_ = 0, box_refused_ = 0;
};

} // namespace conforming_detail
} // namespace imgmesh
