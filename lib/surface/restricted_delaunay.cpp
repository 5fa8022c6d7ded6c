// DELMESH (thesis 7.6.5) on CGAL's Delaunay_triangulation_3, kept
// incremental: every insertion recomputes only the facets of the new cells
// (all incident to the new vertex) and re-checks only the vertices whose
// restricted facets changed.
// See ../shared/notes/implicit2mesh.md for the CGAL calls this follows.
#include "surface/restricted_delaunay.hpp"

#include "implicit/parallel.hpp"
#include "util/error.hpp"

#include <CGAL/Delaunay_triangulation_3.h>
#include <CGAL/Delaunay_triangulation_cell_base_with_circumcenter_3.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Robust_weighted_circumcenter_filtered_traits_3.h>
#include <CGAL/Triangulation_vertex_base_with_info_3.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <map>
#include <optional>
#include <queue>
#include <random>
#include <set>
#include <sstream>
#include <unordered_map>

namespace imgmesh {

double min_ratio_bound() { return (1 + 0.06) * (1 + 0.06); }
double min_roughness_bound() { return 2 * (std::asin(0.06) + std::asin(2 * 0.06 / std::sqrt(3.0))); }

namespace {

using K0 = CGAL::Exact_predicates_inexact_constructions_kernel;
// Circumcentres in floating point, checked with an exact predicate to lie
// inside the tetrahedron's circumsphere, else computed exactly and rounded
// (Mesh_3's traits; Surface_mesher's always go through the lazy exact kernel).
using GT = CGAL::Robust_circumcenter_filtered_traits_3<K0>;
using Point = GT::Point_3;

// Why a vertex is in W; also the per-subroutine counters of --stats.
enum Origin : std::uint8_t { kSeed, kVorEdge, kTopoDisk, kFacetCycle, kHandle, kQuality, kSmooth, kDistance, kFallback, kOrigins };
const char* const kOriginName[kOrigins] = {"seed", "vor_edge", "topo_disk", "facet_cycle", "handle_detection", "quality", "smooth", "max_distance", "topology_fallback"};

struct VInfo {
  int id = -1;
  std::uint8_t origin = kSeed;
  int comp = -1;  // S component (active-cube component) the vertex lies on
  std::uint8_t queued = 0;  // 1: TopoDisk check queued, 2: SMOOTH check queued
  std::uint32_t stamp = 0;  // last insertion that collected this vertex
};

enum : std::uint8_t { kComputed = 1, kRestricted = 2, kMulti = 4 };

// EdgeSurface's answer for one Delaunay facet, stored on both of its sides.
struct FacetInfo {
  std::uint8_t state = 0;
  std::uint32_t computed = 0;  // which computation: queue entries of older ones are stale
  double x[3] = {0, 0, 0};  // surface centre x_t: crossing farthest from the facet's vertices
  double r2 = 0;            // squared radius of the surface Delaunay ball
  float grad[3] = {0, 0, 0};  // grad f at x_t (orients the facet for SMOOTH and output)
};

// The circumcentre from the vertices in lexicographic order. From CGAL's
// vertex order, which vertex removal makes depend on addresses, it would
// differ in its last bits from run to run (the cell base above caches it).
template <class Gt, class Cb = CGAL::Delaunay_triangulation_cell_base_3<Gt>>
class CanonicalCircumcenter : public Cb {
public:
  template <class TDS2> struct Rebind_TDS {
    using Cb2 = typename Cb::template Rebind_TDS<TDS2>::Other;
    using Other = CanonicalCircumcenter<Gt, Cb2>;
  };
  using Cb::Cb;
  typename Gt::Point_3 circumcenter(const Gt& gt = Gt()) const {
    const typename Gt::Point_3* p[4];
    for (int i = 0; i < 4; ++i) p[i] = &this->vertex(i)->point();
    std::sort(p, p + 4, [](const auto* a, const auto* b) { return *a < *b; });
    return gt.construct_circumcenter_3_object()(*p[0], *p[1], *p[2], *p[3]);
  }
};

template <class Gt, class Cb = CGAL::Delaunay_triangulation_cell_base_with_circumcenter_3<Gt, CanonicalCircumcenter<Gt>>>
class CellBase : public Cb {
public:
  template <class TDS2> struct Rebind_TDS {
    using Cb2 = typename Cb::template Rebind_TDS<TDS2>::Other;
    using Other = CellBase<Gt, Cb2>;
  };
  using Cb::Cb;
  FacetInfo facet[4];
};

using Vb = CGAL::Triangulation_vertex_base_with_info_3<VInfo, GT>;
using Tds = CGAL::Triangulation_data_structure_3<Vb, CellBase<GT>>;
using Tr = CGAL::Delaunay_triangulation_3<GT, Tds>;  // Compact_location: see the notes
using Vh = Tr::Vertex_handle;
using Ch = Tr::Cell_handle;
using Facet = Tr::Facet;

inline Vec3 vec(const Point& p) { return {p.x(), p.y(), p.z()}; }
inline Vec3 sub(const Vec3& a, const Vec3& b) { return {a[0] - b[0], a[1] - b[1], a[2] - b[2]}; }
inline double dot(const Vec3& a, const Vec3& b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }
inline Vec3 cross(const Vec3& a, const Vec3& b) {
  return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
}
inline double norm(const Vec3& a) { return std::sqrt(dot(a, a)); }
inline double dist2(const Vec3& a, const Vec3& b) { Vec3 d = sub(a, b); return dot(d, d); }

// An undirected mesh edge as one number.
inline long long edge_key(int a, int b) { return (static_cast<long long>(std::min(a, b)) << 32) | std::max(a, b); }

// Radius-edge ratio R / l_min (Def. 4.3.1).
double ratio(const Vec3& a, const Vec3& b, const Vec3& c) {
  const double la = std::sqrt(dist2(b, c)), lb = std::sqrt(dist2(c, a)), lc = std::sqrt(dist2(a, b));
  const double area2 = norm(cross(sub(b, a), sub(c, a)));  // twice the area
  const double lmin = std::min({la, lb, lc});
  if (area2 <= 0 || lmin <= 0) return INFINITY;
  return la * lb * lc / (2 * area2) / lmin;
}

// The cube grid between voxel centres (thesis ch. 6): signs, active cubes and
// their components (F1, F4).
struct CubeGrid {
  const FloatImage& g;
  long n[3];
  double s[3];
  double hi[3];
  double delta;
  std::unordered_map<long long, int> comp;  // active cube -> S component
  int components = 0;

  // Activity of every cube (one byte each) and of blocks of kBlock^3 cubes,
  // so EdgeSurface crosses empty space a block at a time.
  static constexpr long kBlock = 8;
  std::vector<std::uint8_t> cube_active, block_active;
  long nb[3];

  explicit CubeGrid(const FloatImage& img) : g(img) {
    for (int i = 0; i < 3; ++i) {
      n[i] = long(img.size[i]);
      s[i] = img.spacing[i];
      hi[i] = double(n[i] - 1) * s[i];
      nb[i] = std::max(1L, (n[i] - 1 + kBlock - 1) / kBlock);
    }
    delta = std::min({s[0], s[1], s[2]});
    if (n[0] < 2 || n[1] < 2 || n[2] < 2) return;
    cube_active.assign(std::size_t((n[0] - 1) * (n[1] - 1) * (n[2] - 1)), 0);
    block_active.assign(std::size_t(nb[0] * nb[1] * nb[2]), 0);
    for (long z = 0; z + 1 < n[2]; ++z)
      for (long y = 0; y + 1 < n[1]; ++y)
        for (long x = 0; x + 1 < n[0]; ++x) {
          const bool s0 = neg(x, y, z);
          bool mixed = false;
          for (int k = 1; k < 8 && !mixed; ++k) mixed = neg(x + (k & 1), y + ((k >> 1) & 1), z + ((k >> 2) & 1)) != s0;
          if (!mixed) continue;
          cube_active[std::size_t(x + (n[0] - 1) * (y + (n[1] - 1) * z))] = 1;
          block_active[std::size_t(x / kBlock + nb[0] * (y / kBlock + nb[1] * (z / kBlock)))] = 1;
        }
  }
  bool neg(long x, long y, long z) const { return g(std::size_t(x), std::size_t(y), std::size_t(z)) < 0; }
  long long key(long x, long y, long z) const { return x + (long long)n[0] * (y + (long long)n[1] * z); }
  bool active(long x, long y, long z) const {
    if (x < 0 || y < 0 || z < 0 || x > n[0] - 2 || y > n[1] - 2 || z > n[2] - 2) return false;
    return cube_active[std::size_t(x + (n[0] - 1) * (y + (n[1] - 1) * z))];
  }
  bool block(long x, long y, long z) const {
    return block_active[std::size_t(x + nb[0] * (y + nb[1] * z))];
  }
  int comp_of(long x, long y, long z) const {
    auto it = comp.find(key(x, y, z));
    return it == comp.end() ? -1 : it->second;
  }
  // Label active cubes by components joined through mixed faces (F4).
  void label() {
    std::vector<std::array<long, 3>> stack;
    for (long z = 0; z + 1 < n[2]; ++z)
      for (long y = 0; y + 1 < n[1]; ++y)
        for (long x = 0; x + 1 < n[0]; ++x) {
          if (!active(x, y, z) || comp.count(key(x, y, z))) continue;
          const int c = components++;
          comp[key(x, y, z)] = c;
          stack.push_back({x, y, z});
          while (!stack.empty()) {
            auto q = stack.back();
            stack.pop_back();
            for (int a = 0; a < 3; ++a)
              for (int dir = -1; dir <= 1; dir += 2) {
                std::array<long, 3> r = q;
                r[a] += dir;
                if (!active(r[0], r[1], r[2]) || comp.count(key(r[0], r[1], r[2]))) continue;
                // The shared face: plane coordinate max(q[a], r[a]) on axis a.
                const long pa = std::max(q[a], r[a]);
                const int b = (a + 1) % 3, c2 = (a + 2) % 3;
                bool any_neg = false, any_pos = false;
                for (int k = 0; k < 4; ++k) {
                  std::array<long, 3> v = q;
                  v[a] = pa;
                  v[b] += k & 1;
                  v[c2] += (k >> 1) & 1;
                  (neg(v[0], v[1], v[2]) ? any_neg : any_pos) = true;
                }
                if (!(any_neg && any_pos)) continue;
                comp[key(r[0], r[1], r[2])] = c;
                stack.push_back(r);
              }
          }
        }
  }
  // Component of the active cube containing a local point (or a neighbour).
  int comp_at(const Vec3& q) const {
    long c[3];
    for (int i = 0; i < 3; ++i) c[i] = std::clamp(long(std::floor(q[i] / s[i])), 0L, n[i] - 2);
    int r = comp_of(c[0], c[1], c[2]);
    if (r >= 0) return r;
    for (int dz = -1; dz <= 1; ++dz)
      for (int dy = -1; dy <= 1; ++dy)
        for (int dx = -1; dx <= 1; ++dx)
          if ((r = comp_of(c[0] + dx, c[1] + dy, c[2] + dz)) >= 0) return r;
    return -1;
  }
  // Euler characteristic of bdCA(X) per S component: the boundary quad dual
  // to a mixed grid edge belongs to the component of the cubes around it.
  std::vector<int> euler_by_component() const {
    std::vector<std::pair<int, long long>> verts, edges;
    std::vector<long long> faces(components, 0);
    const long long cx = n[0] + 2, cy = n[1] + 2;
    auto corner = [&](long x, long y, long z) { return x + cx * (y + cy * (long long)z); };
    for (long z = 0; z < n[2]; ++z)
      for (long y = 0; y < n[1]; ++y)
        for (long x = 0; x < n[0]; ++x)
          for (int a = 0; a < 3; ++a) {
            long p[3] = {x, y, z};
            p[a] += 1;
            if (p[a] >= n[a] || neg(x, y, z) == neg(p[0], p[1], p[2])) continue;
            const int b = (a + 1) % 3, c = (a + 2) % 3;
            long cube[3] = {x, y, z};
            if (cube[b] > n[b] - 2) cube[b] -= 1;
            if (cube[c] > n[c] - 2) cube[c] -= 1;
            const int k = comp_of(cube[0], cube[1], cube[2]);
            if (k < 0) continue;
            faces[k] += 1;
            // Quad corners in corner coordinates (voxel v spans [v, v+1]).
            long o[3] = {x, y, z};
            o[a] += 1;
            long q[4][3];
            for (int i = 0; i < 4; ++i) std::copy(o, o + 3, q[i]);
            q[1][b] += 1; q[2][b] += 1; q[2][c] += 1; q[3][c] += 1;
            for (int i = 0; i < 4; ++i) verts.emplace_back(k, corner(q[i][0], q[i][1], q[i][2]));
            edges.emplace_back(k, corner(q[0][0], q[0][1], q[0][2]) * 3 + b);
            edges.emplace_back(k, corner(q[0][0], q[0][1], q[0][2]) * 3 + c);
            edges.emplace_back(k, corner(q[1][0], q[1][1], q[1][2]) * 3 + c);
            edges.emplace_back(k, corner(q[3][0], q[3][1], q[3][2]) * 3 + b);
          }
    std::sort(verts.begin(), verts.end());
    verts.erase(std::unique(verts.begin(), verts.end()), verts.end());
    std::sort(edges.begin(), edges.end());
    edges.erase(std::unique(edges.begin(), edges.end()), edges.end());
    std::vector<int> chi(faces.begin(), faces.end());
    for (auto& v : verts) chi[v.first] += 1;
    for (auto& e : edges) chi[e.first] -= 1;
    return chi;
  }
};

struct EdgeCrossing {
  int count = 0;  // 0, 1 or 2 (two or more)
  Vec3 x{0, 0, 0};
};

struct HalfSpace {  // d.x <= c
  Vec3 d;
  double c;
};

// Vertex ids, each once, in the order they came, with O(1) membership.
struct IdSet {
  std::vector<char> in;
  std::vector<int> ids;
  void add(int id) {
    if (std::size_t(id) >= in.size()) in.resize(std::size_t(id) + 1, 0);
    if (!in[std::size_t(id)]) {
      in[std::size_t(id)] = 1;
      ids.push_back(id);
    }
  }
  bool has(int id) const { return std::size_t(id) < in.size() && in[std::size_t(id)]; }
  void clear() {
    for (int id : ids) in[std::size_t(id)] = 0;
    ids.clear();
  }
};

class Mesher {
public:
  Mesher(const ImplicitSurface& surface, const RestrictedDelaunayOptions& opt)
      : f_(surface), opt_(opt), grid_(surface.samples()), topology_only_(opt.seed_deletion) {}

