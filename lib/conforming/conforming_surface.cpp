#include "conforming/conforming_surface.hpp"

#include "mesh/tet_mesh.hpp"
#include "util/error.hpp"

#include <CGAL/Delaunay_triangulation_3.h>
#include <CGAL/Delaunay_triangulation_cell_base_3.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Robust_weighted_circumcenter_filtered_traits_3.h>
#include <CGAL/Triangulation_cell_base_with_info_3.h>
#include <CGAL/Triangulation_vertex_base_with_info_3.h>

#include <algorithm>
#include <cmath>
#include <numeric>
#include <string>
#include <unordered_map>

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
using Vb = CGAL::Triangulation_vertex_base_with_info_3<int, GT>;  // id; -1: a corner of the bounding box
using Cb = CGAL::Triangulation_cell_base_with_info_3<CInfo, GT, CGAL::Delaunay_triangulation_cell_base_3<GT>>;
using Tds = CGAL::Triangulation_data_structure_3<Vb, Cb>;
using Tr = CGAL::Delaunay_triangulation_3<GT, Tds>;
using Vh = Tr::Vertex_handle;
using Ch = Tr::Cell_handle;

enum Step { kSeed, kVorEdge, kTopoDisk, kPatchFan, kQuality, kDistance, kVoxelSide, kCertificate, kCell, kCellFacet, kOffSurface, kSteps };
const char* const kStepName[kSteps] = {"seed",        "vor_edge", "topo_disk",  "patch_fan", "quality",    "max_distance",
                                       "voxel_side",  "certificate", "cell",     "cell_facet", "off_surface"};
static_assert(kSteps == std::tuple_size<decltype(ConformingSurface::inserted)>::value, "one count a step");

inline Vec3 vec(const Point& p) { return {p.x(), p.y(), p.z()}; }
inline Point pt(const Vec3& v) { return Point(v[0], v[1], v[2]); }
inline Vec3 sub(const Vec3& a, const Vec3& b) { return {a[0] - b[0], a[1] - b[1], a[2] - b[2]}; }
inline double dot(const Vec3& a, const Vec3& b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }
inline Vec3 cross(const Vec3& a, const Vec3& b) {
  return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
}
inline double dist2(const Vec3& a, const Vec3& b) { return dot(sub(a, b), sub(a, b)); }

// Circumradius over shortest edge.
double radius_edge_ratio(const Vec3& a, const Vec3& b, const Vec3& c) {
  const double ab = dist2(a, b), bc = dist2(b, c), ca = dist2(c, a);
  const Vec3 n = cross(sub(b, a), sub(c, a));
  const double area2 = dot(n, n);  // (2 area)^2
  if (!(area2 > 0)) return INFINITY;
  const double r2 = ab * bc * ca / (4 * area2);
  return std::sqrt(r2 / std::min({ab, bc, ca}));
}

// A point to insert, from a facet (v: its vertices, cells: the uids of its
// two cells when found: it is stale once either changed) or a voxel centre.
struct Candidate {
  Vec3 x;
  double priority = 0;  // the surface ball's squared radius: larger first
  int step = kQuality;
  std::array<Vh, 3> v{};
  std::array<std::uint32_t, 2> cells{0, 0};
};

class Mesher {
public:
  Mesher(const LabelFunction& lambda, const LabelImage& x, const InterfaceComplex& k, const ConformingOptions& o)
      : f_(lambda), x_(x), k_(k), o_(o) {
    voxel_ = std::min({x.spacing[0], x.spacing[1], x.spacing[2]});
    if (!(o_.max_distance > 0)) o_.max_distance = 0.3 * voxel_;
  }

