#include "surface/handle_detection.hpp"

#include "implicit/parallel.hpp"
#include "surface/star.hpp"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <map>
#include <unordered_map>

namespace imgmesh::surface_detail {

void voronoi_cell(const Tr& tr, Vh p, std::vector<HalfSpace>& hs) {
  thread_local std::vector<Vh> adj;
  adj.clear();
  star_vertices_threadsafe(tr, p, adj);
  const Vec3 pp = vec(p->point());
  hs.clear();
  for (Vh w : adj)
    if (!tr.is_infinite(w)) {
      const Vec3 pw = vec(w->point());
      hs.push_back({sub(pw, pp), (dot(pw, pw) - dot(pp, pp)) / 2});
    }
}

namespace {

// The lattice cube with low corner (x, y, z) lies wholly beyond face e of
// V(p), corner(i, j, k) giving its lattice points: its corner least far
// along e.d is (d . x, even rounded, is monotone in each coordinate).
template <class Corner> bool beyond_face(const HalfSpace& e, long x, long y, long z, Corner corner) {
  return dot(e.d, corner(x + (e.d[0] < 0), y + (e.d[1] < 0), z + (e.d[2] < 0))) > e.c;
}

// An MT vertex: its point on the sub-grid edge between keys a < b.
struct MtVertex {
  Vec3 x;
  long long a, b;
};

// HandleDetection's state for one vertex p: V(p), the box of the sub-grid
// (step h[i] = s[i] / m[i] on axis i, indices x, y, z) that marching
// tetrahedra (MT) run on, and the triangles they made, clipped to V(p).
// Scratch reused across checks, one per thread (this runs on several
// threads).
struct CellMarch {
  struct Scratch {
    std::vector<Ch> cells;
    std::vector<HalfSpace> hs;
    std::vector<double> fv;  // f at the box's sub-grid points (NaN: not evaluated)
    std::unordered_map<long long, int> vid;
    std::vector<MtVertex> pv;
    std::vector<std::array<int, 3>> tris;
    std::vector<char> tri_border;
    std::vector<std::vector<ClipVertex>> polys;
    std::vector<ClipVertex> next;
  };
  CellMarch(const SurfaceSampler& f, Vh p, Scratch& s) : f(f), grid(f.grid()), s(s), pp(vec(p->point())) {
    resolution(grid.delta / 2);
  }
  const SurfaceSampler& f;
  const CubeGrid& grid;
  Scratch& s;
  const Vec3 pp;
  long m[3] = {2, 2, 2};  // sub-cubes a cube along each axis
  double h[3] = {0, 0, 0};
  double reach2 = 0;  // p's surface Delaunay balls' reach, squared
  Vec3 vlo{-HUGE_VAL, -HUGE_VAL, -HUGE_VAL}, vhi{HUGE_VAL, HUGE_VAL, HUGE_VAL};  // V(p)'s bounding box
  long lo[3] = {0, 0, 0}, n[3] = {0, 0, 0};  // the box: n[i] points from lo[i]
  bool grid_face_lo[3] = {}, grid_face_hi[3] = {}, whole = true;  // its sides on the grid or V(p)'s box

