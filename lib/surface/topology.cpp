#include "surface/topology.hpp"

#include <algorithm>
#include <cmath>
#include <map>
#include <numeric>
#include <unordered_map>

namespace imgmesh {
namespace {

struct UnionFind {
  std::vector<int> parent;
  explicit UnionFind(std::size_t n) : parent(n) { std::iota(parent.begin(), parent.end(), 0); }
  int find(int a) {
    while (parent[a] != a) a = parent[a] = parent[parent[a]];
    return a;
  }
  void unite(int a, int b) { parent[find(a)] = find(b); }
};

// Euler characteristic per component from faces given as vertex and edge keys.
template <class Key>
std::vector<int> euler_per_component(UnionFind& uf, const std::vector<std::vector<Key>>& face_vertices,
                                     const std::vector<std::vector<Key>>& face_edges) {
  const std::size_t n = face_vertices.size();
  std::map<int, int> comp_of_root;
  std::vector<int> comp(n);
  for (std::size_t f = 0; f < n; ++f) {
    int r = uf.find(int(f));
    auto it = comp_of_root.emplace(r, int(comp_of_root.size())).first;
    comp[f] = it->second;
  }
  std::vector<long long> chi(comp_of_root.size(), 0);
  std::vector<std::pair<int, Key>> verts, edges;
  for (std::size_t f = 0; f < n; ++f) {
    chi[comp[f]] += 1;
    for (const Key& v : face_vertices[f]) verts.emplace_back(comp[f], v);
    for (const Key& e : face_edges[f]) edges.emplace_back(comp[f], e);
  }
  std::sort(verts.begin(), verts.end());
  verts.erase(std::unique(verts.begin(), verts.end()), verts.end());
  std::sort(edges.begin(), edges.end());
  edges.erase(std::unique(edges.begin(), edges.end()), edges.end());
  for (auto& v : verts) chi[v.first] += 1;
  for (auto& e : edges) chi[e.first] -= 1;
  std::vector<int> out(chi.begin(), chi.end());
  std::sort(out.begin(), out.end());
  return out;
}

} // namespace

SurfaceTopology voxel_boundary_topology(const FloatImage& g) {
  const long long nx = (long long)g.size[0], ny = (long long)g.size[1], nz = (long long)g.size[2];
  auto in = [&](long long x, long long y, long long z) {
    return g.inside(x, y, z) && g(std::size_t(x), std::size_t(y), std::size_t(z)) < 0;
  };
  // Corners of voxel (x,y,z) span [x, x+1]; shift by one so outside voxels fit.
  const long long cx = nx + 3, cy = ny + 3;
  auto corner = [&](long long x, long long y, long long z) { return (x + 1) + cx * ((y + 1) + cy * (z + 1)); };
  std::vector<std::vector<long long>> fv, fe;
  for (long long z = 0; z < nz; ++z)
    for (long long y = 0; y < ny; ++y)
      for (long long x = 0; x < nx; ++x) {
        if (!in(x, y, z)) continue;
        for (int a = 0; a < 3; ++a)
          for (int s = -1; s <= 1; s += 2) {
            long long p[3] = {x, y, z};
            p[a] += s;
            if (in(p[0], p[1], p[2])) continue;
            // The quad lies in the plane coordinate[a] = (s > 0 ? v+1 : v).
            long long o[3] = {x, y, z};
            if (s > 0) o[a] += 1;
            const int b = (a + 1) % 3, c = (a + 2) % 3;
            long long q[4][3];
            for (int k = 0; k < 4; ++k) {
              q[k][0] = o[0]; q[k][1] = o[1]; q[k][2] = o[2];
            }
            q[1][b] += 1; q[2][b] += 1; q[2][c] += 1; q[3][c] += 1;
            std::vector<long long> vs, es;
            for (int k = 0; k < 4; ++k) vs.push_back(corner(q[k][0], q[k][1], q[k][2]));
            // Edges: from q0 along b, from q0 along c, from q1 along c, from q3 along b.
            es.push_back(corner(q[0][0], q[0][1], q[0][2]) * 3 + b);
            es.push_back(corner(q[0][0], q[0][1], q[0][2]) * 3 + c);
            es.push_back(corner(q[1][0], q[1][1], q[1][2]) * 3 + c);
            es.push_back(corner(q[3][0], q[3][1], q[3][2]) * 3 + b);
            fv.push_back(std::move(vs));
            fe.push_back(std::move(es));
          }
      }
  SurfaceTopology t;
  UnionFind uf(fv.size());
  std::unordered_map<long long, std::vector<int>> by_edge;
  for (std::size_t f = 0; f < fe.size(); ++f)
    for (long long e : fe[f]) by_edge[e].push_back(int(f));
  for (auto& kv : by_edge) {
    if (kv.second.size() != 2) t.manifold = false;
    for (std::size_t i = 1; i < kv.second.size(); ++i) uf.unite(kv.second[0], kv.second[i]);
  }
  t.euler = euler_per_component(uf, fv, fe);
  return t;
}

SurfaceTopology mesh_topology(const SurfaceMesh& m) {
  SurfaceTopology t;
  const std::size_t nf = m.triangles.size();
  auto key = [](int a, int b) { return (static_cast<long long>(std::min(a, b)) << 32) | std::max(a, b); };
  std::unordered_map<long long, std::vector<std::pair<int, bool>>> by_edge;  // face, forward (a<b)
  std::vector<std::vector<long long>> fv(nf), fe(nf);
  for (std::size_t f = 0; f < nf; ++f) {
    const auto& tr = m.triangles[f];
    for (int k = 0; k < 3; ++k) {
      int a = tr[k], b = tr[(k + 1) % 3];
      by_edge[key(a, b)].emplace_back(int(f), a < b);
      fv[f].push_back(a);
      fe[f].push_back(key(a, b));
    }
  }
  UnionFind uf(nf);
  for (auto& kv : by_edge) {
    auto& v = kv.second;
    if (v.size() != 2) t.manifold = false;
    else if (v[0].second == v[1].second) t.oriented = false;
    for (std::size_t i = 1; i < v.size(); ++i) uf.unite(v[0].first, v[i].first);
  }
  // Vertex links: one cycle each.
  std::vector<std::vector<std::pair<int, int>>> link(m.points.size());
  for (const auto& tr : m.triangles)
    for (int k = 0; k < 3; ++k) link[tr[k]].emplace_back(tr[(k + 1) % 3], tr[(k + 2) % 3]);
  for (auto& l : link) {
    if (l.empty()) continue;
    std::map<int, std::vector<int>> adj;
    for (auto& e : l) {
      adj[e.first].push_back(e.second);
      adj[e.second].push_back(e.first);
    }
    bool ok = true;
    for (auto& kv : adj) ok = ok && kv.second.size() == 2;
    if (ok) {  // walk the cycle from one link vertex
      int start = adj.begin()->first, prev = -1, cur = start;
      std::size_t steps = 0;
      do {
        const auto& nb = adj[cur];
        int next = nb[0] != prev ? nb[0] : nb[1];
        prev = cur;
        cur = next;
        ++steps;
      } while (cur != start && steps <= adj.size());
      ok = steps == adj.size();
    }
    if (!ok) t.manifold = false;
  }
  t.euler = euler_per_component(uf, fv, fe);
  return t;
}

TriangleQuality triangle_quality(const SurfaceMesh& m) {
  TriangleQuality q;
  q.min_angle = M_PI;
  for (const auto& tr : m.triangles) {
    const auto &a = m.points[tr[0]], &b = m.points[tr[1]], &c = m.points[tr[2]];
    auto dist = [](const Vec3& u, const Vec3& v) {
      return std::sqrt((u[0] - v[0]) * (u[0] - v[0]) + (u[1] - v[1]) * (u[1] - v[1]) + (u[2] - v[2]) * (u[2] - v[2]));
    };
    const double la = dist(b, c), lb = dist(c, a), lc = dist(a, b);
    const double s = (la + lb + lc) / 2;
    const double area = std::sqrt(std::max(0.0, s * (s - la) * (s - lb) * (s - lc)));
    const double lmin = std::min({la, lb, lc});
    const double R = area > 0 ? la * lb * lc / (4 * area) : INFINITY;
    q.max_ratio = std::max(q.max_ratio, lmin > 0 ? R / lmin : INFINITY);
    // Smallest angle is opposite the shortest edge: sin(A) = lmin / (2R).
    const double ang = R > 0 && std::isfinite(R) ? std::asin(std::min(1.0, lmin / (2 * R))) : 0;
    q.min_angle = std::min(q.min_angle, ang);
  }
  if (m.triangles.empty()) q.min_angle = 0;
  return q;
}

} // namespace imgmesh