  RestrictedDelaunayResult run();

private:
  using Clock = std::chrono::steady_clock;
  enum Kind { kQVorEdge, kQTopoDisk, kQQuality, kQSmooth, kQDistance };
  struct Item {
    int kind;
    double prio;
    std::uint64_t seq;
    Vh a, b, c;  // a facet (a, b, c) or a vertex a
    Ch cell;     // the facet as (cell, index) when it was queued
    int index;
    std::uint32_t computed;  // FacetInfo::computed when it was queued
    bool operator<(const Item& o) const {  // std::priority_queue pops the largest
      if (kind != o.kind) return kind > o.kind;
      if (prio != o.prio) return prio < o.prio;
      return seq > o.seq;
    }
  };

  const ImplicitSurface& f_;
  RestrictedDelaunayOptions opt_;
  CubeGrid grid_;
  Tr tr_;
  std::vector<Vh> vertices_;  // by id; null where a vertex was deleted
  Vh walk_start_;             // a live vertex near the last change
  std::priority_queue<Item> queue_;
  std::uint64_t seq_ = 0;
  std::uint32_t computed_ = 0;  // facet computations so far
  long long inserted_[kOrigins] = {};
  long long refused_ = 0;
  std::atomic<long long> evaluations_{0};  // also counted by FacetCycle's threads
  bool max_hit_ = false;
  std::size_t last_progress_ = 0;
  std::string phase_ = "seeds";
  // Scratch buffers of the vertex checks (no allocation per check).
  std::vector<Facet> facets_buf_;
  std::vector<std::pair<int, int>> link_;
  std::vector<int> ends_;
  std::vector<char> used_;
  // FacetCycle: vertices inserted since the last pass. Insertions create
  // only edges at the new vertex and only shrink the other Voronoi facets,
  // and a cycle inside a shrunken facet was inside it before (notes 2.7).
  IdSet dirty_;
  // SAMPLETOPOLOGY (7.6.2): only the topology queues run, so that seeds can
  // be deleted with no QUALITY/SMOOTH entry pointing at them.
  bool topology_only_ = false;
  long long seeds_deleted_ = 0;
  std::vector<int> comp_vertices_;  // vertices per S component
  long long facet_cycle_checks_ = 0, facet_cycle_passes_ = 0, handle_checks_ = 0, handle_certified_ = 0;
  std::vector<std::pair<int, Vec3>> normals_;
  // Insertion scratch: the conflict zone and the vertices around it.
  std::vector<Facet> zone_facets_;
  std::vector<Ch> zone_cells_, cells_buf_;
  std::vector<Vh> touched_;
  std::uint32_t stamp_ = 0;

  double value(const Vec3& q) {
    evaluations_.fetch_add(1, std::memory_order_relaxed);
    Vec3 c = q;
    for (int i = 0; i < 3; ++i) c[i] = std::clamp(c[i], 0.0, grid_.hi[i]);
    return f_.value(c);
  }
  Vec3 gradient(const Vec3& q) {
    Vec3 c = q, gr;
    for (int i = 0; i < 3; ++i) c[i] = std::clamp(c[i], 0.0, grid_.hi[i]);
    f_.value_gradient(c, gr);
    return gr;
  }
  // Sign convention for zeros (8.4(1)): f == 0 counts as outside, i.e. we
  // mesh f^-1(-eps) symbolically, consistently on every edge.
  static bool inside(double v) { return v < 0; }

