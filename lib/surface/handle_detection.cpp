#include "surface/handle_detection.hpp"

#include "implicit/parallel.hpp"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <unordered_map>

namespace imgmesh::surface_detail {

void voronoi_cell(const Tr& tr, Vh p, std::vector<HalfSpace>& hs) {
  thread_local std::vector<Vh> adj;
  adj.clear();
  tr.adjacent_vertices_threadsafe(p, std::back_inserter(adj));
  const Vec3 pp = vec(p->point());
  hs.clear();
  for (Vh w : adj)
    if (!tr.is_infinite(w)) {
      const Vec3 pw = vec(w->point());
      hs.push_back({sub(pw, pp), (dot(pw, pw) - dot(pp, pp)) / 2});
    }
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
bool handle_detection(const Tr& tr, const SurfaceSampler& f, Vh p, Vec3& q) {
  const CubeGrid& grid = f.grid();
  // Runs on several threads: thread-safe adjacency, thread-local scratch.
  thread_local std::vector<Ch> cells;
  cells.clear();
  tr.incident_cells_threadsafe(p, std::back_inserter(cells));
  const Vec3 pp = vec(p->point());
  double reach2 = 0;
  for (Ch c : cells)
    for (int i = 0; i < 4; ++i)
      if (c->vertex(i) != p && (c->facet[i].state & kRestricted)) reach2 = std::max(reach2, dist2(facet_center(Facet(c, i)), pp));
  // No restricted facet at p: S inside V(p) meets no Voronoi edge (a whole
  // small component, say); start from a voxel.
  if (reach2 <= 0) reach2 = grid.delta * grid.delta;
  thread_local std::vector<HalfSpace> hs;
  voronoi_cell(tr, p, hs);
  auto in_cell = [&](const Vec3& x) {
    for (const HalfSpace& e : hs)
      if (dot(e.d, x) > e.c) return false;
    return true;
  };
  // The box grows while that part of S reaches its border.
  const long long NX = 2 * grid.n[0], NY = 2 * grid.n[1];
  thread_local std::vector<double> fv;
  thread_local std::unordered_map<long long, int> vid;
  struct PV { Vec3 x; long long a, b; bool in; };
  thread_local std::vector<PV> pv;
  thread_local std::vector<std::array<int, 3>> tris;
  bool border = false;
  const double h[3] = {grid.s[0] / 2, grid.s[1] / 2, grid.s[2] / 2};
  auto point = [&](long x, long y, long z) { return Vec3{x * h[0], y * h[1], z * h[2]}; };
  for (double scale = 2;; scale *= 2) {
    const double reach = scale * std::sqrt(reach2);
    // Box in sub-grid indices (spacing s_i / 2).
    long lo[3], n[3];
    for (int i = 0; i < 3; ++i) {
      const long top = 2 * (grid.n[i] - 1);
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
          act = grid.active(c[0], c[1], c[2]);
        }
        if (act) v = f.value(point(x, y, z));
        else v = grid.neg(std::min(x / 2, grid.n[0] - 1), std::min(y / 2, grid.n[1] - 1), std::min(z / 2, grid.n[2] - 1)) ? -1.0 : 1.0;
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
          if (!grid.active(x / 2, y / 2, z / 2)) continue;
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
            for (int m = 0; m < 4; ++m) (SurfaceSampler::inside(v[t[m]]) ? ins[ni++] : outs[no++]) = t[m];
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
  q = f.bisect(xa, xb, f.value(xa));
  return true;
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
  auto outside = [&](long x, long y, long z) {  // all 8 corners beyond one face of V(p)
    for (const HalfSpace& e : hs) {
      bool all = true;
      for (int k = 0; k < 8 && all; ++k) {
        const Vec3 c{(x + (k & 1)) * grid.s[0], (y + ((k >> 1) & 1)) * grid.s[1], (z + ((k >> 2) & 1)) * grid.s[2]};
        all = dot(e.d, c) > e.c;
      }
      if (all) return true;
    }
    return false;
  };
  long c0[3];
  for (int k = 0; k < 3; ++k) c0[k] = std::clamp(long(std::floor(pp[k] / grid.s[k])), 0L, grid.n[k] - 2);
  if (!grid.active(c0[0], c0[1], c0[2])) return false;
  const long nx = grid.n[0], ny = grid.n[1];
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
    for (int k = 0; k < 8; ++k) sg[k] = grid.neg(x + (k & 1), y + ((k >> 1) & 1), z + ((k >> 2) & 1));
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
        if (!grid.active(nbr[0], nbr[1], nbr[2])) continue;
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

// TOPOLOGY's pass (8.3, after TopoDisk and FacetCycle): the full test
// (marching tetrahedra, about a thousand evaluations of f) only where the
// cheap certificate does not settle it.
Candidates handle_points(const Tr& tr, const SurfaceSampler& f, const std::vector<Vh>& todo, int threads, HandleChecks& checks) {
  std::vector<char> found(todo.size(), 0);
  std::vector<Vec3> xs(todo.size());
  std::atomic<long long> full{0};
  implicit_detail::parallel_for(long(todo.size()), unsigned(std::max(1, threads)), [&](long a, long b, unsigned) {
    for (long k = a; k < b; ++k) {
      if (handle_free(tr, f.grid(), todo[std::size_t(k)])) continue;
      full.fetch_add(1, std::memory_order_relaxed);
      found[std::size_t(k)] = handle_detection(tr, f, todo[std::size_t(k)], xs[std::size_t(k)]);
    }
  });
  checks.full += full.load();
  checks.certified += static_cast<long long>(todo.size()) - full.load();
  Candidates pts;
  for (std::size_t k = 0; k < todo.size(); ++k)
    if (found[k]) pts.emplace_back(xs[k], dist2(xs[k], vec(todo[k]->point())));
  return pts;
}

bool handle_component_points(const Tr& tr, const SurfaceSampler& f, const std::vector<Vh>& vertices, const std::vector<int>& bad,
                             int threads, HandleChecks& checks, Candidates& pts) {
  std::vector<char> is_bad(std::size_t(f.grid().components) + 1, 0);
  for (int c : bad)
    if (c >= 0) is_bad[std::size_t(c)] = 1;
  std::vector<Vh> todo;
  for (Vh v : vertices)
    if (v != Vh() && v->info().comp >= 0 && is_bad[std::size_t(v->info().comp)]) todo.push_back(v);
  // On components of more than kHandleBudget samples (brain tissue of genus
  // ~2600), the fallback's refinement is much cheaper.
  if (todo.size() > kHandleBudget) return false;
  std::vector<char> found(todo.size(), 0);
  std::vector<Vec3> xs(todo.size());
  implicit_detail::parallel_for(long(todo.size()), unsigned(std::max(1, threads)), [&](long a, long b, unsigned) {
    for (long k = a; k < b; ++k) found[std::size_t(k)] = handle_detection(tr, f, todo[std::size_t(k)], xs[std::size_t(k)]);
  });
  pts.clear();
  for (std::size_t k = 0; k < todo.size(); ++k)
    if (found[k]) pts.emplace_back(xs[k], dist2(xs[k], vec(todo[k]->point())));
  checks.full += static_cast<long long>(todo.size());
  return true;
}

} // namespace imgmesh::surface_detail