  ConformingSurface run() {
    tr_.infinite_vertex()->info() = -2;
    bounding_box();
    seeds();
    refine();
    ConformingSurface out = certified_rounds();
    if (o_.tets.on) {
      // The cells, then the certificate's rounds again if they changed the
      // surface, and the cells again if those rounds inserted.
      for (int again = 0; again < 3 && !max_hit_; ++again) {
        const std::size_t before = points_;
        refine_cells();
        if (points_ == before) break;
        const int r = rounds_;
        out = certified_rounds();
        if (rounds_ == r) break;
      }
      tets_output(out);
    }
    return out;
  }

private:
  ConformingSurface certified_rounds() {
    ConformingSurface out = output();
    // Rounds repair a patch sampled too coarsely (a small patch in pieces
    // where the curves around it are), not a labelling that disagrees with
    // K(X), where refining does not converge (and grades the mesh around
    // ever finer: the brain map's third round tripled its points): they
    // run while each round halves the failing places, counted across calls
    // (seg2tet calls again after its cells: a fresh count there let each
    // call refine once more, and the brain map's tetrahedra ran to the
    // point cap).
    while (o_.certificate && rounds_ < o_.certificate_rounds && !max_hit_) {
      const auto bad = o_.certificate(out.points, out.triangles, out.pairs);
      out.certified_as_is = true;
      const std::size_t before = places_;
      places_ = bad.size();
      if (bad.empty() || bad.size() > before / 2 || !refine_near(bad)) break;
      ++rounds_;
      refine();
      out = output();
    }
    return out;
  }

  std::int32_t label(Ch c) {
    if (tr_.is_infinite(c)) return 0;
    known(c);
    return c->info().label;
  }
  Vec3 centre(Ch c) {
    known(c);
    return c->info().centre;
  }
  void known(Ch c) {
    if (c->info().label != kUnknown) return;
    c->info().centre = vec(c->circumcenter());
    c->info().label = f_.label(c->info().centre);
  }

  Vec3 voxel_centre(std::ptrdiff_t i, std::ptrdiff_t j, std::ptrdiff_t k) const {
    return x_.world(double(i), double(j), double(k));
  }
  std::int32_t voxel_label(std::ptrdiff_t i, std::ptrdiff_t j, std::ptrdiff_t k) const { return x_.at(i, j, k, 0); }

  // Eight corners two voxels and a half beyond the grid's box: every
  // restricted facet's Voronoi edge is then finite (the cells around the
  // corners lie outside, in 0).
  void bounding_box() {
    for (int c = 0; c < 8; ++c) {
      const double i = (c & 1) ? double(x_.size[0]) + 2.5 : -3.5;
      const double j = (c & 2) ? double(x_.size[1]) + 2.5 : -3.5;
      const double k = (c & 4) ? double(x_.size[2]) + 2.5 : -3.5;
      Vh v = tr_.insert(pt(x_.world(i, j, k)));
      v->info() = -1;
    }
  }