  Vec3 bisect(Vec3 a, Vec3 b, double fa);
  EdgeCrossing edge_surface(const Vec3& a, const Vec3& b, const Vec3& site);
  void compute_facet(Ch c, int i);
  FacetInfo edge_surface_of(Ch c, int i);
  void enqueue_facet(Ch c, int i);
  void enqueue_vertex(Vh v);
  bool insert(const Vec3& x, Origin origin, Facet hint = Facet(Ch(), 0));
  void after_insertion(Vh v);
  void compute_new_cells();
  void add_vertex(Vh v, Origin origin, const Vec3& x);
  bool remove_vertex(Vh v);
  bool delete_and_restore(Vh v);
  // The HandleDetection point being deleted (8.3): it goes back if
  // HandleDetection finds a handle again.
  std::optional<Vec3> handle_trial_;
  long long handle_points_deleted_ = 0, handle_points_restored_ = 0;
  void delete_seeds();
  void requeue_grown();
  std::vector<int> grown_;  // ids of the neighbours of deleted vertices
  void refine();
  void mark_restricted(Ch c, int i);
  void seeds();
  void restricted_around(Vh v);
  bool topo_disk(Vh v, Facet* worst);
  bool smooth(Vh v, Facet* worst);
  void drain();
  bool facet_of(const Item& it, Ch& c, int& i) const;
  Vec3 facet_center(const Facet& f) const {
    const FacetInfo& fi = f.first->facet[f.second];
    return {fi.x[0], fi.x[1], fi.x[2]};
  }
  void progress() {
    if (opt_.progress && vertices_.size() >= last_progress_ + 5000) {
      last_progress_ = vertices_.size();
      opt_.progress(phase_ + ": " + std::to_string(tr_.number_of_vertices()) + " points");
    }
  }
  // A finite facet's vertices by id. CGAL stores a facet on either side and
  // vertex removal makes the side depend on addresses: every construction
  // from a facet's vertices (site, normals, ratios) uses this order, so the
  // last bits, and so the output, are the same on every run.
  static std::array<Vh, 3> facet_vertices(Ch c, int i) {
    std::array<Vh, 3> v{c->vertex((i + 1) & 3), c->vertex((i + 2) & 3), c->vertex((i + 3) & 3)};
    std::sort(v.begin(), v.end(), [](Vh a, Vh b) { return a->info().id < b->info().id; });
    return v;
  }
  // Restricted facets in a deterministic order (by vertex ids).
  std::vector<Facet> restricted_facets() const;
  bool fallback(const std::vector<int>& bad_components);
  bool handle_detection(Vh p, Vec3& q);
  bool handle_free(Vh p);
  // V(p): |x - p|^2 <= |x - w|^2 for every Delaunay neighbour w (thread-safe).
  void voronoi_cell(Vh p, std::vector<HalfSpace>& hs) const {
    thread_local std::vector<Vh> adj;
    adj.clear();
    tr_.adjacent_vertices_threadsafe(p, std::back_inserter(adj));
    const Vec3 pp = vec(p->point());
    hs.clear();
    for (Vh w : adj)
      if (!tr_.is_infinite(w)) {
        const Vec3 pw = vec(w->point());
        hs.push_back({sub(pw, pp), (dot(pw, pw) - dot(pp, pp)) / 2});
      }
  }
  bool handle_vertex_pass();
  // HandleDetection: vertices whose Voronoi cell changed since their check.
  IdSet cell_changed_;
  bool handle_pass(const std::vector<int>& bad_components);
  bool facet_cycle(const Tr::Edge& e, Vec3& x);
  bool facet_cycle_pass();
  bool insert_batch(const std::vector<std::pair<Vec3, double>>& pts, Origin origin);
};

Vec3 Mesher::bisect(Vec3 a, Vec3 b, double fa) {
  // Illinois regula falsi with a bisection safeguard (when the bracket
  // shrinks slowly), to ~1e-11 delta.
  double fb = value(b);
  const bool ia = inside(fa);
  const double tol2 = std::pow(1e-11 * grid_.delta, 2);
  int side = 0;
  double width2 = dist2(a, b);
  for (int it = 0; it < 200 && dist2(a, b) > tol2; ++it) {
    double t = (fa - fb) != 0 ? fa / (fa - fb) : 0.5;
    if (!(t > 0 && t < 1)) t = 0.5;
    if (it % 3 == 2) {  // less than halved in three steps: bisect
      const double w2 = dist2(a, b);
      if (w2 > width2 / 4) t = 0.5;
      width2 = w2;
    }
    Vec3 m{a[0] + t * (b[0] - a[0]), a[1] + t * (b[1] - a[1]), a[2] + t * (b[2] - a[2])};
    const double fm = value(m);
    if (inside(fm) == ia) {
      a = m; fa = fm;
      if (side == -1) fb /= 2;
      side = -1;
    } else {
      b = m; fb = fm;
      if (side == 1) fa /= 2;
      side = 1;
    }
  }
  return std::abs(fa) <= std::abs(fb) ? a : b;
}

// EdgeSurface (8.2): clip the Voronoi edge to the box of voxel centres, walk
// the cubes it crosses, look for roots only in active cubes (F1), and find the
// first and the last crossing. Roots are isolated by sampling at delta/8
// inside active cubes, then refined; two roots closer than that are missed
// (documented limitation, see the man page).
EdgeCrossing Mesher::edge_surface(const Vec3& a, const Vec3& b, const Vec3& site) {
  EdgeCrossing out;
  const Vec3 d = sub(b, a);
  double t0 = 0, t1 = 1;
  for (int i = 0; i < 3; ++i) {
    if (d[i] == 0) {
      if (a[i] < 0 || a[i] > grid_.hi[i]) return out;
      continue;
    }
    double ta = (0 - a[i]) / d[i], tb = (grid_.hi[i] - a[i]) / d[i];
    if (ta > tb) std::swap(ta, tb);
    t0 = std::max(t0, ta);
    t1 = std::min(t1, tb);
  }
  if (!(t0 < t1)) return out;
  auto at = [&](double t) -> Vec3 {
    if (t == 0) return a;  // Voronoi vertices bit-exact: consistent signs (8.4(1))
    if (t == 1) return b;
    return {a[0] + t * d[0], a[1] + t * d[1], a[2] + t * d[2]};
  };
  // Pieces of [t0, t1] inside active cubes, in order: where the segment
  // crosses planes spaced `step` (Amanatides-Woo's events), first at the
  // block level, then cube by cube inside active blocks.
  auto breakpoints = [&](double ta, double tb, const double step[3], std::vector<double>& ts) {
    ts.assign({ta, tb});
    for (int i = 0; i < 3; ++i) {
      if (d[i] == 0) continue;
      const double lo = std::min(a[i] + ta * d[i], a[i] + tb * d[i]);
      const double hi = std::max(a[i] + ta * d[i], a[i] + tb * d[i]);
      for (long k = long(std::ceil(lo / step[i])); k <= long(std::floor(hi / step[i])); ++k) {
        const double t = (double(k) * step[i] - a[i]) / d[i];
        if (t > ta && t < tb) ts.push_back(t);
      }
    }
    std::sort(ts.begin(), ts.end());
  };
  // Scratch reused across calls (no allocation per facet).
  thread_local std::vector<double> tblock, tcube;
  struct Piece { double ta, tb; };
  thread_local std::vector<Piece> pieces;
  pieces.clear();
  const double bstep[3] = {grid_.s[0] * CubeGrid::kBlock, grid_.s[1] * CubeGrid::kBlock, grid_.s[2] * CubeGrid::kBlock};
  breakpoints(t0, t1, bstep, tblock);
  for (std::size_t kb = 0; kb + 1 < tblock.size(); ++kb) {
    if (!(tblock[kb + 1] > tblock[kb])) continue;
    const Vec3 mb = at((tblock[kb] + tblock[kb + 1]) / 2);
    long cb[3];
    for (int i = 0; i < 3; ++i) cb[i] = std::clamp(long(std::floor(mb[i] / bstep[i])), 0L, grid_.nb[i] - 1);
    if (!grid_.block(cb[0], cb[1], cb[2])) continue;
    breakpoints(tblock[kb], tblock[kb + 1], grid_.s, tcube);
    for (std::size_t k = 0; k + 1 < tcube.size(); ++k) {
      const double ta = tcube[k], tb = tcube[k + 1];
      if (!(tb > ta)) continue;
      const Vec3 m = at((ta + tb) / 2);
      long c[3];
      for (int i = 0; i < 3; ++i) c[i] = std::clamp(long(std::floor(m[i] / grid_.s[i])), 0L, grid_.n[i] - 2);
      if (!grid_.active(c[0], c[1], c[2])) continue;
      if (!pieces.empty() && pieces.back().tb == ta) pieces.back().tb = tb;  // merge runs of active cubes
      else pieces.push_back({ta, tb});
    }
  }
  if (pieces.empty()) return out;
  const double len = norm(d);
  const double step = grid_.delta / 8;
  // All sign changes of one piece, as sample pairs.
  // Near-tangential crossings (8.4(2)): where |f| has a local minimum between
  // three samples of one sign that may dip through zero, search the minimum
  // (golden section). A sign change there gives two crossings; a minimum at
  // |f| ~ 0 is a tangency, reported as a double root at that point (VorEdge
  // inserts it, Lemma 8.4.1).
  auto dip = [&](double ta, double tb, bool in, std::vector<std::pair<double, double>>& ch, std::vector<double>& fv) {
    const double g = 0.6180339887498949;
    const double s = in ? -1 : 1;  // minimise s * f
    double a = ta, b = tb, c = b - g * (b - a), d = a + g * (b - a);
    double fc = value(at(c)), fd = value(at(d));
    for (int it = 0; it < 40; ++it) {
      for (double tt : {c, d}) {
        const double ft = tt == c ? fc : fd;
        if (inside(ft) != in) {  // crossed: two sign changes around tt
          ch.emplace_back(ta, tt);
          fv.push_back(value(at(ta)));
          ch.emplace_back(tt, tb);
          fv.push_back(ft);
          return;
        }
      }
      if ((b - a) * len < 1e-9 * grid_.delta) break;
      if (s * fc < s * fd) {
        b = d; d = c; fd = fc; c = b - g * (b - a); fc = value(at(c));
      } else {
        a = c; c = d; fc = fd; d = a + g * (b - a); fd = value(at(d));
      }
    }
    const double tm = s * fc < s * fd ? c : d, fm = std::min(std::abs(fc), std::abs(fd));
    if (fm < 1e-9 * grid_.delta) {  // tangency: a double root
      ch.emplace_back(tm, tm);
      fv.push_back(fm);
      ch.emplace_back(tm, tm);
      fv.push_back(fm);
    }
  };
  // All sign changes of one piece, as sample pairs, in order.
  auto changes = [&](const Piece& p, std::vector<std::pair<double, double>>& ch, std::vector<double>& fv) {
    const int m = std::max(2, int(std::ceil((p.tb - p.ta) * len / step)));
    double tq = p.ta, fq = 0;  // the sample before the previous one
    double tp = p.ta, fp = value(at(tp));
    for (int k = 1; k <= m; ++k) {
      const double t = k == m ? p.tb : p.ta + (p.tb - p.ta) * k / m;
      const double fc = value(at(t));
      if (inside(fc) != inside(fp)) {
        ch.emplace_back(tp, t);
        fv.push_back(fp);
      } else if (k >= 2 && inside(fq) == inside(fp) && std::abs(fp) < std::abs(fq) && std::abs(fp) < std::abs(fc) &&
                 std::abs(fp) < std::abs(fq - fp) + std::abs(fc - fp)) {
        dip(tq, t, inside(fp), ch, fv);
      }
      tq = tp;
      fq = fp;
      tp = t;
      fp = fc;
    }
  };
  // Forward to the first piece with a root, backward to the last one.
  std::size_t first = pieces.size();
  thread_local std::vector<std::pair<double, double>> ch_first, ch_last;
  thread_local std::vector<double> fv_first, fv_last;
  ch_first.clear(); ch_last.clear(); fv_first.clear(); fv_last.clear();
  for (std::size_t k = 0; k < pieces.size(); ++k) {
    changes(pieces[k], ch_first, fv_first);
    if (!ch_first.empty()) { first = k; break; }
  }
  if (first == pieces.size()) return out;
  for (std::size_t k = pieces.size() - 1; k > first; --k) {
    changes(pieces[k], ch_last, fv_last);
    if (!ch_last.empty()) break;
  }
  const Vec3 x0 = bisect(at(ch_first.front().first), at(ch_first.front().second), fv_first.front());
  out.count = 1;
  out.x = x0;
  Vec3 x1 = x0;
  if (!ch_last.empty()) {
    x1 = bisect(at(ch_last.back().first), at(ch_last.back().second), fv_last.back());
    out.count = 2;
  } else if (ch_first.size() > 1) {
    x1 = bisect(at(ch_first.back().first), at(ch_first.back().second), fv_first.back());
    out.count = 2;
  }
  // x_t: the crossing farthest from the facet's vertices (7.6: largest ball).
  if (out.count == 2 && dist2(x1, site) > dist2(x0, site)) out.x = x1;
  return out;
}

void Mesher::compute_facet(Ch c, int i) {
  FacetInfo fi = edge_surface_of(c, i);
  fi.computed = ++computed_;
  Ch n = c->neighbor(i);
  c->facet[i] = fi;
  n->facet[n->index(c)] = fi;
  enqueue_facet(c, i);
}

// EdgeSurface for the Voronoi edge dual to facet (c, i).
FacetInfo Mesher::edge_surface_of(Ch c, int i) {
  Ch n = c->neighbor(i);
  const int j = n->index(c);
  FacetInfo fi;
  fi.state = kComputed;
  if (!tr_.is_infinite(c, i)) {
    const std::array<Vh, 3> fv = facet_vertices(c, i);
    const Vec3 p0 = vec(fv[0]->point());
    const bool ci = tr_.is_infinite(c), ni = tr_.is_infinite(n);
    Vec3 a, b;
    bool ok = true;
    if (!ci && !ni) {
      a = vec(tr_.dual(c));
      b = vec(tr_.dual(n));
      if (b < a) std::swap(a, b);  // lexicographic: both sides agree bit for bit
      ok = a != b;                 // zero-length Voronoi edge: not restricted
    } else {
      // A ray from the finite cell's circumcentre, away from its fourth vertex.
      Ch fc = ci ? n : c;
      const int fi_ = ci ? j : i;
      const Vec3 q0 = p0, q1 = vec(fv[1]->point()), q2 = vec(fv[2]->point()), opp = vec(fc->vertex(fi_)->point());
      Vec3 nrm = cross(sub(q1, q0), sub(q2, q0));
      if (dot(nrm, sub(opp, q0)) > 0) nrm = {-nrm[0], -nrm[1], -nrm[2]};
      const double nl = norm(nrm);
      ok = nl > 0;
      if (ok) {
        a = vec(tr_.dual(fc));
        double reach = 0;  // far enough to leave the box
        for (int k = 0; k < 3; ++k) reach += std::abs(a[k]) + grid_.hi[k];
        b = {a[0] + nrm[0] / nl * reach, a[1] + nrm[1] / nl * reach, a[2] + nrm[2] / nl * reach};
      }
    }
    if (ok) {
      const EdgeCrossing e = edge_surface(a, b, p0);
      if (e.count > 0) {
        fi.state |= kRestricted;
        if (e.count > 1) fi.state |= kMulti;
        std::copy(e.x.begin(), e.x.end(), fi.x);
        fi.r2 = dist2(e.x, p0);
        const Vec3 gr = gradient(e.x);
        for (int k = 0; k < 3; ++k) fi.grad[k] = float(gr[k]);
      }
    }
  }
  return fi;
}

void Mesher::enqueue_facet(Ch c, int i) {
  const FacetInfo& fi = c->facet[i];
  if (!(fi.state & kRestricted)) return;
  const auto [a, b, d] = facet_vertices(c, i);
  if (fi.state & kMulti) queue_.push({kQVorEdge, fi.r2, seq_++, a, b, d, c, i, fi.computed});
  const Vec3 pa = vec(a->point()), pb = vec(b->point()), pd = vec(d->point());
  if (topology_only_) return;
  if (ratio(pa, pb, pd) > opt_.ratio) queue_.push({kQQuality, fi.r2, seq_++, a, b, d, c, i, fi.computed});
  if (opt_.max_distance > 0) {
    Vec3 nrm = cross(sub(pb, pa), sub(pd, pa));
    const double nl = norm(nrm);
    const Vec3 x{fi.x[0], fi.x[1], fi.x[2]};
    if (nl > 0 && std::abs(dot(nrm, sub(x, pa))) / nl > opt_.max_distance)
      queue_.push({kQDistance, fi.r2, seq_++, a, b, d, c, i, fi.computed});
  }
}

// A vertex is queued at most once per check: the check runs on the state at
// pop time, which includes every change since it was queued.
void Mesher::enqueue_vertex(Vh v) {
  if (!(v->info().queued & 1)) queue_.push({kQTopoDisk, 0, seq_++, v, Vh(), Vh(), Ch(), 0, 0});
  v->info().queued |= 1;
  if (topology_only_) return;
  if (!(v->info().queued & 2)) queue_.push({kQSmooth, 0, seq_++, v, Vh(), Vh(), Ch(), 0, 0});
  v->info().queued |= 2;
}

bool Mesher::insert(const Vec3& x, Origin origin, Facet hint) {
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
  // conflict zone starts there without a walk (notes 2, step 3).
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
    for (int m = 1; m < 4; ++m)
      if (f.first->vertex((f.second + m) & 3)->point() == p) return false;
  // Vertices whose restricted facets die: TopoDisk/SMOOTH re-check them.
  ++stamp_;
  touched_.clear();
  for (Ch c : zone_cells_)
    for (int i = 0; i < 4; ++i) mark_restricted(c, i);
  Vh v = tr_.insert_in_hole(p, zone_cells_.begin(), zone_cells_.end(), zone_facets_[0].first, zone_facets_[0].second);
  add_vertex(v, origin, x);
  after_insertion(v);
  progress();
  return true;
}

void Mesher::add_vertex(Vh v, Origin origin, const Vec3& x) {
  v->info() = {int(vertices_.size()), std::uint8_t(origin), grid_.comp_at(x)};
  vertices_.push_back(v);
  walk_start_ = v;
  ++inserted_[origin];
  if (v->info().comp >= 0) ++comp_vertices_[std::size_t(v->info().comp)];
}

// Deletion (7.6.2, 8.3): the cells around v are replaced by a Delaunay
// triangulation of its link (CGAL's remove), and the facets of the new cells
// are computed anew. v's neighbours gained Voronoi volume: TopoDisk,
// FacetCycle and HandleDetection check them again. False if v had to stay.
bool Mesher::remove_vertex(Vh v) {
  std::vector<Vh> adj;
  tr_.adjacent_vertices(v, std::back_inserter(adj));
  const Vec3 x = vec(v->point());
  const Origin origin = Origin(v->info().origin);
  vertices_[std::size_t(v->info().id)] = Vh();
  if (v->info().comp >= 0) --comp_vertices_[std::size_t(v->info().comp)];
  cells_buf_.clear();
  tr_.remove_and_give_new_cells(v, std::back_inserter(cells_buf_));
  if (tr_.dimension() < 3) {  // the rest is coplanar: put it back (bootstrap)
    insert(x, origin);
    --inserted_[origin];
    return false;
  }
  compute_new_cells();
  for (Vh w : adj)
    if (!tr_.is_infinite(w)) {
      walk_start_ = w;
      grown_.push_back(w->info().id);
      cell_changed_.add(w->info().id);
    }
  return true;
}

// Deletes v, then TOPOLOGY restores the closed ball property (Lemma 7.6.3).
// A component keeps at least two vertices (notes 4.5): with fewer, it can
// hide inside one Voronoi cell, where no Voronoi edge sees it.
bool Mesher::delete_and_restore(Vh v) {
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
void Mesher::delete_seeds() {
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
void Mesher::requeue_grown() {
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

// TOPOLOGY and the other queues until they drain, then FacetCycle and
// HandleDetection passes over what changed, until none inserts.
void Mesher::refine() {
  for (;;) {
    drain();
    if (max_hit_) return;
    if (opt_.facet_cycle && facet_cycle_pass()) continue;
    if (!handle_vertex_pass()) return;
  }
}

// The facets of the new cells cells_buf_, computed (and so queued) in the
// order of their vertex ids, not CGAL's storage order: vertex removal makes
// that depend on addresses, and the queue's ties would then differ from run
// to run.
void Mesher::compute_new_cells() {
  for (Ch c : cells_buf_) c->facet[0].state = c->facet[1].state = c->facet[2].state = c->facet[3].state = 0;
  thread_local std::vector<std::pair<std::array<int, 3>, Facet>> order;
  order.clear();
  for (Ch c : cells_buf_)
    for (int i = 0; i < 4; ++i) {
      std::array<int, 3> ids;
      for (int m = 1; m < 4; ++m) {
        const Vh w = c->vertex((i + m) & 3);
        ids[m - 1] = tr_.is_infinite(w) ? -1 : w->info().id;
      }
      std::sort(ids.begin(), ids.end());
      order.emplace_back(ids, Facet(c, i));
    }
  std::sort(order.begin(), order.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
  for (const auto& [ids, f] : order)
    if (!(f.first->facet[f.second].state & kComputed)) compute_facet(f.first, f.second);
}

// Remember the finite vertices of facet (c, i) if it is restricted.
void Mesher::mark_restricted(Ch c, int i) {
  if (!(c->facet[i].state & kRestricted)) return;
  for (int m = 1; m < 4; ++m) {
    Vh w = c->vertex((i + m) & 3);
    if (w->info().stamp != stamp_) {
      w->info().stamp = stamp_;
      touched_.push_back(w);
    }
  }
}

// The new cells are exactly the cells incident to v: recompute their facets
// (both sides), and re-check the vertices whose restricted facets changed.
// An edge's Voronoi facet changed only if both its ends are in the cavity.
void Mesher::after_insertion(Vh v) {
  cells_buf_.clear();
  tr_.incident_cells(v, std::back_inserter(cells_buf_));
  compute_new_cells();
  for (Ch c : cells_buf_)
    for (int i = 0; i < 4; ++i) mark_restricted(c, i);
  enqueue_vertex(v);
  std::sort(touched_.begin(), touched_.end(), [](Vh a, Vh b) { return a->info().id < b->info().id; });
  for (Vh w : touched_) enqueue_vertex(w);
  dirty_.add(v->info().id);
  for (Ch c : cells_buf_)
    for (int i = 0; i < 4; ++i)
      if (!tr_.is_infinite(c->vertex(i))) cell_changed_.add(c->vertex(i)->info().id);
}

// Seeds (8.1): on every component of S, crossings of mixed cube edges in the
// component's extremal cubes along +-x, +-y, +-z (at least two per
// component); no critical points needed.
void Mesher::seeds() {
  std::vector<std::array<long, 4>> extreme(std::size_t(grid_.components) * 6, {-1, 0, 0, 0});
  std::vector<std::pair<long long, int>> cubes(grid_.comp.begin(), grid_.comp.end());
  std::sort(cubes.begin(), cubes.end());  // deterministic
  for (auto& kc : cubes) {
    long long k = kc.first;
    const long x = long(k % grid_.n[0]), y = long((k / grid_.n[0]) % grid_.n[1]), z = long(k / grid_.n[0] / grid_.n[1]);
    const long c[3] = {x, y, z};
    for (int a = 0; a < 3; ++a)
      for (int s = 0; s < 2; ++s) {
        auto& e = extreme[std::size_t(kc.second) * 6 + a * 2 + s];
        if (e[0] < 0 || (s == 0 ? c[a] < e[1 + a] : c[a] > e[1 + a])) e = {1, x, y, z};
      }
  }
  // The crossing on the `which`-th mixed edge of cube (x,y,z): unique, f
  // monotone along the edge (F2).
  auto crossing = [&](long x, long y, long z, Vec3& out, int which = 0) {
    static const int edges[12][2] = {{0, 1}, {2, 3}, {4, 5}, {6, 7}, {0, 2}, {1, 3}, {4, 6}, {5, 7}, {0, 4}, {1, 5}, {2, 6}, {3, 7}};
    for (auto& e : edges) {
      long p[2][3];
      for (int k = 0; k < 2; ++k) {
        p[k][0] = x + (e[k] & 1);
        p[k][1] = y + ((e[k] >> 1) & 1);
        p[k][2] = z + ((e[k] >> 2) & 1);
      }
      if (grid_.neg(p[0][0], p[0][1], p[0][2]) == grid_.neg(p[1][0], p[1][1], p[1][2])) continue;
      if (which-- > 0) continue;
      const Vec3 a{p[0][0] * grid_.s[0], p[0][1] * grid_.s[1], p[0][2] * grid_.s[2]};
      const Vec3 b{p[1][0] * grid_.s[0], p[1][1] * grid_.s[1], p[1][2] * grid_.s[2]};
      out = bisect(a, b, value(a));
      return true;
    }
    return false;
  };
  std::vector<Vec3> pts;
  for (auto& e : extreme) {
    Vec3 x;
    if (e[0] >= 0 && crossing(e[1], e[2], e[3], x)) pts.push_back(x);
  }
  std::sort(pts.begin(), pts.end());
  pts.erase(std::unique(pts.begin(), pts.end()), pts.end());
  std::mt19937_64 rng(opt_.seed);
  std::shuffle(pts.begin(), pts.end(), rng);
  for (const Vec3& x : pts) insert(x, kSeed);
  // Degenerate seed sets (a single voxel, a one-voxel rod): add crossings of
  // other mixed edges until the triangulation is 3D.
  for (std::size_t k = 0; tr_.dimension() < 3 && k < cubes.size(); k += std::max<std::size_t>(1, cubes.size() / 64)) {
    const long long key = cubes[k].first;
    Vec3 x;
    for (int which = 0; tr_.dimension() < 3 && which < 12; ++which)
      if (crossing(long(key % grid_.n[0]), long((key / grid_.n[0]) % grid_.n[1]), long(key / grid_.n[0] / grid_.n[1]), x, which))
        insert(x, kSeed);
  }
  if (tr_.dimension() < 3) throw Error("cannot place four non-coplanar seed points on the surface");
}

// TopoDisk (7.6.1): the restricted facets around v form one closed disk:
// every link vertex in two link edges, and the link edges one cycle.
// The restricted facets incident to v, each once, into facets_buf_.
void Mesher::restricted_around(Vh v) {
  facets_buf_.clear();
  cells_buf_.clear();
  tr_.incident_cells(v, std::back_inserter(cells_buf_));
  for (Ch c : cells_buf_) {
    const int iv = c->index(v);
    for (int i = 0; i < 4; ++i) {
      if (i == iv || !(c->facet[i].state & kRestricted)) continue;
      Ch n = c->neighbor(i);  // also around v: take the facet from one side
      if (&*c < &*n) facets_buf_.emplace_back(c, i);
    }
  }
}

bool Mesher::topo_disk(Vh v, Facet* worst) {
  restricted_around(v);
  link_.clear();
  double best = -1;
  for (const Facet& f : facets_buf_) {
    const FacetInfo& fi = f.first->facet[f.second];
    if (!(fi.state & kRestricted)) continue;
    int ids[2], k = 0;
    for (int m = 1; m < 4; ++m) {
      Vh w = f.first->vertex((f.second + m) & 3);
      if (w != v) ids[k++] = w->info().id;
    }
    link_.emplace_back(ids[0], ids[1]);
    if (fi.r2 > best) {
      best = fi.r2;
      *worst = f;
    }
  }
  if (link_.empty()) return true;
  ends_.clear();
  for (auto& e : link_) {
    ends_.push_back(e.first);
    ends_.push_back(e.second);
  }
  std::sort(ends_.begin(), ends_.end());
  for (std::size_t i = 0; i < ends_.size(); i += 2)
    if (ends_[i] != ends_[i + 1] || (i + 2 < ends_.size() && ends_[i + 2] == ends_[i])) return false;
  // Walk the cycle from the first edge.
  used_.assign(link_.size(), 0);
  used_[0] = 1;
  const int start = link_[0].first;
  int cur = link_[0].second;
  std::size_t steps = 1;
  while (cur != start) {
    std::size_t k = 0;
    for (; k < link_.size(); ++k)
      if (!used_[k] && (link_[k].first == cur || link_[k].second == cur)) break;
    if (k == link_.size()) return false;
    used_[k] = 1;
    cur = link_[k].first == cur ? link_[k].second : link_[k].first;
    ++steps;
  }
  return steps == link_.size();
}

// SMOOTH (7.6.4): the roughness of an edge (v, u), the angle between the
// oriented normals of its two restricted facets, stays below g.
bool Mesher::smooth(Vh v, Facet* worst) {
  restricted_around(v);
  normals_.clear();  // (other vertex of the edge, oriented unit normal)
  double best = -1;
  for (const Facet& f : facets_buf_) {
    const FacetInfo& fi = f.first->facet[f.second];
    if (!(fi.state & kRestricted)) continue;
    const std::array<Vh, 3> fv = facet_vertices(f.first, f.second);
    const Vec3 a = vec(fv[0]->point()), b = vec(fv[1]->point()), c = vec(fv[2]->point());
    Vec3 n = cross(sub(b, a), sub(c, a));
    const double nl = norm(n);
    if (nl <= 0) continue;
    const Vec3 gr{fi.grad[0], fi.grad[1], fi.grad[2]};
    const double s = dot(n, gr) < 0 ? -1 / nl : 1 / nl;
    n = {n[0] * s, n[1] * s, n[2] * s};
    for (int m = 1; m < 4; ++m) {
      Vh w = f.first->vertex((f.second + m) & 3);
      if (w != v) normals_.emplace_back(w->info().id, n);
    }
    if (fi.r2 > best) {
      best = fi.r2;
      *worst = f;
    }
  }
  std::sort(normals_.begin(), normals_.end(), [](const auto& x, const auto& y) { return x.first < y.first; });
  for (std::size_t i = 0; i + 1 < normals_.size();) {
    std::size_t j = i;
    while (j < normals_.size() && normals_[j].first == normals_[i].first) ++j;
    if (j - i == 2) {  // other counts are TopoDisk's business
      const double c = std::clamp(dot(normals_[i].second, normals_[i + 1].second), -1.0, 1.0);
      if (std::acos(c) > opt_.roughness) return false;
    }
    i = j;
  }
  return true;
}

// The queued facet, if its cell is still alive and still holds its three
// vertices at the queued index (O(1); a dead facet's cell died with it, and a
// re-created facet was queued again from its new cell).
bool Mesher::facet_of(const Item& it, Ch& c, int& i) const {
  if (!tr_.tds().cells().is_used(it.cell)) return false;
  c = it.cell;
  i = it.index;
  for (int m = 1; m < 4; ++m) {
    Vh w = c->vertex((i + m) & 3);
    if (w != it.a && w != it.b && w != it.c) return false;
  }
  return true;
}

// DELMESH as one loop over prioritised queues (notes 4.8): VorEdge, TopoDisk,
// QUALITY, SMOOTH, max-distance; every insertion re-queues only what changed.
void Mesher::drain() {
  const double guard2 = std::pow(1e-3 * grid_.delta, 2);  // quality/smooth minimum distance
  while (!queue_.empty() && !max_hit_) {
    const Item it = queue_.top();
    queue_.pop();
    if (it.kind == kQTopoDisk || it.kind == kQSmooth) {
      it.a->info().queued &= std::uint8_t(it.kind == kQTopoDisk ? ~1 : ~2);
      Facet worst;
      if (it.kind == kQTopoDisk) {
        phase_ = "topology";
        if (topo_disk(it.a, &worst)) continue;
        if (!insert(facet_center(worst), kTopoDisk, worst)) ++refused_;
      } else {
        phase_ = "smooth";
        if (smooth(it.a, &worst)) continue;
        if (worst.first->facet[worst.second].r2 < guard2 || !insert(facet_center(worst), kSmooth, worst)) ++refused_;
      }
      continue;
    }
    Ch c;
    int i;
    if (!facet_of(it, c, i)) continue;  // facet destroyed since
    const FacetInfo& fi = c->facet[i];
    if (!(fi.state & kRestricted) || fi.computed != it.computed) continue;  // stale entry
    const Vec3 x{fi.x[0], fi.x[1], fi.x[2]};
    if (it.kind == kQVorEdge) {
      phase_ = "topology";
      if (!(fi.state & kMulti)) continue;
      if (!insert(x, kVorEdge, Facet(c, i))) ++refused_;
    } else {
      phase_ = it.kind == kQQuality ? "quality" : "max-distance";
      if (fi.r2 < guard2 || !insert(x, it.kind == kQQuality ? kQuality : kDistance, Facet(c, i))) ++refused_;
    }
  }
}


// FacetCycle (8.2): does S have a closed curve inside the Voronoi facet h
// dual to the Delaunay edge pq (a piece of S that no Voronoi edge sees)?
// h = bisector plane Pi cut by V(p)'s half-spaces and the box: convex, so
// it is rasterised row by row on Pi at delta/16 (at delta/4, curves missed
// there cost the brain labels' certificate fallback rounds), into runs of
// one sign. The sign of f at a sample is the corner sign in an inactive
// cube (F1) and f's sign in an active one. A sign region that does not
// reach the border of h is enclosed by a cycle of S; its point farthest from p is found on the sample pair (region,
// neighbour) farthest from p, by root finding along that segment, i.e. on
// S inside Pi. Cycles narrower than the step are missed (like EdgeSurface).
bool Mesher::facet_cycle(const Tr::Edge& e, Vec3& out) {
  const Vh p = e.first->vertex(e.second), q = e.first->vertex(e.third);
  const Vec3 pp = vec(p->point()), pq = vec(q->point());
  Vec3 n = sub(pq, pp);
  const double nl = norm(n);
  if (!(nl > 0)) return false;
  n = {n[0] / nl, n[1] / nl, n[2] / nl};
  const Vec3 m{(pp[0] + pq[0]) / 2, (pp[1] + pq[1]) / 2, (pp[2] + pq[2]) / 2};
  Vec3 u = std::abs(n[0]) < 0.6 ? cross(n, Vec3{1, 0, 0}) : cross(n, Vec3{0, 1, 0});
  const double ul = norm(u);
  u = {u[0] / ul, u[1] / ul, u[2] / ul};
  const Vec3 v = cross(n, u);
  // Half-planes A a + B b <= C on Pi (x = m + a u + b v): V(p)'s faces and the box.
  struct HP { double A, B, C; };
  // Scratch reused across checks (no allocation per edge).
  thread_local std::vector<HP> hp;
  thread_local std::vector<Vh> adj;
  hp.clear();
  adj.clear();
  tr_.adjacent_vertices_threadsafe(p, std::back_inserter(adj));
  for (Vh w : adj) {
    if (w == q) continue;
    const Vec3 pw = vec(w->point());
    const Vec3 d = sub(pw, pp);  // |x-p|^2 <= |x-w|^2  <=>  2 x.d <= |w|^2 - |p|^2
    const double C = dot(pw, pw) - dot(pp, pp) - 2 * dot(m, d);
    hp.push_back({2 * dot(u, d), 2 * dot(v, d), C});
  }
  for (int i = 0; i < 3; ++i) {  // 0 <= m_i + a u_i + b v_i <= hi_i
    hp.push_back({u[i], v[i], grid_.hi[i] - m[i]});
    hp.push_back({-u[i], -v[i], m[i]});
  }
  // Extent on Pi: the box's corners projected (h lies in the box).
  double a0 = INFINITY, a1 = -INFINITY, b0 = INFINITY, b1 = -INFINITY;
  // Extent on Pi: the finite Voronoi vertices of h (circumcentres of the
  // cells around pq), or the box's corners when h is unbounded.
  bool bounded = true;
  {
    Tr::Cell_circulator cc = tr_.incident_cells(e), done = cc;
    do {
      if (tr_.is_infinite(cc)) { bounded = false; break; }
      const Vec3 c = vec(tr_.dual(cc));
      const double a = dot(sub(c, m), u), b = dot(sub(c, m), v);
      a0 = std::min(a0, a); a1 = std::max(a1, a); b0 = std::min(b0, b); b1 = std::max(b1, b);
    } while (++cc != done);
  }
  double ba0 = INFINITY, ba1 = -INFINITY, bb0 = INFINITY, bb1 = -INFINITY;
  for (int k = 0; k < 8; ++k) {
    const Vec3 c{(k & 1) ? grid_.hi[0] : 0, (k & 2) ? grid_.hi[1] : 0, (k & 4) ? grid_.hi[2] : 0};
    const double a = dot(sub(c, m), u), b = dot(sub(c, m), v);
    ba0 = std::min(ba0, a); ba1 = std::max(ba1, a); bb0 = std::min(bb0, b); bb1 = std::max(bb1, b);
  }
  if (!bounded) { a0 = ba0; a1 = ba1; b0 = bb0; b1 = bb1; }
  a0 = std::max(a0, ba0); a1 = std::min(a1, ba1); b0 = std::max(b0, bb0); b1 = std::min(b1, bb1);
  if (!(a0 < a1 && b0 < b1)) return false;
  // Tighten b by the polygon: rows where the a-interval is empty are skipped anyway.
  const double step = grid_.delta / 16;
  const long nb = long(std::ceil((b1 - b0) / step)) + 1;
  // Rows: the a-interval where every half-plane holds.
  thread_local std::vector<long> lo, hi;
  thread_local std::vector<double> alo_row, ahi_row;  // h's exact border on each row
  lo.assign(nb, 0);
  hi.assign(nb, -1);
  alo_row.assign(nb, 0);
  ahi_row.assign(nb, 0);
  long rows_used = 0;
  for (long j = 0; j < nb; ++j) {
    const double b = b0 + j * step;
    double alo = a0, ahi = a1;
    for (const HP& h : hp) {
      const double r = h.C - h.B * b;
      if (h.A > 1e-15) ahi = std::min(ahi, r / h.A);
      else if (h.A < -1e-15) alo = std::max(alo, r / h.A);
      else if (r < 0) { alo = 1; ahi = 0; break; }
    }
    if (!(alo <= ahi)) continue;
    alo_row[j] = alo;
    ahi_row[j] = ahi;
    lo[j] = long(std::ceil((alo - a0) / step));
    hi[j] = long(std::floor((ahi - a0) / step));
    if (hi[j] >= lo[j]) ++rows_used;
  }
  if (rows_used < 3) return false;
  // Samples inside h, with their signs, as runs of one sign per row: an
  // inactive cube's samples all take its corner sign (F1), so the raster
  // jumps to the cube's exit; f is evaluated only in active cubes.
  long total = 0;
  for (long j = 0; j < nb; ++j) total += std::max(0L, hi[j] - lo[j] + 1);
  if (total < 9 || total > 4000000) return false;
  auto point = [&](long i, long j) {
    const double a = a0 + i * step, b = b0 + j * step;
    return Vec3{m[0] + a * u[0] + b * v[0], m[1] + a * u[1] + b * v[1], m[2] + a * u[2] + b * v[2]};
  };
  auto cube_of = [&](const Vec3& x, long c[3]) {
    for (int k = 0; k < 3; ++k) c[k] = std::clamp(long(std::floor(x[k] / grid_.s[k])), 0L, grid_.n[k] - 2);
  };
  struct Run { long j, s, e; signed char sg; };
  thread_local std::vector<Run> runs;
  thread_local std::vector<long> row_run;  // runs of row j: [row_run[j], row_run[j + 1])
  runs.clear();
  row_run.assign(nb + 1, 0);
  bool any_neg = false, any_pos = false;
  for (long j = 0; j < nb; ++j) {
    row_run[j] = long(runs.size());
    for (long i = lo[j]; i <= hi[j];) {
      const Vec3 x = point(i, j);
      long c[3];
      cube_of(x, c);
      long last = i;
      bool in;
      if (grid_.active(c[0], c[1], c[2])) {
        in = inside(value(x));
      } else {
        in = grid_.neg(c[0], c[1], c[2]);
        // The row leaves the cube at a_exit; the samples before it are in it
        // (a cube is convex; the floor test settles rounding at its faces).
        double a_exit = INFINITY;
        const double b = b0 + j * step;
        for (int k = 0; k < 3; ++k) {
          if (u[k] > 1e-15) a_exit = std::min(a_exit, ((c[k] + 1) * grid_.s[k] - m[k] - b * v[k]) / u[k]);
          else if (u[k] < -1e-15) a_exit = std::min(a_exit, (c[k] * grid_.s[k] - m[k] - b * v[k]) / u[k]);
        }
        const double t = std::floor((a_exit - a0) / step);
        last = std::isfinite(t) ? long(std::clamp(t, double(i), double(hi[j]))) : hi[j];
        for (long c2[3]; last > i; --last) {
          cube_of(point(last, j), c2);
          if (c2[0] == c[0] && c2[1] == c[1] && c2[2] == c[2]) break;
        }
      }
      (in ? any_neg : any_pos) = true;
      if (long(runs.size()) > row_run[j] && runs.back().sg == static_cast<signed char>(in)) runs.back().e = last;
      else runs.push_back({j, i, last, static_cast<signed char>(in)});
      i = last + 1;
    }
  }
  row_run[nb] = long(runs.size());
  if (!(any_neg && any_pos)) return false;
  // Sign regions (4-connected): runs of one sign overlapping in adjacent rows,
  // joined by union-find. A region touching h's border is open; one that
  // never does is enclosed by a cycle of S.
  thread_local std::vector<long> parent;
  thread_local std::vector<char> open;
  parent.resize(runs.size());
  open.assign(runs.size(), 0);
  for (std::size_t r = 0; r < runs.size(); ++r) parent[r] = long(r);
  auto find = [&](long r) {
    while (parent[std::size_t(r)] != r) r = parent[std::size_t(r)] = parent[std::size_t(parent[std::size_t(r)])];
    return r;
  };
  auto inside_row = [&](long j, long s0, long e0) { return j >= 0 && j < nb && lo[j] <= s0 && e0 <= hi[j]; };
  for (long j = 0; j < nb; ++j)
    for (long r = row_run[j]; r < row_run[j + 1]; ++r) {
      const Run& x = runs[std::size_t(r)];
      if (j + 1 >= nb) continue;
      for (long r2 = row_run[j + 1]; r2 < row_run[j + 2]; ++r2) {
        const Run& y = runs[std::size_t(r2)];
        if (y.e < x.s) continue;
        if (y.s > x.e) break;
        if (y.sg == x.sg) parent[std::size_t(find(r))] = find(r2);
      }
    }
  // A region is open where it reaches h's border itself: the sign at the
  // exact border point beyond a sample next to the border must be the
  // region's (else S passes in between and the region may be enclosed, as
  // when a thin feature's cross-section nearly fills a narrow facet).
  auto sign_at = [&](double a, double b) {
    const Vec3 x{m[0] + a * u[0] + b * v[0], m[1] + a * u[1] + b * v[1], m[2] + a * u[2] + b * v[2]};
    long c[3];
    cube_of(x, c);
    return grid_.active(c[0], c[1], c[2]) ? inside(value(x)) : grid_.neg(c[0], c[1], c[2]);
  };
  auto column_end = [&](double a, int dir) {  // h's border above (dir 1) or below (-1) a
    double bmin = -INFINITY, bmax = INFINITY;
    for (const HP& h : hp) {
      const double r = h.C - h.A * a;
      if (h.B > 1e-15) bmax = std::min(bmax, r / h.B);
      else if (h.B < -1e-15) bmin = std::max(bmin, r / h.B);
    }
    return dir > 0 ? std::min(bmax, b1) : std::max(bmin, b0);
  };
  auto exits = [&](const Run& x) {
    const long j = x.j;
    const double b = b0 + j * step;
    const bool sg = x.sg;
    if (x.s == lo[j] && sign_at(alo_row[j], b) == sg) return true;
    if (x.e == hi[j] && sign_at(ahi_row[j], b) == sg) return true;
    for (int dir : {-1, 1}) {
      const long j2 = j + dir;
      if (inside_row(j2, x.s, x.e)) continue;
      for (long i = x.s; i <= x.e; ++i) {
        if (j2 >= 0 && j2 < nb && lo[j2] <= i && i <= hi[j2]) continue;  // that neighbour is in h
        const double a = a0 + i * step;
        if (sign_at(a, column_end(a, dir)) == sg) return true;
      }
    }
    return false;
  };
  for (std::size_t r = 0; r < runs.size(); ++r) {
    const long root = find(long(r));
    if (!open[std::size_t(root)] && exits(runs[r])) open[std::size_t(root)] = 1;
  }
  // Enclosed regions: the sample pair (region, neighbour) farthest from p;
  // along a row or an overlap of two rows the distance is convex, so only
  // the ends of runs and overlaps are candidates.
  double best = -1;
  Vec3 ba{}, bb{};
  auto candidate = [&](long i, long j, long i2, long j2) {
    const Vec3 xa = point(i, j), xb = point(i2, j2);
    const Vec3 mid{(xa[0] + xb[0]) / 2, (xa[1] + xb[1]) / 2, (xa[2] + xb[2]) / 2};
    const double d = dist2(mid, pp);
    if (d > best) { best = d; ba = xa; bb = xb; }
  };
  for (long j = 0; j < nb; ++j)
    for (long r = row_run[j]; r < row_run[j + 1]; ++r) {
      if (open[std::size_t(find(r))]) continue;
      const Run& x = runs[std::size_t(r)];
      candidate(x.s, j, x.s - 1, j);  // enclosed: its neighbours are in h
      candidate(x.e, j, x.e + 1, j);
      for (long j2 : {j - 1, j + 1})
        for (long r2 = row_run[j2]; r2 < row_run[j2 + 1]; ++r2) {
          const Run& y = runs[std::size_t(r2)];
          if (y.e < x.s) continue;
          if (y.s > x.e) break;
          if (y.sg == x.sg) continue;
          const long s0 = std::max(x.s, y.s), e0 = std::min(x.e, y.e);
          candidate(s0, j, s0, j2);
          candidate(e0, j, e0, j2);
        }
    }
  if (best < 0) return false;
  out = bisect(ba, bb, value(ba));
  return true;
}

// Points found on one state of W, inserted one after the other: a point
// goes in only while it is still at least half its clearance (its distance
// to W when it was found) away from W, so two points found for neighbouring
// features do not both go in and make a tiny, unrefinable triangle.
bool Mesher::insert_batch(const std::vector<std::pair<Vec3, double>>& pts, Origin origin) {
  bool any = false;
  for (const auto& [x, clearance2] : pts) {
    Vh nv = tr_.nearest_vertex(Point(x[0], x[1], x[2]), walk_start_->cell());
    if (dist2(x, vec(nv->point())) < clearance2 / 4) {
      ++refused_;
      continue;
    }
    any = insert(x, origin) || any;
  }
  return any;
}

// One FacetCycle pass over the edges whose Voronoi facet may have changed
// since the last pass; inserts the cycle points found. True if any went in.
bool Mesher::facet_cycle_pass() {
  ++facet_cycle_passes_;
  phase_ = "facet cycle";
  // The edges at new vertices, each once (from the smaller id when both
  // ends are new), found from the new vertices' cells.
  std::vector<std::pair<std::pair<int, int>, Tr::Edge>> edges;
  for (int ia : dirty_.ids) {
    const Vh a = vertices_[std::size_t(ia)];
    if (a == Vh()) continue;  // deleted
    ++stamp_;
    cells_buf_.clear();
    tr_.incident_cells(a, std::back_inserter(cells_buf_));
    for (Ch c : cells_buf_)
      for (int k = 0; k < 4; ++k) {
        Vh b = c->vertex(k);
        if (b == a || tr_.is_infinite(b) || b->info().stamp == stamp_) continue;
        const int ib = b->info().id;
        if (dirty_.has(ib) && ib < ia) continue;
        b->info().stamp = stamp_;
        // p (the edge's first vertex): the smaller id, as before.
        edges.push_back({{std::min(ia, ib), std::max(ia, ib)}, ia < ib ? Tr::Edge(c, c->index(a), k) : Tr::Edge(c, k, c->index(a))});
      }
  }
  dirty_.clear();
  std::sort(edges.begin(), edges.end(), [](const auto& x, const auto& y) { return x.first < y.first; });
  // The checks only read the triangulation (every finite cell's
  // circumcentre is cached by then: EdgeSurface asked for it), so they run
  // on --threads threads; the points go in afterwards, in edge order.
  facet_cycle_checks_ += static_cast<long long>(edges.size());
  std::vector<char> found(edges.size(), 0);
  std::vector<Vec3> xs(edges.size());
  implicit_detail::parallel_for(long(edges.size()), unsigned(std::max(1, opt_.threads)), [&](long a, long b, unsigned) {
    for (long k = a; k < b; ++k) found[std::size_t(k)] = facet_cycle(edges[std::size_t(k)].second, xs[std::size_t(k)]);
  });
  std::vector<std::pair<Vec3, double>> pts;
  for (std::size_t k = 0; k < edges.size(); ++k)
    if (found[k]) pts.emplace_back(xs[k], dist2(xs[k], vec(edges[k].second.first->vertex(edges[k].second.second)->point())));
  return insert_batch(pts, kFacetCycle);
}

std::vector<Facet> Mesher::restricted_facets() const {
  std::vector<std::pair<std::array<int, 3>, Facet>> out;
  for (auto it = tr_.finite_facets_begin(); it != tr_.finite_facets_end(); ++it) {
    if (!(it->first->facet[it->second].state & kRestricted)) continue;
    std::array<int, 3> ids;
    for (int m = 1; m < 4; ++m) ids[m - 1] = it->first->vertex((it->second + m) & 3)->info().id;
    std::sort(ids.begin(), ids.end());
    out.emplace_back(ids, *it);
  }
  std::sort(out.begin(), out.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
  std::vector<Facet> fs;
  for (auto& p : out) fs.push_back(p.second);
  return fs;
}

// HandleDetection (8.3): is S inside V(p) a disk? S is triangulated by
// marching tetrahedra on a grid of half the voxel spacing (f sampled only in
// active cubes; F1 gives the sign elsewhere) in a box around p, twice the
// reach of p's surface Delaunay balls and doubled while that part of S
// reaches the box's border; the triangles whose vertices all lie in V(p)
// approximate S inside V(p), and their Euler characteristic must be 1 (a
// handle makes it <= -1, a second piece >= 2). If not, q is the vertex there
// farthest from p, moved onto S (the thesis's choice; a whole component
// inside V(p) has characteristic 2 and gets a second point). No answer (false)
// when the box would exceed 300,000 sample points. It costs about a
// thousand evaluations of f: handle_free() settles most vertices first.
bool Mesher::handle_detection(Vh p, Vec3& q) {
  // Runs on several threads: thread-safe adjacency, thread-local scratch.
  thread_local std::vector<Ch> cells;
  cells.clear();
  tr_.incident_cells_threadsafe(p, std::back_inserter(cells));
  const Vec3 pp = vec(p->point());
  double reach2 = 0;
  for (Ch c : cells)
    for (int i = 0; i < 4; ++i)
      if (c->vertex(i) != p && (c->facet[i].state & kRestricted)) reach2 = std::max(reach2, dist2(facet_center(Facet(c, i)), pp));
  // No restricted facet at p: S inside V(p) meets no Voronoi edge (a whole
  // small component, say); start from a voxel.
  if (reach2 <= 0) reach2 = grid_.delta * grid_.delta;
  thread_local std::vector<HalfSpace> hs;
  voronoi_cell(p, hs);
  auto in_cell = [&](const Vec3& x) {
    for (const HalfSpace& e : hs)
      if (dot(e.d, x) > e.c) return false;
    return true;
  };
  // The box grows while that part of S reaches its border.
  const long long NX = 2 * grid_.n[0], NY = 2 * grid_.n[1];
  thread_local std::vector<double> fv;
  thread_local std::unordered_map<long long, int> vid;
  struct PV { Vec3 x; long long a, b; bool in; };
  thread_local std::vector<PV> pv;
  thread_local std::vector<std::array<int, 3>> tris;
  bool border = false;
  const double h[3] = {grid_.s[0] / 2, grid_.s[1] / 2, grid_.s[2] / 2};
  auto point = [&](long x, long y, long z) { return Vec3{x * h[0], y * h[1], z * h[2]}; };
  for (double scale = 2;; scale *= 2) {
    const double reach = scale * std::sqrt(reach2);
    // Box in sub-grid indices (spacing s_i / 2).
    long lo[3], n[3];
    for (int i = 0; i < 3; ++i) {
      const long top = 2 * (grid_.n[i] - 1);
      lo[i] = std::clamp(long(std::floor((pp[i] - reach) / h[i])), 0L, top);
      const long hi = std::clamp(long(std::ceil((pp[i] + reach) / h[i])), 0L, top);
      n[i] = hi - lo[i] + 1;
      if (n[i] < 2) return false;
    }
    if (n[0] * n[1] * n[2] > 300000) return false;
    // Signs and values at the sub-grid points (NaN: not evaluated).
    fv.assign(std::size_t(n[0] * n[1] * n[2]), NAN);
    auto idx = [&](long x, long y, long z) { return std::size_t((x - lo[0]) + n[0] * ((y - lo[1]) + n[1] * (z - lo[2]))); };
    auto f_at = [&](long x, long y, long z) {
      double& v = fv[idx(x, y, z)];
      if (std::isnan(v)) {
        // An active cube containing the point: f; else the cube's corner sign.
        bool act = false;
        for (int k = 0; k < 8 && !act; ++k) {
          const long c[3] = {(x - (k & 1)) / 2, (y - ((k >> 1) & 1)) / 2, (z - ((k >> 2) & 1)) / 2};
          act = grid_.active(c[0], c[1], c[2]);
        }
        if (act) v = value(point(x, y, z));
        else v = grid_.neg(std::min(x / 2, grid_.n[0] - 1), std::min(y / 2, grid_.n[1] - 1), std::min(z / 2, grid_.n[2] - 1)) ? -1.0 : 1.0;
      }
      return v;
    };
    // Marching tetrahedra (6 tetrahedra around each sub-cube's main diagonal:
    // the same split in every sub-cube, so the pieces fit). Vertices are keyed
    // by their sub-grid edge; triangles kept only when all three are in V(p).
    static const int tets[6][4] = {{0, 1, 3, 7}, {0, 3, 2, 7}, {0, 2, 6, 7}, {0, 6, 4, 7}, {0, 4, 5, 7}, {0, 5, 1, 7}};
    vid.clear();
    pv.clear();
    tris.clear();
    auto vertex = [&](long long ka, long long kb, const long (&ca)[3], const long (&cb)[3]) {
      // The edge: its first end and the step to the other (27 directions).
      const long long key = ka * 27 + (cb[0] - ca[0] + 1) + 3 * (cb[1] - ca[1] + 1) + 9 * (cb[2] - ca[2] + 1);
      auto it = vid.find(key);
      if (it != vid.end()) return it->second;
      const double fa = f_at(ca[0], ca[1], ca[2]), fb = f_at(cb[0], cb[1], cb[2]);
      const double t = fa / (fa - fb);
      const Vec3 xa = point(ca[0], ca[1], ca[2]), xb = point(cb[0], cb[1], cb[2]);
      const Vec3 x{xa[0] + t * (xb[0] - xa[0]), xa[1] + t * (xb[1] - xa[1]), xa[2] + t * (xb[2] - xa[2])};
      pv.push_back({x, ka, kb, in_cell(x)});
      vid.emplace(key, int(pv.size()) - 1);
      return int(pv.size()) - 1;
    };
    for (long z = lo[2]; z + 1 < lo[2] + n[2]; ++z)
      for (long y = lo[1]; y + 1 < lo[1] + n[1]; ++y)
        for (long x = lo[0]; x + 1 < lo[0] + n[0]; ++x) {
          // Only sub-cubes of active cubes can meet S.
          if (!grid_.active(x / 2, y / 2, z / 2)) continue;
          long c[8][3];
          double v[8];
          long long key[8];
          for (int k = 0; k < 8; ++k) {
            c[k][0] = x + (k & 1);
            c[k][1] = y + ((k >> 1) & 1);
            c[k][2] = z + ((k >> 2) & 1);
            v[k] = f_at(c[k][0], c[k][1], c[k][2]);
            key[k] = c[k][0] + NX * (c[k][1] + NY * c[k][2]);
          }
          for (const auto& t : tets) {
            int ins[4], outs[4], ni = 0, no = 0;
            for (int m = 0; m < 4; ++m) (inside(v[t[m]]) ? ins[ni++] : outs[no++]) = t[m];
            if (ni == 0 || no == 0) continue;
            auto vx = [&](int a, int b) {
              if (key[a] > key[b]) std::swap(a, b);
              return vertex(key[a], key[b], c[a], c[b]);
            };
            const bool edge_box = x == lo[0] || y == lo[1] || z == lo[2] || x + 2 == lo[0] + n[0] || y + 2 == lo[1] + n[1] || z + 2 == lo[2] + n[2];
            auto keep = [&](const std::array<int, 3>& tr) {
              if (!(pv[tr[0]].in && pv[tr[1]].in && pv[tr[2]].in)) return;
              if (edge_box) border = true;
              tris.push_back(tr);
            };
            if (ni == 1 || no == 1) {
              const int a = ni == 1 ? ins[0] : outs[0];
              const int* o = ni == 1 ? outs : ins;
              keep({vx(a, o[0]), vx(a, o[1]), vx(a, o[2])});
            } else {
              const int q0 = vx(ins[0], outs[0]), q1 = vx(ins[0], outs[1]), q2 = vx(ins[1], outs[1]), q3 = vx(ins[1], outs[0]);
              keep({q0, q1, q2});
              keep({q0, q2, q3});
            }
          }
        }
    if (tris.empty()) return false;
    if (!border) break;
    border = false;
  }
  // Euler characteristic V - E + F of the kept triangles.
  thread_local std::vector<long long> edges;
  thread_local std::vector<int> verts;
  edges.clear();
  verts.clear();
  for (const auto& t : tris)
    for (int k = 0; k < 3; ++k) {
      const int a = t[k], b = t[(k + 1) % 3];
      edges.push_back(edge_key(a, b));
      verts.push_back(a);
    }
  std::sort(edges.begin(), edges.end());
  std::sort(verts.begin(), verts.end());
  const long long E = std::unique(edges.begin(), edges.end()) - edges.begin();
  const long long V = std::unique(verts.begin(), verts.end()) - verts.begin();
  if (V - E + static_cast<long long>(tris.size()) == 1) return false;
  // The kept vertex farthest from p, moved onto S along its sub-grid edge.
  int best = -1;
  double bd = -1;
  for (std::size_t k = 0; k < std::size_t(V); ++k) {
    const double d = dist2(pv[std::size_t(verts[k])].x, pp);
    if (d > bd) { bd = d; best = verts[k]; }
  }
  const PV& b = pv[std::size_t(best)];
  auto coords = [&](long long key) { return point(long(key % NX), long((key / NX) % NY), long(key / NX / NY)); };
  const Vec3 xa = coords(b.a), xb = coords(b.b);
  q = bisect(xa, xb, value(xa));
  return true;
}

// HandleDetection's cheap certificate (notes 4.3(a)): the active cubes
// reached from p's cube through mixed faces, without those lying wholly
// outside one half-space of V(p). If every active cube holds a disk of S,
// every mixed face one arc and every crossed edge one point (F2), S inside
// their union X has Euler characteristic cubes - mixed faces + crossed
// edges, and it is connected; when that is 1, S n X is a disk, so S n V(p)
// (inside it) has no handle. True: no handle.
bool Mesher::handle_free(Vh p) {
  const Vec3 pp = vec(p->point());
  thread_local std::vector<HalfSpace> hs;
  voronoi_cell(p, hs);
  auto outside = [&](long x, long y, long z) {  // all 8 corners beyond one face of V(p)
    for (const HalfSpace& e : hs) {
      bool all = true;
      for (int k = 0; k < 8 && all; ++k) {
        const Vec3 c{(x + (k & 1)) * grid_.s[0], (y + ((k >> 1) & 1)) * grid_.s[1], (z + ((k >> 2) & 1)) * grid_.s[2]};
        all = dot(e.d, c) > e.c;
      }
      if (all) return true;
    }
    return false;
  };
  long c0[3];
  for (int k = 0; k < 3; ++k) c0[k] = std::clamp(long(std::floor(pp[k] / grid_.s[k])), 0L, grid_.n[k] - 2);
  if (!grid_.active(c0[0], c0[1], c0[2])) return false;
  const long nx = grid_.n[0], ny = grid_.n[1];
  auto key = [&](long x, long y, long z) { return x + nx * (y + ny * z); };
  thread_local std::vector<long long> cubes, faces, edges;
  thread_local std::vector<std::array<long, 3>> stack;
  cubes.assign(1, key(c0[0], c0[1], c0[2]));
  faces.clear();
  edges.clear();
  stack.assign(1, {c0[0], c0[1], c0[2]});
  auto seen = [&](long long k) { return std::find(cubes.begin(), cubes.end(), k) != cubes.end(); };
  while (!stack.empty()) {
    const auto [x, y, z] = stack.back();
    stack.pop_back();
    if (cubes.size() > 512) return false;  // V(p) still large: the full test
    bool sg[8];
    for (int k = 0; k < 8; ++k) sg[k] = grid_.neg(x + (k & 1), y + ((k >> 1) & 1), z + ((k >> 2) & 1));
    // 12 edges: corner pairs differing in one bit; key (corner, axis).
    for (int k = 0; k < 8; ++k)
      for (int a = 0; a < 3; ++a)
        if (!(k >> a & 1) && sg[k] != sg[k | 1 << a])
          edges.push_back(3 * key(x + (k & 1), y + ((k >> 1) & 1), z + ((k >> 2) & 1)) + a);
    // 6 faces: axis a, side 0/1; key (min corner, axis).
    for (int a = 0; a < 3; ++a)
      for (int side = 0; side < 2; ++side) {
        bool any_in = false, any_out = false;
        for (int k = 0; k < 8; ++k)
          if ((k >> a & 1) == side) (sg[k] ? any_in : any_out) = true;
        if (!(any_in && any_out)) continue;
        long f[3] = {x, y, z};
        f[a] += side;
        faces.push_back(3 * key(f[0], f[1], f[2]) + a);
        long nbr[3] = {x, y, z};
        nbr[a] += side ? 1 : -1;
        if (!grid_.active(nbr[0], nbr[1], nbr[2])) continue;
        const long long kn = key(nbr[0], nbr[1], nbr[2]);
        if (seen(kn) || outside(nbr[0], nbr[1], nbr[2])) continue;
        cubes.push_back(kn);
        stack.push_back({nbr[0], nbr[1], nbr[2]});
      }
  }
  std::sort(faces.begin(), faces.end());
  std::sort(edges.begin(), edges.end());
  const long long F = std::unique(faces.begin(), faces.end()) - faces.begin();
  const long long E = std::unique(edges.begin(), edges.end()) - edges.begin();
  return static_cast<long long>(cubes.size()) - F + E == 1;
}

// HandleDetection (8.3) in TOPOLOGY, after TopoDisk and FacetCycle: every
// vertex whose Voronoi cell changed since its last check; the full test
// (marching tetrahedra, about a thousand evaluations of f) only where the
// cheap certificate does not settle it. True if a point went in.
bool Mesher::handle_vertex_pass() {
  std::sort(cell_changed_.ids.begin(), cell_changed_.ids.end());
  std::vector<Vh> todo;
  for (int id : cell_changed_.ids)
    if (vertices_[std::size_t(id)] != Vh()) todo.push_back(vertices_[std::size_t(id)]);
  cell_changed_.clear();
  std::vector<char> found(todo.size(), 0);
  std::vector<Vec3> xs(todo.size());
  std::atomic<long long> full{0};
  implicit_detail::parallel_for(long(todo.size()), unsigned(std::max(1, opt_.threads)), [&](long a, long b, unsigned) {
    for (long k = a; k < b; ++k) {
      if (handle_free(todo[std::size_t(k)])) continue;
      full.fetch_add(1, std::memory_order_relaxed);
      found[std::size_t(k)] = handle_detection(todo[std::size_t(k)], xs[std::size_t(k)]);
    }
  });
  handle_checks_ += full.load();
  handle_certified_ += static_cast<long long>(todo.size()) - full.load();
  std::vector<std::pair<Vec3, double>> pts;
  for (std::size_t k = 0; k < todo.size(); ++k)
    if (found[k]) pts.emplace_back(xs[k], dist2(xs[k], vec(todo[k]->point())));
  if (handle_trial_ && !pts.empty()) {  // the deleted handle point goes back
    const Vec3 x = *handle_trial_;
    handle_trial_.reset();
    ++handle_points_restored_;
    return insert(x, kHandle);
  }
  return insert_batch(pts, kHandle);
}

// HandleDetection on every vertex of the S components whose mesh has the
// wrong topology (the certificate says which), before the blunter fallback.
constexpr std::size_t kHandleBudget = 20000;
bool Mesher::handle_pass(const std::vector<int>& bad) {
  std::vector<char> is_bad(std::size_t(grid_.components) + 1, 0);
  for (int c : bad)
    if (c >= 0) is_bad[std::size_t(c)] = 1;
  std::vector<Vh> todo;
  for (Vh v : vertices_)
    if (v != Vh() && v->info().comp >= 0 && is_bad[std::size_t(v->info().comp)]) todo.push_back(v);
  // A check costs about a thousand evaluations of f: on components of more
  // than kHandleBudget samples (brain tissue of genus ~2600), the fallback's
  // refinement is much cheaper.
  if (todo.size() > kHandleBudget) return false;
  std::vector<char> found(todo.size(), 0);
  std::vector<Vec3> xs(todo.size());
  implicit_detail::parallel_for(long(todo.size()), unsigned(std::max(1, opt_.threads)), [&](long a, long b, unsigned) {
    for (long k = a; k < b; ++k) found[std::size_t(k)] = handle_detection(todo[std::size_t(k)], xs[std::size_t(k)]);
  });
  std::vector<std::pair<Vec3, double>> pts;
  for (std::size_t k = 0; k < todo.size(); ++k)
    if (found[k]) pts.emplace_back(xs[k], dist2(xs[k], vec(todo[k]->point())));
  handle_checks_ += static_cast<long long>(todo.size());
  return insert_batch(pts, kHandle);
}

// Beyond HandleDetection: when the certificate still
// (or again) finds a component of S whose mesh has the wrong topology, refine it: the
// largest surface Delaunay balls there, and the point of S (a mixed-edge
// crossing) farthest from W. Denser samples end as an epsilon-sample, where
// the restricted Delaunay surface is homeomorphic to S (Amenta-Bern, CDRR).
bool Mesher::fallback(const std::vector<int>& bad) {
  bool any = false;
  std::vector<Facet> fs = restricted_facets();
  for (int comp : bad) {
    std::vector<std::pair<double, Facet>> mine;
    for (const Facet& f : fs)
      if (f.first->vertex((f.second + 1) & 3)->info().comp == comp) mine.emplace_back(f.first->facet[f.second].r2, f);
    std::stable_sort(mine.begin(), mine.end(), [](const auto& a, const auto& b) { return a.first > b.first; });
    const std::size_t take = std::min<std::size_t>(mine.size(), std::max<std::size_t>(1, mine.size() / 10));
    std::vector<std::pair<Vec3, double>> pts;
    for (std::size_t k = 0; k < take; ++k) pts.emplace_back(facet_center(mine[k].second), mine[k].first);
    // Farthest mixed-edge crossing (linear estimate, then refined).
    double far = -1;
    Vec3 fa{}, fb{};
    std::size_t count = 0, stride = 1;
    for (auto& kc : grid_.comp) count += kc.second == comp;
    stride = std::max<std::size_t>(1, count / 4000);
    std::size_t k = 0;
    std::vector<std::pair<long long, int>> cubes(grid_.comp.begin(), grid_.comp.end());
    std::sort(cubes.begin(), cubes.end());
    for (auto& kc : cubes) {
      if (kc.second != comp || (k++ % stride)) continue;
      const long x = long(kc.first % grid_.n[0]), y = long((kc.first / grid_.n[0]) % grid_.n[1]),
                 z = long(kc.first / grid_.n[0] / grid_.n[1]);
      for (int a = 0; a < 3; ++a) {
        long p[3] = {x, y, z}, q[3] = {x, y, z};
        q[a] += 1;
        if (grid_.neg(p[0], p[1], p[2]) == grid_.neg(q[0], q[1], q[2])) continue;
        const Vec3 pa{p[0] * grid_.s[0], p[1] * grid_.s[1], p[2] * grid_.s[2]};
        const Vec3 pb{q[0] * grid_.s[0], q[1] * grid_.s[1], q[2] * grid_.s[2]};
        const double ga = grid_.g(p[0], p[1], p[2]), gb = grid_.g(q[0], q[1], q[2]);
        const double t = ga / (ga - gb);
        const Vec3 m{pa[0] + t * (pb[0] - pa[0]), pa[1] + t * (pb[1] - pa[1]), pa[2] + t * (pb[2] - pa[2])};
        Vh nv = tr_.nearest_vertex(Point(m[0], m[1], m[2]));
        const double dd = dist2(m, vec(nv->point()));
        if (dd > far) {
          far = dd;
          fa = pa;
          fb = pb;
        }
      }
    }
    if (far > 0) pts.emplace_back(bisect(fa, fb, value(fa)), far);
    any = insert_batch(pts, kFallback) || any;
  }
  return any;
}

RestrictedDelaunayResult Mesher::run() {
  RestrictedDelaunayResult res;
  const auto t_start = Clock::now();
  auto secs = [](Clock::time_point a) { return std::chrono::duration<double>(Clock::now() - a).count(); };
  const FloatImage& g = f_.samples();
  if (g.dimension != 3 || g.size[0] < 2 || g.size[1] < 2 || g.size[2] < 2)
    throw Error("the implicit function must be sampled on a 3D grid of at least 2x2x2 voxels");
  for (float v : g.data)
    if (!std::isfinite(v)) throw Error("the implicit function has non-finite samples");
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
  const std::vector<int> expected_by_comp = grid_.euler_by_component();
  res.expected.euler = expected_by_comp;
  std::sort(res.expected.euler.begin(), res.expected.euler.end());

  phase_ = "seeds";
  comp_vertices_.assign(std::size_t(grid_.components), 0);
  seeds();
  const double t_seeds = secs(t_start);
  const auto t_refine = Clock::now();
  // DELMESH: SAMPLETOPOLOGY (TOPOLOGY, seed deletion), then every queue.
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

  // Certificate: components and Euler characteristics per S component; on a
  // mismatch, refine there (fallback) and run DELMESH's queues again.
  int rounds = 0;
  std::vector<int> bad;
  SurfaceMesh mesh;
  std::vector<Vec3> centers;
  std::vector<int> tri_comp;
  std::vector<Facet> fs;  // fs[k]: the Delaunay facet of triangle k
  for (;;) {
    mesh = SurfaceMesh();
    centers.clear();
    fs = restricted_facets();
    std::vector<int> index(vertices_.size(), -1);
    std::vector<int> comp_of_vertex;
    for (const Facet& f : fs) {
      std::array<int, 3> t;
      const std::array<Vh, 3> vs = facet_vertices(f.first, f.second);
      for (int m = 0; m < 3; ++m) {
        int& id = index[vs[m]->info().id];
        if (id < 0) {
          id = int(mesh.points.size());
          mesh.points.push_back(vec(vs[m]->point()));
          comp_of_vertex.push_back(vs[m]->info().comp);
        }
        t[m] = id;
      }
      // Outward: along grad f at the surface centre.
      const Vec3 n = cross(sub(mesh.points[t[1]], mesh.points[t[0]]), sub(mesh.points[t[2]], mesh.points[t[0]]));
      const Vec3 x = facet_center(f);
      const FacetInfo& fi = f.first->facet[f.second];
      if (dot(n, Vec3{fi.grad[0], fi.grad[1], fi.grad[2]}) < 0) std::swap(t[1], t[2]);
      mesh.triangles.push_back(t);
      centers.push_back(x);
    }
    // Make orientation consistent per mesh component (BFS), by majority.
    {
      const std::size_t nt = mesh.triangles.size();
      std::unordered_map<long long, std::vector<int>> by_edge;
      for (std::size_t t = 0; t < nt; ++t)
        for (int k = 0; k < 3; ++k) by_edge[edge_key(mesh.triangles[t][k], mesh.triangles[t][(k + 1) % 3])].push_back(int(t));
      std::vector<int> flip(nt, -1);
      tri_comp.assign(nt, -1);
      int ncomp = 0;
      for (std::size_t s0 = 0; s0 < nt; ++s0) {
        if (flip[s0] >= 0) continue;
        std::vector<int> members{int(s0)}, stack{int(s0)};
        flip[s0] = 0;
        tri_comp[s0] = ncomp;
        while (!stack.empty()) {
          const int t = stack.back();
          stack.pop_back();
          auto tt = mesh.triangles[t];
          if (flip[t]) std::swap(tt[1], tt[2]);
          for (int k = 0; k < 3; ++k) {
            const int a = tt[k], b = tt[(k + 1) % 3];
            for (int u : by_edge[edge_key(a, b)]) {
              if (u == t || flip[u] >= 0) continue;
              // u must traverse the edge as (b, a).
              const auto& tu = mesh.triangles[u];
              bool forward = false;
              for (int m = 0; m < 3; ++m) forward = forward || (tu[m] == a && tu[(m + 1) % 3] == b);
              flip[u] = forward ? 1 : 0;
              tri_comp[u] = ncomp;
              members.push_back(u);
              stack.push_back(u);
            }
          }
        }
        long long agree = 0;
        for (int t : members) agree += flip[t] ? -1 : 1;
        if (agree < 0)
          for (int t : members) flip[t] = 1 - flip[t];
        ++ncomp;
      }
      for (std::size_t t = 0; t < nt; ++t)
        if (flip[t] == 1) std::swap(mesh.triangles[t][1], mesh.triangles[t][2]);
    }
    res.topology = mesh_topology(mesh);
    // Per S component: exactly one mesh component with bdCA's Euler characteristic.
    std::map<int, std::vector<int>> mesh_comps;  // S comp -> mesh components
    {
      std::map<int, int> seen;
      for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
        const int sc = comp_of_vertex[mesh.triangles[t][0]];
        if (seen.emplace(tri_comp[t], sc).second) mesh_comps[sc].push_back(tri_comp[t]);
      }
    }
    bad.clear();
    for (int c = 0; c < grid_.components; ++c)
      if (mesh_comps[c].size() != 1) bad.push_back(c);
    if (mesh_comps.count(-1)) bad.push_back(-1);
    const bool ok = bad.empty() && res.topology.manifold && res.topology.oriented && res.topology.same_as(res.expected);
    if (ok || max_hit_ || rounds >= 40) break;
    if (bad.empty()) {  // per-component χ differs: find which components
      // χ of each mesh component vs. its S component.
      std::map<int, long long> chi;  // mesh comp -> V - E + F
      std::map<int, std::set<int>> vset;
      std::map<int, std::set<long long>> eset;
      for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
        const auto& tt = mesh.triangles[t];
        chi[tri_comp[t]] += 1;
        for (int k = 0; k < 3; ++k) {
          vset[tri_comp[t]].insert(tt[k]);
          const int a = tt[k], b = tt[(k + 1) % 3];
          eset[tri_comp[t]].insert(edge_key(a, b));
        }
      }
      for (auto& kv : mesh_comps) {
        const int mc = kv.second.front();
        if (kv.first >= 0 && chi[mc] + long(vset[mc].size()) - long(eset[mc].size()) != expected_by_comp[kv.first])
          bad.push_back(kv.first);
      }
    }
    bad.erase(std::remove(bad.begin(), bad.end(), -1), bad.end());
    ++rounds;
    if (bad.empty()) break;
    phase_ = "handle detection";
    if (!handle_pass(bad)) {
      phase_ = "topology fallback";
      if (!fallback(bad)) break;
    }
    refine();
  }
  const double t_refine_s = secs(t_refine);
  const auto t_final = Clock::now();

  // Guarantees, measured on the output.
  const TriangleQuality q = triangle_quality(mesh);
  double max_f = 0, max_rough = 0, max_dist = 0;
  for (const Vec3& p : mesh.points) max_f = std::max(max_f, std::abs(value(p)));
  {
    std::unordered_map<long long, std::vector<Vec3>> nrm;
    for (const auto& t : mesh.triangles) {
      Vec3 n = cross(sub(mesh.points[t[1]], mesh.points[t[0]]), sub(mesh.points[t[2]], mesh.points[t[0]]));
      const double nl = norm(n);
      if (nl > 0) n = {n[0] / nl, n[1] / nl, n[2] / nl};
      for (int k = 0; k < 3; ++k) {
        const int a = t[k], b = t[(k + 1) % 3];
        nrm[edge_key(a, b)].push_back(n);
      }
    }
    for (auto& kv : nrm)
      if (kv.second.size() == 2) max_rough = std::max(max_rough, std::acos(std::clamp(dot(kv.second[0], kv.second[1]), -1.0, 1.0)));
    for (std::size_t k = 0; k < mesh.triangles.size(); ++k) {
      const auto& t = mesh.triangles[k];
      const Vec3 n = cross(sub(mesh.points[t[1]], mesh.points[t[0]]), sub(mesh.points[t[2]], mesh.points[t[0]]));
      const double nl = norm(n);
      if (nl > 0) max_dist = std::max(max_dist, std::abs(dot(n, sub(centers[k], mesh.points[t[0]]))) / nl);
    }
  }
  // Geometric error estimate: |f| at the triangles' centroids (f
  // interpolates g, the signed distance to the voxel boundary, world units).
  double max_centroid = 0;
  for (const auto& t : mesh.triangles) {
    Vec3 c;
    for (int i = 0; i < 3; ++i) c[i] = (mesh.points[t[0]][i] + mesh.points[t[1]][i] + mesh.points[t[2]][i]) / 3;
    max_centroid = std::max(max_centroid, std::abs(value(c)));
  }
  // Restricted Delaunay property: each surface centre's nearest site is a
  // vertex of its facet (its ball is empty).
  long long rd_violations = 0;
  for (std::size_t k = 0; k < mesh.triangles.size(); ++k) {
    const Vec3& x = centers[k];
    const double r2 = dist2(x, mesh.points[mesh.triangles[k][0]]);
    Vh nv = tr_.nearest_vertex(Point(x[0], x[1], x[2]), fs[k].first);
    if (dist2(x, vec(nv->point())) < r2 * (1 - 1e-9)) ++rd_violations;
  }
  res.topology_ok = res.topology.manifold && res.topology.oriented && res.topology.same_as(res.expected) && bad.empty();
  res.ratio_ok = q.max_ratio <= opt_.ratio * (1 + 1e-9);
  res.roughness_ok = max_rough <= opt_.roughness + 1e-9;
  res.distance_ok = opt_.max_distance <= 0 || max_dist <= opt_.max_distance * (1 + 1e-9);
  res.max_points_hit = max_hit_;
  if (max_hit_) res.failure = "--max-points reached (" + std::to_string(opt_.max_points) + " points); ";
  if (!res.topology_ok) res.failure += "topology differs from the voxel boundary bdCA(X); ";
  if (!res.ratio_ok) res.failure += "radius-edge ratio above the bound; ";
  if (!res.roughness_ok) res.failure += "roughness above the bound; ";
  if (!res.distance_ok) res.failure += "distance to the surface above --max-distance; ";
  if (rd_violations) res.failure += "restricted Delaunay property violated; ";
  if (!res.failure.empty()) res.failure.resize(res.failure.size() - 2);

  // World coordinates; a reflecting direction matrix flips orientation.
  for (Vec3& p : mesh.points) p = f_.to_world(p);
  for (Vec3& x : centers) x = f_.to_world(x);
  if (f_.reflects())
    for (auto& t : mesh.triangles) std::swap(t[1], t[2]);
  res.mesh = std::move(mesh);
  res.centers = std::move(centers);

  Json& st = res.stats;
  Json pts = Json::object();
  for (int o = 0; o < kOrigins; ++o) pts[kOriginName[o]] = inserted_[o];
  st["points_inserted"] = pts;
  st["points_refused"] = refused_;
  st["seeds_deleted"] = seeds_deleted_;
  st["handle_points_deleted"] = handle_points_deleted_;
  st["handle_points_restored"] = handle_points_restored_;
  st["topology_fallback_rounds"] = rounds;
  st["topology_fallback_points"] = inserted_[kFallback];
  st["facet_cycle_checks"] = facet_cycle_checks_;
  st["facet_cycle_passes"] = facet_cycle_passes_;
  st["handle_detection_checks"] = handle_checks_;
  st["handle_detection_certified"] = handle_certified_;
  st["vertices"] = res.mesh.points.size();
  st["triangles"] = res.mesh.triangles.size();
  Json comps = Json::array();
  for (int e : res.topology.euler) comps.push_back(e);
  st["components_euler"] = comps;
  Json ex = Json::array();
  for (int e : res.expected.euler) ex.push_back(e);
  st["voxel_boundary_euler"] = ex;
  st["closed_manifold"] = res.topology.manifold;
  st["oriented"] = res.topology.oriented;
  st["topology_matches"] = res.topology_ok;
  st["min_angle_degrees"] = q.min_angle * 180 / M_PI;
  st["max_radius_edge_ratio"] = q.max_ratio;
  st["ratio_bound"] = opt_.ratio;
  st["max_roughness_degrees"] = max_rough * 180 / M_PI;
  st["roughness_bound_degrees"] = opt_.roughness * 180 / M_PI;
  st["max_distance_to_plane"] = max_dist;
  st["max_abs_f_at_vertices"] = max_f;
  st["max_abs_f_at_centroids"] = max_centroid;
  st["restricted_delaunay_violations"] = rd_violations;
  st["function_evaluations"] = evaluations_.load();
  Json times = Json::object();
  times["seeds"] = t_seeds;
  times["refinement"] = t_refine_s;
  times["verification"] = secs(t_final);
  st["phase_seconds"] = times;
  return res;
}

} // namespace

RestrictedDelaunayResult restricted_delaunay_mesh(const ImplicitSurface& surface, const RestrictedDelaunayOptions& options) {
  if (!(options.ratio >= min_ratio_bound()))
    throw UsageError("--ratio must be at least (1+k)^2 = " + std::to_string(min_ratio_bound()) + " (k = 0.06)");
  if (!(options.roughness >= min_roughness_bound()))
    throw UsageError("--roughness must be at least 2(arcsin k + arcsin(2k/sqrt 3)) = " + std::to_string(min_roughness_bound()) + " rad");
  if (!(options.max_distance >= 0) || !std::isfinite(options.max_distance)) throw UsageError("--max-distance must be >= 0");
  if (options.max_points < 4) throw UsageError("--max-points must be at least 4");
  Mesher m(surface, options);
  return m.run();
}

void add_normals(const ImplicitSurface& surface, SurfaceMesh& mesh) {
  mesh.normals.resize(mesh.points.size());
  for (std::size_t k = 0; k < mesh.points.size(); ++k) {
    Vec3 q = surface.to_local(mesh.points[k]), gr;
    const Geometry& g = surface.samples();
    for (int i = 0; i < 3; ++i) q[i] = std::clamp(q[i], 0.0, double(g.size[i] - 1) * g.spacing[i]);
    surface.value_gradient(q, gr);
    Vec3 w = surface.vector_to_world(gr);
    const double l = norm(w);
    mesh.normals[k] = l > 0 ? Vec3{w[0] / l, w[1] / l, w[2] / l} : Vec3{0, 0, 0};
  }
}

} // namespace imgmesh