  // The sub-grid: each cube split along axis i into m[i] >= 2 parts of at
  // most `step`, the same step on every axis where the spacings allow (half
  // of each axis's own spacing made MT's triangles, on a grid of 10 x 1 x 1
  // voxels, 5 voxels long across cells a voxel wide: issue 35).
  void resolution(double step) {
    for (int i = 0; i < 3; ++i) {
      m[i] = std::max(2L, long(std::ceil(grid.s[i] / step * (1 - 1e-12))));
      h[i] = grid.s[i] / double(m[i]);
    }
  }
  Vec3 point(long x, long y, long z) const { return Vec3{x * h[0], y * h[1], z * h[2]}; }
  void cell(const Tr& tr, Vh p);
  HandleAnswer test(Vec3& q);
  bool set_box(double reach);
  void march();
  bool clip_all();
  bool far_point(const ClippedComplex& k, Vec3& q) const;

private:
  // A sub-grid point's index in the box, also its key (keys ordered as the
  // points' (z, y, x)).
  std::size_t idx(long x, long y, long z) const { return std::size_t((x - lo[0]) + n[0] * ((y - lo[1]) + n[1] * (z - lo[2]))); }
  double f_at(long x, long y, long z);
  int vertex(long long ka, long long kb, const long (&ca)[3], const long (&cb)[3]);
  void sub_cube(long x, long y, long z);
  void clip(int t, std::vector<ClipVertex>& out);
  bool interior(const Vec3& x) const;
};

} // namespace

// HandleDetection (8.3): is S inside V(p) a disk? S is triangulated by
// marching tetrahedra on a sub-grid of step delta/2 on every axis (f sampled
// only in active cubes; F1 gives the sign elsewhere) in a box around p, twice the
// reach of p's surface Delaunay balls, doubled while the piece of S in V(p)
// reaches a side of the box that is not a face of the grid or of V(p)'s
// bounding box (S n V(p) lies inside both, so the growth ends at the latest
// when the box is their intersection).
// Each triangle is clipped to V(p) (convex: one half-space after the other),
// the pieces glued along shared MT edges and clipping points, and S n V(p)
// is a disk iff that complex is connected with Euler characteristic 1: a
// handle makes it <= -1, a second piece (a disk and an annulus, a whole
// component) makes it disconnected. If not a disk, q is the MT vertex in
// V(p) farthest from p, moved onto S and still inside V(p) (the thesis's
// choice). Undecided when the box would exceed 300,000 sample points, S n
// V(p) is below the MT resolution, or no such q is found: then once more
// on a sub-grid of a quarter of the reach, where V(p) is small against
// delta/2 (its piece of S a few MT triangles that V(p)'s faces cut in two:
// every refinement made V(p) smaller against that fixed step, and the test
// never decided again; issue 35). Still undecided: the caller refines (or
// counts), never passes.
HandleAnswer handle_detection(const Tr& tr, const SurfaceSampler& f, Vh p, Vec3& q) {
  thread_local CellMarch::Scratch scratch;
  CellMarch c(f, p, scratch);
  c.cell(tr, p);
  const HandleAnswer a = c.test(q);
  const double fine = std::sqrt(c.reach2) / 4;
  if (a != HandleAnswer::kUndecided || !(fine < f.grid().delta / 2)) return a;
  c.resolution(fine);
  return c.test(q);
}

// The test at the sub-grid's resolution.
HandleAnswer CellMarch::test(Vec3& q) {
  for (double scale = 2;; scale *= 2) {
    if (!set_box(scale * std::sqrt(reach2))) return HandleAnswer::kUndecided;
    march();
    if (!clip_all() || whole) break;
  }
  ClippedComplex k;
  glue_pieces(s.polys, s.tris.size(), k);
  if (k.faces == 0) return HandleAnswer::kUndecided;  // S n V(p) below the MT resolution
  if (k.components == 1 && k.chi == 1) return HandleAnswer::kDisk;
  return far_point(k, q) ? HandleAnswer::kNotDisk : HandleAnswer::kUndecided;
}

// V(p), the reach of p's surface Delaunay balls and V(p)'s bounding box.
void CellMarch::cell(const Tr& tr, Vh p) {
  s.cells.clear();
  star_cells_threadsafe(tr, p, s.cells);
  for (Ch c : s.cells)
    for (int i = 0; i < 4; ++i)
      if (c->vertex(i) != p && c->facet.restricted(i)) reach2 = std::max(reach2, dist2(facet_center(Facet(c, i)), pp));
  // No restricted facet at p: S inside V(p) meets no Voronoi edge (a whole
  // small component, say); start from a voxel.
  if (reach2 <= 0) reach2 = grid.delta * grid.delta;
  voronoi_cell(tr, p, s.hs);
  // V(p)'s bounding box: its vertices, the circumcentres of the cells at p
  // (computed here, not from CGAL's lazy cache, as this runs on threads);
  // unbounded at a hull vertex.
  bool bounded = true;
  for (Ch c : s.cells) bounded = bounded && !tr.is_infinite(c);
  if (!bounded) return;
  vlo = {HUGE_VAL, HUGE_VAL, HUGE_VAL};
  vhi = {-HUGE_VAL, -HUGE_VAL, -HUGE_VAL};
  for (Ch c : s.cells) {
    const Vec3 v = vec(CGAL::circumcenter(c->vertex(0)->point(), c->vertex(1)->point(), c->vertex(2)->point(), c->vertex(3)->point()));
    for (int i = 0; i < 3; ++i) {
      vlo[i] = std::min(vlo[i], v[i]);
      vhi[i] = std::max(vhi[i], v[i]);
    }
  }
}

// The box within `reach` of p, in sub-grid indices, inside the grid and
// V(p)'s bounding box (sides on those do not ask for growth); false if it
// would exceed 300,000 points.
bool CellMarch::set_box(double reach) {
  whole = true;
  for (int i = 0; i < 3; ++i) {
    const long top = m[i] * (grid.n[i] - 1);
    const long cell_lo = std::clamp(long(std::floor(std::max(vlo[i] / h[i], -1.0))), 0L, top - 1);
    const long cell_hi = std::clamp(long(std::ceil(std::min(vhi[i] / h[i], double(top) + 1))), cell_lo + 1, top);
    lo[i] = std::clamp(long(std::floor((pp[i] - reach) / h[i])), cell_lo, cell_hi - 1);
    const long hi = std::clamp(long(std::ceil((pp[i] + reach) / h[i])), lo[i] + 1, cell_hi);
    n[i] = hi - lo[i] + 1;
    grid_face_lo[i] = lo[i] == cell_lo;
    grid_face_hi[i] = hi == cell_hi;
    whole = whole && grid_face_lo[i] && grid_face_hi[i];
  }
  return n[0] * n[1] * n[2] <= 300000;
}

// f at a sub-grid point of the box, once: f in an active cube containing
// the point, else the cube's corner sign.
double CellMarch::f_at(long x, long y, long z) {
  double& v = s.fv[idx(x, y, z)];
  if (std::isnan(v)) {
    bool act = false;
    for (int k = 0; k < 8 && !act; ++k) {
      const long c[3] = {(x - (k & 1)) / m[0], (y - ((k >> 1) & 1)) / m[1], (z - ((k >> 2) & 1)) / m[2]};
      act = grid.active(c[0], c[1], c[2]);
    }
    if (act) v = f.value(point(x, y, z));
    else v = grid.neg(std::min(x / m[0], grid.n[0] - 1), std::min(y / m[1], grid.n[1] - 1), std::min(z / m[2], grid.n[2] - 1)) ? -1.0 : 1.0;
  }
  return v;
}

// The MT vertex on the sub-grid edge from point ca (key ka) to cb, once:
// the edge is keyed by its first end and the step to the other (27
// directions).
int CellMarch::vertex(long long ka, long long kb, const long (&ca)[3], const long (&cb)[3]) {
  const long long key = ka * 27 + (cb[0] - ca[0] + 1) + 3 * (cb[1] - ca[1] + 1) + 9 * (cb[2] - ca[2] + 1);
  auto it = s.vid.find(key);
  if (it != s.vid.end()) return it->second;
  const double fa = f_at(ca[0], ca[1], ca[2]), fb = f_at(cb[0], cb[1], cb[2]);
  const double t = fa / (fa - fb);
  const Vec3 xa = point(ca[0], ca[1], ca[2]), xb = point(cb[0], cb[1], cb[2]);
  const Vec3 x{xa[0] + t * (xb[0] - xa[0]), xa[1] + t * (xb[1] - xa[1]), xa[2] + t * (xb[2] - xa[2])};
  s.pv.push_back({x, ka, kb});
  s.vid.emplace(key, int(s.pv.size()) - 1);
  return int(s.pv.size()) - 1;
}

// Marching tetrahedra over the box's sub-cubes (6 tetrahedra around each
// sub-cube's main diagonal: the same split in every sub-cube, so the pieces
// fit); only sub-cubes of active cubes can meet S, and those wholly beyond
// one face of V(p) hold none of S n V(p).
void CellMarch::march() {
  s.fv.assign(std::size_t(n[0] * n[1] * n[2]), NAN);
  s.vid.clear();
  s.pv.clear();
  s.tris.clear();
  s.tri_border.clear();
  for (long z = lo[2]; z + 1 < lo[2] + n[2]; ++z)
    for (long y = lo[1]; y + 1 < lo[1] + n[1]; ++y)
      for (long x = lo[0]; x + 1 < lo[0] + n[0]; ++x) {
        if (!grid.active(x / m[0], y / m[1], z / m[2])) continue;
        bool beyond = false;
        for (std::size_t e = 0; e < s.hs.size() && !beyond; ++e)
          beyond = beyond_face(s.hs[e], x, y, z, [&](long i, long j, long k) { return point(i, j, k); });
        if (!beyond) sub_cube(x, y, z);
      }
}

// The MT triangles of sub-cube (x, y, z), marked when it lies on a side
// of the box that could still move.
void CellMarch::sub_cube(long x, long y, long z) {
  static const int tets[6][4] = {{0, 1, 3, 7}, {0, 3, 2, 7}, {0, 2, 6, 7}, {0, 6, 4, 7}, {0, 4, 5, 7}, {0, 5, 1, 7}};
  long c[8][3];
  double v[8];
  long long key[8];
  for (int k = 0; k < 8; ++k) {
    c[k][0] = x + (k & 1);
    c[k][1] = y + ((k >> 1) & 1);
    c[k][2] = z + ((k >> 2) & 1);
    v[k] = f_at(c[k][0], c[k][1], c[k][2]);
    key[k] = static_cast<long long>(idx(c[k][0], c[k][1], c[k][2]));
  }
  const bool side = (x == lo[0] && !grid_face_lo[0]) || (y == lo[1] && !grid_face_lo[1]) ||
                    (z == lo[2] && !grid_face_lo[2]) || (x + 2 == lo[0] + n[0] && !grid_face_hi[0]) ||
                    (y + 2 == lo[1] + n[1] && !grid_face_hi[1]) || (z + 2 == lo[2] + n[2] && !grid_face_hi[2]);
  for (const auto& t : tets) {
    int ins[4], outs[4], ni = 0, no = 0;
    for (int m = 0; m < 4; ++m) (SurfaceSampler::inside(v[t[m]]) ? ins[ni++] : outs[no++]) = t[m];
    if (ni == 0 || no == 0) continue;
    auto vx = [&](int a, int b) {
      if (key[a] > key[b]) std::swap(a, b);
      return vertex(key[a], key[b], c[a], c[b]);
    };
    auto add = [&](const std::array<int, 3>& tr) {
      s.tris.push_back(tr);
      s.tri_border.push_back(side);
    };
    if (ni == 1 || no == 1) {
      const int a = ni == 1 ? ins[0] : outs[0];
      const int* o = ni == 1 ? outs : ins;
      add({vx(a, o[0]), vx(a, o[1]), vx(a, o[2])});
    } else {
      const int q0 = vx(ins[0], outs[0]), q1 = vx(ins[0], outs[1]), q2 = vx(ins[1], outs[1]), q3 = vx(ins[1], outs[0]);
      add({q0, q1, q2});
      add({q0, q2, q3});
    }
  }
}

// The part of MT triangle t inside V(p), as a convex polygon (empty if none).
void CellMarch::clip(int t, std::vector<ClipVertex>& out) {
  const auto& tv = s.tris[std::size_t(t)];
  const long long H = static_cast<long long>(s.hs.size());
  out.clear();
  for (int k = 0; k < 3; ++k)
    out.push_back({s.pv[std::size_t(tv[k])].x, ClipKey{0, tv[k], 0}, edge_key(tv[k], tv[(k + 1) % 3])});
  for (long long hi = 0; hi < H && !out.empty(); ++hi) {
    const HalfSpace& e = s.hs[std::size_t(hi)];
    bool any_out = false;
    for (const ClipVertex& v : out) any_out = any_out || dot(e.d, v.x) > e.c;
    if (!any_out) continue;
    s.next.clear();
    for (std::size_t m = 0; m < out.size(); ++m) {
      const ClipVertex& P = out[m];
      const ClipVertex& Q = out[(m + 1) % out.size()];
      const bool pin = dot(e.d, P.x) <= e.c, qin = dot(e.d, Q.x) <= e.c;
      if (pin == qin) {
        if (pin) s.next.push_back(P);
        continue;
      }
      // The crossing, from the edge's own ends in a fixed order so that
      // both triangles at an MT edge compute the same point.
      Vec3 A = P.x, B = Q.x;
      ClipKey key;
      if (P.support >= 0) {
        const int i = int(P.support >> 32), j = int(P.support & 0xffffffff);
        A = s.pv[std::size_t(i)].x;
        B = s.pv[std::size_t(j)].x;
        key = {1, P.support, hi};
      } else {
        const long long h0 = -1 - P.support;
        if (!pin) std::swap(A, B);
        key = {2, t, std::min(h0, hi) * H + std::max(h0, hi)};
      }
      const double sa = dot(e.d, A) - e.c, sb = dot(e.d, B) - e.c;
      const double u = sa / (sa - sb);
      const Vec3 X{A[0] + u * (B[0] - A[0]), A[1] + u * (B[1] - A[1]), A[2] + u * (B[2] - A[2])};
      if (pin) {
        s.next.push_back(P);
        s.next.push_back({X, key, -1 - hi});  // leaves along the plane
      } else {
        s.next.push_back({X, key, P.support});
      }
    }
    out.swap(s.next);
  }
}

// Every triangle clipped to V(p); true (grow the box) if a clipped piece
// lies in a sub-cube on a side of the box that could still move.
bool CellMarch::clip_all() {
  s.polys.resize(std::max(s.polys.size(), s.tris.size()));
  bool border = false;
  for (std::size_t t = 0; t < s.tris.size(); ++t) {
    clip(int(t), s.polys[t]);
    border = border || (s.tri_border[t] && !s.polys[t].empty());
  }
  return border;
}

void glue_pieces(const std::vector<std::vector<ClipVertex>>& polys, std::size_t count, ClippedComplex& k) {
  std::vector<int> parent;
  auto find = [&](int x) {
    while (parent[std::size_t(x)] != x) x = parent[std::size_t(x)] = parent[std::size_t(parent[std::size_t(x)])];
    return x;
  };
  std::vector<std::pair<int, int>> edges;
  for (std::size_t t = 0; t < count; ++t) {
    const std::vector<ClipVertex>& pg = polys[t];
    if (pg.size() < 3) continue;
    ++k.faces;
    int first = -1, prev = -1;
    for (const ClipVertex& cv : pg) {
      auto [it, fresh] = k.vkey.emplace(cv.key, int(k.vx.size()));
      if (fresh) {
        k.vx.push_back(cv.x);
        parent.push_back(it->second);
      }
      const int id = it->second;
      if (prev >= 0) edges.emplace_back(std::min(prev, id), std::max(prev, id));
      else first = id;
      prev = id;
    }
    edges.emplace_back(std::min(prev, first), std::max(prev, first));
  }
  if (k.faces == 0) return;
  std::sort(edges.begin(), edges.end());
  edges.erase(std::unique(edges.begin(), edges.end()), edges.end());
  for (const auto& [a, b] : edges) parent[std::size_t(find(a))] = find(b);
  for (std::size_t v = 0; v < k.vx.size(); ++v) k.components += find(int(v)) == int(v);
  k.chi = static_cast<long long>(k.vx.size()) - static_cast<long long>(edges.size()) + k.faces;
}

// Strictly inside V(p): a point on a face is also the neighbour's.
bool CellMarch::interior(const Vec3& x) const {
  for (const HalfSpace& e : s.hs)
    if (dot(e.d, x) >= e.c - 1e-9 * grid.delta * norm(e.d)) return false;
  return true;
}

// The MT vertex strictly inside V(p) farthest from p whose point of S
// (moved along its sub-grid edge) is still strictly inside and not p
// itself (10^-3 delta away); none of the first 64: false (the caller
// refines at p's farthest surface centre).
bool CellMarch::far_point(const ClippedComplex& k, Vec3& q) const {
  std::vector<std::pair<double, int>> order;  // (-distance^2, MT vertex)
  for (const auto& [key, id] : k.vkey)
    if (key[0] == 0 && interior(k.vx[std::size_t(id)])) order.emplace_back(-dist2(k.vx[std::size_t(id)], pp), int(key[1]));
  std::sort(order.begin(), order.end());
  auto coords = [&](long long key) { return point(lo[0] + long(key % n[0]), lo[1] + long((key / n[0]) % n[1]), lo[2] + long(key / n[0] / n[1])); };
  for (std::size_t i = 0; i < order.size() && i < 64; ++i) {
    const MtVertex& b = s.pv[std::size_t(order[i].second)];
    const Vec3 xa = coords(b.a), xb = coords(b.b);
    if (!f.bisect(xa, xb, f.value(xa), q)) continue;  // no root between them: not a point of S
    if (interior(q) && dist2(q, pp) > 1e-6 * grid.delta * grid.delta) return true;
  }
  return false;
}

// Where HandleDetection cannot decide: the surface centre of p's restricted
// facet farthest from p (a point of S that shrinks V(p)); false if p has none.
static bool refinement_point(const Tr& tr, Vh p, Vec3& x) {
  thread_local std::vector<Ch> cells;
  cells.clear();
  star_cells_threadsafe(tr, p, cells);
  const Vec3 pp = vec(p->point());
  double best = -1;
  for (Ch c : cells)
    for (int i = 0; i < 4; ++i)
      if (c->vertex(i) != p && c->facet.restricted(i) && dist2(facet_center(Facet(c, i)), pp) > best) {
        best = dist2(facet_center(Facet(c, i)), pp);
        x = facet_center(Facet(c, i));
      }
  return best > 0;
}

// HandleDetection's cheap certificate (doc/implicit2mesh.md 4.3(a)): the active cubes
// reached from p's cube through mixed faces, without those lying wholly
// outside one half-space of V(p). If every active cube holds a disk of S,
// every mixed face one arc and every crossed edge one point (F2), S inside
// their union X has Euler characteristic cubes - mixed faces + crossed
// edges, and it is connected; when that is 1, S n X is a disk, so S n V(p)
// (inside it) has no handle. True: no handle.
bool handle_free(const Tr& tr, const CubeGrid& grid, Vh p) {
  const Vec3 pp = vec(p->point());
  thread_local std::vector<HalfSpace> hs;
  voronoi_cell(tr, p, hs);
  auto outside = [&](long x, long y, long z) {  // wholly beyond one face of V(p)
    // beyond_face's corners, their coordinates computed once a cube.
    const double cx[2] = {x * grid.s[0], (x + 1) * grid.s[0]}, cy[2] = {y * grid.s[1], (y + 1) * grid.s[1]},
                 cz[2] = {z * grid.s[2], (z + 1) * grid.s[2]};
    for (const HalfSpace& e : hs)
      if (dot(e.d, Vec3{cx[e.d[0] < 0], cy[e.d[1] < 0], cz[e.d[2] < 0]}) > e.c) return true;
    return false;
  };
  long c0[3];
  for (int k = 0; k < 3; ++k) c0[k] = std::clamp(long(std::floor(pp[k] / grid.s[k])), 0L, grid.n[k] - 2);
  if (!grid.active(c0[0], c0[1], c0[2])) return false;
  const long nx = grid.n[0], ny = grid.n[1];
  auto key = [&](long x, long y, long z) { return x + nx * (y + ny * z); };
  thread_local std::vector<long long> faces, edges;
  thread_local std::vector<std::array<long, 3>> stack;
  thread_local KeySet tested;  // keys + 1 of the cubes met
  tested.clear();
  tested.insert(std::uint64_t(key(c0[0], c0[1], c0[2]) + 1));
  std::size_t cubes = 1;  // reached
  faces.clear();
  edges.clear();
  stack.assign(1, {c0[0], c0[1], c0[2]});
  // The corners (bit k: corner (k & 1, k >> 1 & 1, k >> 2 & 1)) on side
  // `side` of axis a.
  static constexpr unsigned kFace[3][2] = {{0x55, 0xaa}, {0x33, 0xcc}, {0x0f, 0xf0}};
  while (!stack.empty()) {
    const auto [x, y, z] = stack.back();
    stack.pop_back();
    if (cubes > 512) return false;  // V(p) still large: the full test
    unsigned sg = 0;  // bit k: corner k inside
    for (int k = 0; k < 8; ++k) sg |= unsigned(grid.neg(x + (k & 1), y + ((k >> 1) & 1), z + ((k >> 2) & 1))) << k;
    // 12 edges: corner pairs differing in one bit; key (corner, axis).
    for (int k = 0; k < 8; ++k)
      for (int a = 0; a < 3; ++a)
        if (!(k >> a & 1) && ((sg >> k ^ sg >> (k | 1 << a)) & 1))
          edges.push_back(3 * key(x + (k & 1), y + ((k >> 1) & 1), z + ((k >> 2) & 1)) + a);
    // 6 faces: axis a, side 0/1; key (min corner, axis).
    for (int a = 0; a < 3; ++a)
      for (int side = 0; side < 2; ++side) {
        const unsigned m = kFace[a][side];
        if (!(sg & m) || !(~sg & m)) continue;  // not mixed
        long f[3] = {x, y, z};
        f[a] += side;
        faces.push_back(3 * key(f[0], f[1], f[2]) + a);
        long nbr[3] = {x, y, z};
        nbr[a] += side ? 1 : -1;
        if (!grid.active(nbr[0], nbr[1], nbr[2])) continue;
        const long long kn = key(nbr[0], nbr[1], nbr[2]);
        // Each cube tested once: reached, or wholly outside V(p) (the same
        // answer from any side).
        if (!tested.insert(std::uint64_t(kn + 1)) || outside(nbr[0], nbr[1], nbr[2])) continue;
        ++cubes;
        stack.push_back({nbr[0], nbr[1], nbr[2]});
      }
  }
  std::sort(faces.begin(), faces.end());
  std::sort(edges.begin(), edges.end());
  const long long F = std::unique(faces.begin(), faces.end()) - faces.begin();
  const long long E = std::unique(edges.begin(), edges.end()) - edges.begin();
  return static_cast<long long>(cubes) - F + E == 1;
}

// One vertex: the cheap certificate (when `cheap`), then the full test; an
// undecided answer asks for a refinement point instead. True: x goes in.
static bool check_vertex(const Tr& tr, const SurfaceSampler& f, Vh p, bool cheap, Vec3& x, std::atomic<long long>& full,
                         std::atomic<long long>& undecided, std::atomic<long long>& unresolved) {
  if (cheap && handle_free(tr, f.grid(), p)) return false;
  full.fetch_add(1, std::memory_order_relaxed);
  const HandleAnswer a = handle_detection(tr, f, p, x);
  if (a == HandleAnswer::kNotDisk) return true;
  if (a == HandleAnswer::kDisk) return false;
  undecided.fetch_add(1, std::memory_order_relaxed);
  if (refinement_point(tr, p, x)) return true;
  unresolved.fetch_add(1, std::memory_order_relaxed);
  return false;
}

static Candidates check_all(const Tr& tr, const SurfaceSampler& f, const std::vector<Vh>& todo, bool cheap, int threads,
                            HandleChecks& checks) {
  // The few points found, per thread with their vertex's index, not a
  // point per vertex checked: the pass after the queues drain checks every
  // vertex, and that array (24 bytes a vertex) was the run's peak (CT liver).
  const unsigned nt = implicit_detail::resolve_threads(unsigned(std::max(1, threads)));
  std::vector<std::vector<std::pair<std::size_t, Vec3>>> found(nt);
  std::atomic<long long> full{0}, undecided{0}, unresolved{0};
  implicit_detail::parallel_for(long(todo.size()), nt, [&](long a, long b, unsigned t) {
    for (long k = a; k < b; ++k) {
      Vec3 x;
      if (check_vertex(tr, f, todo[std::size_t(k)], cheap, x, full, undecided, unresolved)) found[t].emplace_back(std::size_t(k), x);
    }
  });
  checks.full += full.load();
  checks.certified += static_cast<long long>(todo.size()) - full.load();
  checks.undecided += undecided.load();
  checks.unresolved += unresolved.load();
  std::vector<std::pair<std::size_t, Vec3>> all;
  for (const auto& v : found) all.insert(all.end(), v.begin(), v.end());
  std::sort(all.begin(), all.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
  Candidates pts;
  for (const auto& [k, x] : all) pts.emplace_back(x, dist2(x, vec(todo[k]->point())));
  return pts;
}

// TOPOLOGY's pass (8.3, after TopoDisk and FacetCycle): the full test
// (marching tetrahedra, about a thousand evaluations of f) only where the
// cheap certificate does not settle it.
Candidates handle_points(const Tr& tr, const SurfaceSampler& f, const std::vector<Vh>& todo, int threads, HandleChecks& checks) {
  return check_all(tr, f, todo, true, threads, checks);
}

bool handle_component_points(const Tr& tr, const SurfaceSampler& f, const std::vector<Vh>& vertices, const std::vector<int>& bad,
                             int threads, HandleChecks& checks, Candidates& pts) {
  std::vector<char> is_bad(std::size_t(f.grid().components) + 1, 0);
  for (int c : bad)
    if (c >= 0) is_bad[std::size_t(c)] = 1;
  std::vector<Vh> todo;
  for (Vh v : vertices)
    if (v != Vh() && on_surface(v->info().origin) && v->info().comp >= 0 && is_bad[std::size_t(v->info().comp)])
      todo.push_back(v);
  // On components of more than kHandleBudget samples (brain tissue of genus
  // ~2600), the fallback's refinement is much cheaper.
  if (todo.size() > kHandleBudget) return false;
  pts = check_all(tr, f, todo, false, threads, checks);
  return true;
}

} // namespace imgmesh::surface_detail