  // start: a cell near p where the caller knows one (the walk starts there;
  // the triangulation is the same whatever the start).
  bool insert(const Vec3& p, int step, Ch start = Ch()) {
    if (points_ >= o_.max_points) {
      max_hit_ = true;
      return false;
    }
    Tr::Locate_type lt;
    int li, lj;
    Ch c = tr_.locate(pt(p), lt, li, lj, start != Ch() ? start : hint_);
    if (lt == Tr::VERTEX) {
      ++refused_;
      return false;
    }
    Vh near = tr_.nearest_vertex(pt(p), c);
    if (dist2(vec(near->point()), p) < 1e-12 * voxel_ * voxel_) {
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

  // The two voxels of a face of K(X), and lambda's change between their centres.
  bool face_point(std::uint64_t key, Vec3& p) const {
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
  void seeds() {
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

  std::array<Vh, 3> facet_vertices(Ch c, int i) const {
    std::array<Vh, 3> v{c->vertex((i + 1) & 3), c->vertex((i + 2) & 3), c->vertex((i + 3) & 3)};
    std::sort(v.begin(), v.end(), [](Vh a, Vh b) { return a->info() < b->info(); });
    return v;
  }

  // The facet's surface centre and ball radius, when restricted (one change).
  bool surface_centre(Ch c, int i, Vec3& x) {
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

  // VorEdge, QUALITY and the distance bound on facet (c, i).
  void check_facet(Ch c, int i) {
    Ch n = c->neighbor(i);
    if (tr_.is_infinite(c) || tr_.is_infinite(n)) return;
    const Vec3 a = centre(c), b = centre(n);
    const std::int32_t la = label(c), lb = label(n);
    const auto v = facet_vertices(c, i);
    if (v[0]->info() < 0) return;  // a bounding-box corner: outside, in 0
    const std::int32_t ends[2] = {la, lb};
    f_.changes(a, b, changes_, o_.step, 0, ends);
    if (changes_.empty()) return;
    Candidate cand;
    cand.v = v;
    cand.cells = {c->info().uid, n->info().uid};
    const Vec3 p0 = vec(v[0]->point()), p1 = vec(v[1]->point()), p2 = vec(v[2]->point());
    auto at = [&](double t) { return Vec3{a[0] + t * (b[0] - a[0]), a[1] + t * (b[1] - a[1]), a[2] + t * (b[2] - a[2])}; };
    if (changes_.size() >= 2 || la == lb) {
      const Vec3 first = at(changes_.front().t), last = at(changes_.back().t);
      cand.x = dist2(first, p0) >= dist2(last, p0) ? first : last;
      cand.step = kVorEdge;
      cand.priority = dist2(cand.x, p0);
      topology_.push_back(cand);
      return;
    }
    cand.x = at(changes_[0].t);
    cand.priority = dist2(cand.x, p0);
    // A vertex off the interfaces (a cell's circumcentre, seg2tet): the
    // facet's surface centre goes in, so every surface vertex lies on one.
    if (!on_surface_[std::size_t(v[0]->info())] || !on_surface_[std::size_t(v[1]->info())] ||
        !on_surface_[std::size_t(v[2]->info())]) {
      cand.step = kOffSurface;
      quality_.push_back(cand);
      return;
    }
    if (radius_edge_ratio(p0, p1, p2) > o_.ratio) {
      cand.step = kQuality;
      quality_.push_back(cand);
      return;
    }
    const Vec3 nrm = cross(sub(p1, p0), sub(p2, p0));
    const double nn = dot(nrm, nrm), h = dot(nrm, sub(cand.x, p0));
    if (nn > 0 && h * h > o_.max_distance * o_.max_distance * nn) {
      cand.step = kDistance;
      quality_.push_back(cand);
    }
  }

  // TopoDisk per label at v: for each label around v (not all one), the
  // facets between its cells and the others' form one cycle in v's link.
  void check_vertex(Vh v) {
    cells_.clear();
    tr_.incident_cells(v, std::back_inserter(cells_));
    std::int32_t first = label(cells_[0]);
    bool one = true;
    for (Ch c : cells_) one = one && label(c) == first;
    if (one) return;
    labels_.clear();
    for (Ch c : cells_) labels_.push_back(label(c));
    std::sort(labels_.begin(), labels_.end());
    labels_.erase(std::unique(labels_.begin(), labels_.end()), labels_.end());
    for (std::int32_t l : labels_) {
      link_.clear();
      other_.clear();
      for (Ch c : cells_) {
        if (label(c) != l) continue;
        const int iv = c->index(v);
        for (int j = 0; j < 4; ++j) {
          if (j == iv || label(c->neighbor(j)) == l) continue;
          int e[2], m = 0;
          for (int q = 0; q < 4; ++q)
            if (q != j && q != iv) e[m++] = tr_.is_infinite(c->vertex(q)) ? -2 : c->vertex(q)->info();
          link_.push_back({e[0], e[1]});
          other_.push_back(label(c->neighbor(j)));
        }
      }
      // Each label's facets around v one disk, and within it each pair's
      // facets one fan: a patch that comes back to v after other patches
      // is two fans there (the mesh's patch pinched or split where K(X)'s
      // is not, on a tiny patch: the curves sampled too coarsely).
      std::int32_t pair = kUnknown;
      if (one_cycle(link_) && (pair = split_pair(link_, other_)) == kUnknown) continue;
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
          Vec3 x;
          if (!surface_centre(c, j, x)) continue;
          const double r2 = dist2(x, vec(v->point()));
          if (r2 > best.priority) {
            best.x = x, best.priority = r2, best.v = facet_vertices(c, j);
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

  // Each link vertex in two link edges, the edges one closed walk.
  static bool one_cycle(std::vector<std::array<int, 2>>& link) {
    if (link.size() < 3) return false;
    std::unordered_map<int, std::array<int, 3>> adj;  // up to two neighbours and a count
    for (const auto& e : link)
      for (int s = 0; s < 2; ++s) {
        auto& a = adj.try_emplace(e[s], std::array<int, 3>{0, 0, 0}).first->second;
        if (a[2] == 2) return false;
        a[a[2]++] = e[1 - s];
      }
    for (const auto& kv : adj)
      if (kv.second[2] != 2) return false;
    int prev = link[0][0], cur = link[0][1];
    std::size_t steps = 1;
    while (cur != link[0][0]) {
      const auto& a = adj[cur];
      const int next = a[0] == prev ? a[1] : a[0];
      prev = cur, cur = next;
      if (++steps > link.size()) return false;
    }
    return steps == link.size();
  }

  // The link's edges (one cycle) in cyclic order: a label of `other` (the
  // label across each edge's facet) in two runs or more, else kUnknown.
  static std::int32_t split_pair(const std::vector<std::array<int, 2>>& link, const std::vector<std::int32_t>& other) {
    std::unordered_map<int, std::array<std::size_t, 2>> at;
    const std::size_t none = std::size_t(-1);
    for (std::size_t e = 0; e < link.size(); ++e)
      for (int s = 0; s < 2; ++s) {
        auto& a = at.try_emplace(link[e][s], std::array<std::size_t, 2>{none, none}).first->second;
        (a[0] == none ? a[0] : a[1]) = e;
      }
    std::vector<std::int32_t> seq;
    seq.reserve(link.size());
    std::size_t e = 0;
    int cur = link[0][1];
    for (std::size_t n = 0; n < link.size(); ++n) {
      seq.push_back(other[e]);
      const auto& a = at[cur];
      e = a[0] == e ? a[1] : a[0];
      cur = link[e][0] == cur ? link[e][1] : link[e][0];
    }
    std::vector<std::int32_t> starts;
    for (std::size_t i = 0; i < seq.size(); ++i)
      if (seq[i] != seq[(i + seq.size() - 1) % seq.size()]) starts.push_back(seq[i]);
    std::sort(starts.begin(), starts.end());
    for (std::size_t i = 1; i < starts.size(); ++i)
      if (starts[i] == starts[i - 1]) return starts[i];
    return kUnknown;
  }

  // Every voxel centre next to an interface in a cell of its own label.
  void voxel_sides() {
    std::vector<char> seen(x_.count(), 0);
    for (std::uint64_t key : k_.faces) {
      const auto q = k_.corner(InterfaceComplex::face_corner(key));
      const int a = InterfaceComplex::face_axis(key);
      for (int s = 0; s < 2; ++s) {
        std::array<std::ptrdiff_t, 3> v{std::ptrdiff_t(q[0]), std::ptrdiff_t(q[1]), std::ptrdiff_t(q[2])};
        v[a] -= s;
        if (!x_.inside(v[0], v[1], v[2])) continue;
        char& done = seen[x_.index(std::size_t(v[0]), std::size_t(v[1]), std::size_t(v[2]))];
        if (done) continue;
        done = 1;
        const Vec3 p = voxel_centre(v[0], v[1], v[2]);
        Tr::Locate_type lt;
        int li, lj;
        Ch c = tr_.locate(pt(p), lt, li, lj, hint_);
        hint_ = c;
        const std::int32_t own = voxel_label(v[0], v[1], v[2]);
        // On a facet, edge or vertex of W: every cell there must be its label.
        if (lt != Tr::CELL && lt != Tr::OUTSIDE_CONVEX_HULL) {
          cells_.clear();
          if (lt == Tr::FACET) cells_ = {c, c->neighbor(li)};
          else if (lt == Tr::EDGE) {
            auto circ = tr_.incident_cells(c, li, lj), end = circ;
            do cells_.push_back(circ); while (++circ != end);
          } else tr_.incident_cells(c->vertex(li), std::back_inserter(cells_));
          for (Ch n : cells_)
            if (label(n) != own) c = n;
        }
        if (label(c) == own) continue;
        Candidate cand;
        if (!f_.first_change(p, centre(c), cand.x, o_.step)) continue;
        cand.step = kVoxelSide;
        cand.priority = dist2(cand.x, p);
        sides_.push_back(cand);
      }
    }
  }

  // The surface centres of the restricted facets in the voxels within one
  // of the voxel holding each place.
  bool refine_near(const std::vector<Vec3>& places) {
    std::vector<char> near(x_.count(), 0);
    for (const Vec3& p : places) {
      const Vec3 q = x_.continuous_index(p);
      const auto i = std::ptrdiff_t(std::floor(q[0] + 0.5)), j = std::ptrdiff_t(std::floor(q[1] + 0.5)),
                 k = std::ptrdiff_t(std::floor(q[2] + 0.5));
      for (std::ptrdiff_t dz = -1; dz <= 1; ++dz)
        for (std::ptrdiff_t dy = -1; dy <= 1; ++dy)
          for (std::ptrdiff_t dx = -1; dx <= 1; ++dx)
            if (x_.inside(i + dx, j + dy, k + dz))
              near[x_.index(std::size_t(i + dx), std::size_t(j + dy), std::size_t(k + dz))] = 1;
    }
    std::vector<Vec3> pts;
    for (auto f = tr_.finite_facets_begin(); f != tr_.finite_facets_end(); ++f) {
      Vec3 x;
      if (!surface_centre(f->first, f->second, x)) continue;
      const Vec3 q = x_.continuous_index(x);
      const auto i = std::ptrdiff_t(std::floor(q[0] + 0.5)), j = std::ptrdiff_t(std::floor(q[1] + 0.5)),
                 k = std::ptrdiff_t(std::floor(q[2] + 0.5));
      if (x_.inside(i, j, k) && near[x_.index(std::size_t(i), std::size_t(j), std::size_t(k))]) pts.push_back(x);
    }
    bool any = false;
    for (const Vec3& x : pts) any = insert(x, kCertificate) || any;
    return any;
  }

  // Still the facet it was found on (same vertices, same two cells)?
  // cell: one of the facet's two cells, when it is.
  bool current(const Candidate& c, Ch& cell) {
    cell = Ch();
    if (c.step == kVoxelSide) return true;
    int i, j, k;
    if (!tr_.is_facet(c.v[0], c.v[1], c.v[2], cell, i, j, k)) return false;
    Ch n = cell->neighbor(6 - i - j - k);
    const std::uint32_t a = cell->info().uid, b = n->info().uid;
    return a != 0 && b != 0 && ((a == c.cells[0] && b == c.cells[1]) || (a == c.cells[1] && b == c.cells[0]));
  }

  bool insert_all(std::vector<Candidate>& cands) {
    std::stable_sort(cands.begin(), cands.end(),
                     [](const Candidate& a, const Candidate& b) { return a.priority > b.priority; });
    bool any = false;
    for (const Candidate& c : cands) {
      Ch near;
      if (current(c, near) && insert(c.x, c.step, near)) any = true;
    }
    cands.clear();
    return any;
  }

  void refine() {
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
          cells_.clear();
          tr_.incident_cells(v, std::back_inserter(cells_));
          for (Ch c : cells_) take(c);
        }
      }
      new_vertices_.clear();
      touched_.clear();
      for (Ch c : fresh_) {
        for (int i = 0; i < 4; ++i) {
          Ch n = c->neighbor(i);
          if (is_fresh(n) && n->info().uid < c->info().uid) continue;
          check_facet(c, i);
        }
        for (int i = 0; i < 4; ++i)
          if (c->vertex(i)->info() >= 0) touched_.push_back(c->vertex(i));
      }
      // By id, not address: the same candidates in the same order every run.
      std::sort(touched_.begin(), touched_.end(), [](Vh a, Vh b) { return a->info() < b->info(); });
      touched_.erase(std::unique(touched_.begin(), touched_.end()), touched_.end());
      for (Vh v : touched_) check_vertex(v);
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
  }
  bool is_fresh(Ch c) const { return c->info().uid >= fresh_first_; }

  // How far a labelled cell is beyond R and S (0: within); slivers (only a
  // small dihedral angle, none under 1e-3 voxel) below every other bad cell.
  double badness(Ch c, bool& sliver) {
    std::array<Vec3, 4> p;
    for (int i = 0; i < 4; ++i) p[std::size_t(i)] = vec(c->vertex(i)->point());
    const ConformingTetOptions& t = o_.tets;
    return refinement_badness(p, dist2(centre(c), p[0]), t.cell_ratio, t.cell_size, t.sliver_angle, 1e-3 * voxel_,
                              sliver);
  }

  struct BadCell {
    double bad;
    Ch c;
    std::array<Vh, 4> v;
    bool sliver;
  };
  bool alive(const BadCell& e) const {
    if (!tr_.tds().cells().is_used(e.c)) return false;
    for (int i = 0; i < 4; ++i)
      if (e.c->vertex(i) != e.v[std::size_t(i)]) return false;
    return true;
  }

  // Rounds of cell refinement (tets.on), REFINE after each: the bad
  // labelled cells, worst first, each its circumcentre c or, when c lies in
  // the surface Delaunay ball of a restricted facet (such a ball lies in
  // the circumballs of the facet's cells, so the facet is one of c's
  // conflict zone), that facet's surface centre: the surface is refined,
  // never crossed.
  void refine_cells() {
    const ConformingTetOptions& t = o_.tets;
    const double floor2 = 1e-6 * voxel_ * voxel_;
    std::vector<BadCell> bad;
    for (;;) {
      bad.clear();
      for (auto c = tr_.finite_cells_begin(); c != tr_.finite_cells_end(); ++c) {
        if (label(c) == 0) continue;
        bool sliver;
        const double b = badness(c, sliver);
        if (b > 0) bad.push_back({b, c, {c->vertex(0), c->vertex(1), c->vertex(2), c->vertex(3)}, sliver});
      }
      if (bad.empty()) return;
      if (cell_rounds_ >= t.max_rounds) {
        cell_rounds_exhausted_ = true;
        return;
      }
      ++cell_rounds_;
      std::stable_sort(bad.begin(), bad.end(), [](const BadCell& a, const BadCell& b) { return a.bad > b.bad; });
      bool any = false;
      for (const BadCell& e : bad) {
        if (cell_points_ >= t.max_cell_points) {
          cell_points_exhausted_ = true;
          break;
        }
        if (max_hit_) break;
        if (!alive(e)) continue;
        const Vec3 cc = centre(e.c);
        Tr::Locate_type lt;
        int li, lj;
        const Ch at = tr_.locate(pt(cc), lt, li, lj, e.c);
        if (lt == Tr::VERTEX) continue;
        zone_.clear();
        tr_.find_conflicts(pt(cc), at, CGAL::Emptyset_iterator(), std::back_inserter(zone_));
        double worst = 0;
        Vec3 wx{0, 0, 0};
        Ch wc;
        for (Ch z : zone_)
          for (int i = 0; i < 4; ++i) {
            if (label(z) == label(z->neighbor(i))) continue;
            Vec3 x;
            if (!surface_centre(z, i, x)) continue;
            const double r2 = dist2(x, vec(z->vertex((i + 1) & 3)->point()));
            if (r2 > worst && dist2(cc, x) < r2) worst = r2, wx = x, wc = z;
          }
        bool ok;
        if (worst > 0) ok = worst >= floor2 && insert(wx, kCellFacet, wc);
        else {
          ok = insert(cc, kCell, at);
          sliver_points_ += ok && e.sliver;
        }
        if (ok) {
          any = true;
          ++cell_points_;
        }
      }
      if (!any || max_hit_ || cell_points_exhausted_) return;
      refine();
    }
  }

  // The labelled cells and the interfaces (tets.on), and every voxel
  // centre located: those in a cell of another label.
  void tets_output(ConformingSurface& out) {
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
      if (label(c) == 0) continue;
      const std::array<Vh, 4> v{c->vertex(0), c->vertex(1), c->vertex(2), c->vertex(3)};  // positively oriented
      cells.emplace_back(key(label(c), v, 4), v);
    }
    const auto orient = GT().orientation_3_object();
    for (auto f = tr_.finite_facets_begin(); f != tr_.finite_facets_end(); ++f) {
      const Ch c = f->first, n = c->neighbor(f->second);
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
          const Ch c = tr_.locate(pt(voxel_centre(std::ptrdiff_t(i), std::ptrdiff_t(j), std::ptrdiff_t(k))), lt, li, lj, start);
          hint = c;
          if (i == 0) {
            row = c;
            if (j == 0) slice = c;
          }
          bool wrong = label(c) != own;
          if (lt == Tr::FACET) wrong = wrong || label(c->neighbor(li)) != own;
          else if (lt == Tr::EDGE) {
            auto circ = tr_.incident_cells(c, li, lj), end = circ;
            do wrong = wrong || label(circ) != own; while (++circ != end);
          } else if (lt == Tr::VERTEX) {
            cells_.clear();
            tr_.incident_cells(c->vertex(li), std::back_inserter(cells_));
            for (Ch n : cells_) wrong = wrong || label(n) != own;
          }
          ++out.centres_checked;
          out.centres_wrong += wrong;
        }
  }

  // The facets in the order of their sorted vertex ids, the vertices
  // numbered by first use: CGAL's storage order depends on addresses.
  ConformingSurface output() {
    ConformingSurface out;
    std::unordered_map<int, int> id;
    auto index = [&](Vh v) {
      auto [it, added] = id.try_emplace(v->info(), int(out.points.size()));
      if (added) out.points.push_back(vec(v->point()));
      return it->second;
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

  const LabelFunction& f_;
  const LabelImage& x_;
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
  std::vector<Ch> fresh_, cells_;
  std::vector<Vh> touched_, new_vertices_;
  std::vector<std::int32_t> labels_;
  std::vector<std::array<int, 2>> link_;
  std::vector<std::int32_t> other_;
  std::vector<LabelFunction::Change> changes_;
  std::vector<Candidate> topology_, quality_, sides_;
  std::vector<char> on_surface_;  // per vertex id: on an interface (not a cell's circumcentre)
  std::vector<Ch> zone_;
  long long cell_points_ = 0, sliver_points_ = 0;
  int cell_rounds_ = 0;
  bool cell_rounds_exhausted_ = false, cell_points_exhausted_ = false;
};

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
  return j;
}

ConformingSurface conforming_surface(const LabelFunction& lambda, const LabelImage& x, const InterfaceComplex& k,
                                     const ConformingOptions& options) {
  if (k.dimension != 3 || k.lattice != std::array<std::size_t, 3>{x.size[0] + 1, x.size[1] + 1, x.size[2] + 1})
    throw Error("internal: the interface complex is not the label image's");
  return conforming_detail::Mesher(lambda, x, k, options).run();
}

} // namespace imgmesh
