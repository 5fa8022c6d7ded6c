#include "mesh/topology.hpp"

#include "mesh/topology_detail.hpp"

#include "util/error.hpp"
#include "util/ranked_bits.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <numeric>
#include <string>

namespace imgmesh {

using mesh_detail::UnionFind;

std::vector<long long> MeshTopology::euler_list() const {
  std::vector<long long> e;
  for (const auto& c : components) e.push_back(c.euler);
  return e;
}

std::vector<long long> MeshTopology::sorted_euler() const {
  std::vector<long long> e = euler_list();
  std::sort(e.begin(), e.end());
  return e;
}

std::string euler_summary(std::vector<long long> euler) {
  std::sort(euler.begin(), euler.end());
  std::string out;
  for (std::size_t i = 0, j; i < euler.size(); i = j) {
    for (j = i; j < euler.size() && euler[j] == euler[i];) ++j;
    out += (i ? ", " : "") + std::to_string(euler[i]) + (j - i > 1 ? " (x" + std::to_string(j - i) + ")" : "");
  }
  return out;
}

Json MeshTopology::to_json() const {
  Json j = Json::object();
  j["components"] = components.size();
  j["euler"] = euler_list();
  Json comps = Json::array();
  for (const auto& c : components) {
    Json o = Json::object();
    o["vertices"] = c.vertices;
    o["edges"] = c.edges;
    o["faces"] = c.faces;
    o["euler"] = c.euler;
    o["genus"] = c.genus;
    o["boundary_loops"] = c.boundary_loops;
    o["closed"] = c.closed;
    o["manifold"] = c.manifold;
    o["oriented"] = c.oriented;
    o["orientable"] = c.orientable;
    comps.push_back(o);
  }
  j["component_list"] = comps;
  j["euler_total"] = euler;
  j["closed"] = closed;
  j["manifold"] = manifold;
  j["oriented"] = oriented;
  j["boundary_loops"] = boundary_loops;
  j["boundary_edges"] = boundary_edges;
  j["nonmanifold_edges"] = nonmanifold_edges;
  j["nonmanifold_vertices"] = nonmanifold_vertices;
  j["inconsistent_edges"] = inconsistent_edges;
  j["isolated_vertices"] = isolated_vertices;
  return j;
}

namespace {

// Union-find that also tracks the parity (flip or not) of each face relative
// to its root, to tell orientable components from non-orientable ones.
struct ParityUnionFind {
  std::vector<std::uint32_t> p;  // fewer than 2^31 faces (checked by the caller)
  std::vector<std::uint8_t> par;  // parity to parent
  explicit ParityUnionFind(std::size_t n) : p(n), par(n, 0) { std::iota(p.begin(), p.end(), std::uint32_t(0)); }
  std::size_t find(std::size_t x, std::uint8_t& parity) {
    parity = 0;
    std::size_t r = x;
    while (p[r] != r) { parity ^= par[r]; r = p[r]; }
    // Path compression with parities.
    std::uint8_t acc = parity;
    while (p[x] != r) {
      const std::size_t next = p[x];
      const std::uint8_t px = par[x];
      p[x] = std::uint32_t(r);
      par[x] = acc;
      acc ^= px;
      x = next;
    }
    return r;
  }
  // Returns false on a contradiction.
  bool unite(std::size_t a, std::size_t b, std::uint8_t rel) {
    std::uint8_t pa, pb;
    const std::size_t ra = find(a, pa), rb = find(b, pb);
    if (ra == rb) return (pa ^ pb) == rel;
    p[rb] = std::uint32_t(ra);
    par[rb] = pa ^ pb ^ rel;
    return true;
  }
};

// nf faces whose corners are numbered face by face: corner(i) its vertex,
// offset(f) the first corner of face f (offset(nf) the number of corners),
// face_of(i) the face of corner i. Accessors, not arrays, so that a triangle
// mesh is read in place: this runs beside the mesher's triangulation, at its
// peak.
template <class Corner, class Offset, class FaceOf> struct Faces {
  std::size_t nv, nf;
  Corner corner;
  Offset offset;
  FaceOf face_of;

  std::size_t corners() const { return offset(nf); }
  std::size_t next(std::size_t c) const {
    const std::size_t f = face_of(c);
    return c + 1 == offset(f + 1) ? offset(f) : c + 1;
  }
  std::size_t prev(std::size_t c) const {
    const std::size_t f = face_of(c);
    return c == offset(f) ? offset(f + 1) - 1 : c - 1;
  }
  // Whether half-edge h (by the corner it starts at) runs from the lower vertex.
  bool forward(std::size_t h) const { return corner(h) < corner(next(h)); }
};

// Vertex ids in range, none twice in a face.
template <class F> void check_faces(const F& fs) {
  for (std::size_t f = 0; f < fs.nf; ++f) {
    const std::size_t b = fs.offset(f), e = fs.offset(f + 1);  // e >= b + 3: checked by the caller
    for (std::size_t i = b; i < e; ++i) {
      if (fs.corner(i) < 0 || std::size_t(fs.corner(i)) >= fs.nv)
        throw Error("face " + std::to_string(f) + ": vertex id out of range");
      for (std::size_t k = b; k < i; ++k)
        if (fs.corner(k) == fs.corner(i)) throw Error("face " + std::to_string(f) + ": repeated vertex");
    }
  }
}

// The corners at each vertex (counted, then placed): 4 bytes a corner, where
// half-edges sorted by edge took 12 beside the mesher's triangulation at its
// peak. The half-edges of edge {a, b} are found among the corners of
// whichever end has fewer.
struct CornerIndex {
  std::vector<std::uint32_t> start;  // per vertex, then the end
  std::vector<std::uint32_t> at;     // the corners of vertex v: at[start[v]] .. at[start[v + 1] - 1]
  std::uint32_t count(std::uint32_t v) const { return start[v + 1] - start[v]; }
};

template <class F> CornerIndex index_corners(const F& fs) {
  const std::size_t nc = fs.corners();
  if (nc > 0x7fffffffu || fs.nf > 0x7fffffffu) throw Error("topology: more than 2^31 corners");
  CornerIndex x{std::vector<std::uint32_t>(fs.nv + 1, 0), std::vector<std::uint32_t>(nc)};
  for (std::size_t i = 0; i < nc; ++i) ++x.start[std::size_t(fs.corner(i)) + 1];
  for (std::size_t v = 0; v < fs.nv; ++v) x.start[v + 1] += x.start[v];
  std::vector<std::uint32_t> next(x.start.begin(), x.start.end() - 1);
  for (std::size_t i = 0; i < nc; ++i) x.at[next[std::size_t(fs.corner(i))]++] = std::uint32_t(i);
  return x;
}

// edge(lo, hi, hs) once per undirected edge, hs its half-edges (each by the
// corner it starts at) ascending; edges in the order of their first
// half-edge.
template <class F, class Edge> void for_each_edge(const F& fs, const CornerIndex& x, Edge edge) {
  std::vector<std::uint32_t> hs;
  for (std::size_t i = 0; i < fs.corners(); ++i) {
    const std::uint32_t a = std::uint32_t(fs.corner(i)), b = std::uint32_t(fs.corner(fs.next(i)));
    const std::uint32_t s = x.count(a) <= x.count(b) ? a : b, o = a ^ b ^ s;
    hs.clear();
    for (std::uint32_t k = x.start[s]; k < x.start[s + 1]; ++k) {
      const std::size_t c = x.at[k];
      if (std::uint32_t(fs.corner(fs.next(c))) == o) hs.push_back(std::uint32_t(c));
      const std::size_t p = fs.prev(c);
      if (std::uint32_t(fs.corner(p)) == o) hs.push_back(std::uint32_t(p));
    }
    std::sort(hs.begin(), hs.end());
    if (hs[0] == i) edge(std::min(a, b), std::max(a, b), hs);
  }
}

// What the walk over the edges finds, per vertex and face. Per edge, counted
// at its lower end for that end's component (known once every edge is seen):
// one walk over the edges, not two.
struct EdgeWalk {
  enum : std::uint8_t { kOpen = 1, kMisoriented = 2 };
  EdgeWalk(std::size_t nv, std::size_t nf)
      : vertices(nv), boundary(nv), faces(nf), used(nv, 0), on_boundary(nv, 0), bad_vertex(nv, 0), edges_at(nv, 0),
        edge_flags(nv, 0) {}
  UnionFind vertices, boundary;  // joined across the edges, across the boundary edges
  ParityUnionFind faces;         // joined across the edges in two faces, flipped or not
  std::vector<char> used, on_boundary, bad_vertex;  // in a face; on a boundary edge; non-manifold
  std::vector<std::size_t> nonorientable_faces;     // a face per contradiction of the flips
  std::vector<std::uint32_t> edges_at;              // edges at their lower end
  std::vector<std::uint8_t> edge_flags;             // kOpen, kMisoriented at their lower end
};

// Every edge once: boundary (one face), shared by two faces (consistently
// oriented or not), or non-manifold (more; its ends are bad vertices).
template <class F> void walk_edges(const F& fs, const CornerIndex& x, EdgeWalk& w, MeshTopology& t) {
  for (std::size_t i = 0; i < fs.corners(); ++i) w.used[std::size_t(fs.corner(i))] = 1;
  for_each_edge(fs, x, [&](std::uint32_t a, std::uint32_t b, const std::vector<std::uint32_t>& h) {
    w.vertices.unite(a, b);
    ++w.edges_at[a];
    const std::size_t n = h.size();
    if (n == 1) {
      ++t.boundary_edges;
      w.on_boundary[a] = w.on_boundary[b] = 1;
      w.boundary.unite(a, b);
      w.edge_flags[a] |= EdgeWalk::kOpen;
    } else if (n == 2) {
      const bool same = fs.forward(h[0]) == fs.forward(h[1]);
      if (same) ++t.inconsistent_edges, w.edge_flags[a] |= EdgeWalk::kMisoriented;
      if (!w.faces.unite(fs.face_of(h[0]), fs.face_of(h[1]), same ? 1 : 0))
        w.nonorientable_faces.push_back(fs.face_of(h[0]));
    } else {
      ++t.nonmanifold_edges;
      w.bad_vertex[a] = w.bad_vertex[b] = 1;
    }
  });
}

// A vertex whose corners form more than one fan is non-manifold (bow-tie):
// its corners joined across the edges at it with exactly two faces. Per
// vertex, on its own few corners (a union-find over every corner was 4 bytes
// a corner beside the mesher's triangulation at its peak).
template <class F> void mark_bowties(const F& fs, const CornerIndex& x, std::vector<char>& bad_vertex) {
  std::vector<std::uint32_t> next_of, prev_of, root;  // per corner at v: its face's neighbours of v; union-find
  for (std::size_t v = 0; v < fs.nv; ++v) {
    const std::uint32_t b = x.start[v], d = x.start[v + 1] - b;
    if (d < 2) continue;
    next_of.resize(d);
    prev_of.resize(d);
    root.resize(d);
    for (std::uint32_t k = 0; k < d; ++k) {
      next_of[k] = std::uint32_t(fs.corner(fs.next(x.at[b + k])));
      prev_of[k] = std::uint32_t(fs.corner(fs.prev(x.at[b + k])));
      root[k] = k;
    }
    auto find = [&](std::uint32_t k) {
      while (root[k] != k) k = root[k] = root[root[k]];
      return k;
    };
    for (std::uint32_t k = 0; k < d; ++k)
      for (const std::uint32_t u : {next_of[k], prev_of[k]}) {
        // The faces at edge {v, u}: the corners of v beside u.
        std::uint32_t faces = 0, other = k;
        for (std::uint32_t m = 0; m < d; ++m)
          if (next_of[m] == u || prev_of[m] == u) {
            ++faces;
            if (m != k) other = m;
          }
        if (faces == 2) {
          const std::uint32_t p = find(k), q = find(other);
          root[std::max(p, q)] = std::min(p, q);
        }
      }
    for (std::uint32_t k = 1; k < d; ++k)
      if (find(k) != find(0)) bad_vertex[v] = 1;
  }
}

// The components, keyed by the root vertex of the edge walk's union-find.
struct Components {
  std::vector<long long> id;  // per root vertex, else -1
  std::vector<ComponentTopology> list;
  ComponentTopology& of(EdgeWalk& w, std::size_t v) { return list[std::size_t(id[w.vertices.find(v)])]; }
};

// Each component's vertices (first one, non-manifold ones) and boundary loops
// (one root of the boundary union-find each); the isolated vertices.
Components components_by_vertex(EdgeWalk& w, MeshTopology& t) {
  const std::size_t nv = w.used.size();
  Components c{std::vector<long long>(nv, -1), {}};
  for (std::size_t v = 0; v < nv; ++v) {
    if (!w.used[v]) { ++t.isolated_vertices; continue; }
    const std::size_t r = w.vertices.find(v);
    if (c.id[r] < 0) {
      c.id[r] = (long long)c.list.size();
      c.list.emplace_back();
      c.list.back().manifold = true;
      c.list.back().first_vertex = v;
    }
    auto& k = c.list[std::size_t(c.id[r])];
    ++k.vertices;
    if (w.bad_vertex[v]) { k.manifold = false; ++t.nonmanifold_vertices; }
    if (w.on_boundary[v] && w.boundary.find(v) == v) ++k.boundary_loops;
  }
  return c;
}

// Each component's faces, edges and flags; then its Euler characteristic and
// genus.
template <class F> void complete_components(const F& fs, EdgeWalk& w, Components& c) {
  for (std::size_t f = 0; f < fs.nf; ++f) ++c.of(w, std::size_t(fs.corner(fs.offset(f)))).faces;
  for (auto& k : c.list) { k.oriented = true; k.orientable = true; k.closed = true; }
  for (std::size_t v = 0; v < fs.nv; ++v) {
    if (!w.edges_at[v]) continue;
    auto& k = c.of(w, v);
    k.edges += w.edges_at[v];
    if (w.edge_flags[v] & EdgeWalk::kOpen) k.closed = false;
    if (w.edge_flags[v] & EdgeWalk::kMisoriented) k.oriented = false;
  }
  for (std::size_t f : w.nonorientable_faces) c.of(w, std::size_t(fs.corner(fs.offset(f)))).orientable = false;
  for (auto& k : c.list) {
    k.euler = (long long)k.vertices - (long long)k.edges + (long long)k.faces;
    if (!k.manifold) k.oriented = k.orientable = false;
    if (k.manifold) {
      const long long x = 2 - k.euler - (long long)k.boundary_loops;
      k.genus = k.orientable ? (x % 2 == 0 && x >= 0 ? x / 2 : -1) : x;
    }
  }
}

// The components largest first (component_of follows the new order), and the
// mesh's totals.
void order_components(EdgeWalk& w, Components& c, MeshTopology& t) {
  std::vector<std::size_t> order(c.list.size());
  std::iota(order.begin(), order.end(), std::size_t(0));
  std::stable_sort(order.begin(), order.end(),
                   [&](std::size_t a, std::size_t b) { return c.list[a].faces > c.list[b].faces; });
  std::vector<int> rank(c.list.size());
  for (std::size_t i = 0; i < order.size(); ++i) {
    rank[order[i]] = int(i);
    t.components.push_back(c.list[order[i]]);
  }
  const std::size_t nv = w.used.size();
  t.component_of.assign(nv, -1);
  for (std::size_t v = 0; v < nv; ++v)
    if (w.used[v]) t.component_of[v] = rank[std::size_t(c.id[w.vertices.find(v)])];
  t.closed = t.manifold = t.oriented = !t.components.empty();
  for (const auto& k : t.components) {
    t.euler += k.euler;
    t.boundary_loops += k.boundary_loops;
    t.closed = t.closed && k.closed;
    t.manifold = t.manifold && k.manifold;
    t.oriented = t.oriented && k.oriented;
  }
}

// The topology of the faces (see Faces).
template <class Corner, class Offset, class FaceOf>
MeshTopology topology_of(std::size_t nv, std::size_t nf, Corner corner, Offset offset, FaceOf face_of) {
  const Faces<Corner, Offset, FaceOf> fs{nv, nf, corner, offset, face_of};
  check_faces(fs);
  const CornerIndex x = index_corners(fs);
  MeshTopology t;
  EdgeWalk w(nv, nf);
  walk_edges(fs, x, w, t);
  mark_bowties(fs, x, w.bad_vertex);
  Components c = components_by_vertex(w, t);
  complete_components(fs, w, c);
  order_components(w, c, t);
  return t;
}

} // namespace

MeshTopology mesh_topology(std::size_t nv, const std::vector<int>& corners,
                           const std::vector<std::size_t>& offsets) {
  if (offsets.empty()) throw Error("no face offsets");
  for (std::size_t f = 0; f + 1 < offsets.size(); ++f)
    if (offsets[f + 1] < offsets[f] + 3 || offsets[f + 1] > corners.size()) throw Error("face " + std::to_string(f) + " has fewer than 3 corners");
  // Faces of one size k (the voxel boundary's quads): the face of a corner
  // by division, not a binary search (topology_of asks it per corner met).
  const std::size_t nf = offsets.size() - 1, k = nf ? offsets[1] - offsets[0] : 0;
  bool uniform = offsets[0] == 0;
  for (std::size_t f = 0; f < nf && uniform; ++f) uniform = offsets[f + 1] == k * (f + 1);
  return topology_of(
      nv, nf, [&](std::size_t i) { return corners[i]; }, [&](std::size_t f) { return offsets[f]; },
      [&](std::size_t i) {
        return uniform ? i / k : std::size_t(std::upper_bound(offsets.begin(), offsets.end(), i) - offsets.begin()) - 1;
      });
}

MeshTopology mesh_topology(std::size_t nv, const std::vector<std::vector<int>>& faces) {
  std::vector<int> corners;
  std::vector<std::size_t> offsets{0};
  for (const auto& f : faces) {
    corners.insert(corners.end(), f.begin(), f.end());
    offsets.push_back(corners.size());
  }
  return mesh_topology(nv, corners, offsets);
}

MeshTopology mesh_topology(std::size_t nv, const std::vector<std::array<int, 3>>& triangles) {
  return topology_of(
      nv, triangles.size(), [&](std::size_t i) { return triangles[i / 3][i % 3]; }, [](std::size_t f) { return 3 * f; },
      [](std::size_t i) { return i / 3; });
}

namespace {

MeshTopology pixel_boundary_topology(const BinaryImage& img) {
  // Lattice points (x, y) of pixel corners; boundary edges between a
  // foreground pixel and a background/outside one.
  const std::size_t nx = img.size[0], ny = img.size[1];
  const std::size_t W = nx + 1;
  std::vector<std::uint64_t> verts;
  std::vector<std::pair<std::uint64_t, std::uint64_t>> edges;
  auto fg = [&](std::ptrdiff_t x, std::ptrdiff_t y) { return img.at(x, y, 0, 0) != 0; };
  for (std::size_t y = 0; y < ny; ++y)
    for (std::size_t x = 0; x < nx; ++x) {
      if (!img(x, y, 0)) continue;
      const std::ptrdiff_t X = std::ptrdiff_t(x), Y = std::ptrdiff_t(y);
      auto id = [&](std::size_t i, std::size_t j) { return std::uint64_t(j) * W + i; };
      if (!fg(X - 1, Y)) edges.push_back({id(x, y), id(x, y + 1)});
      if (!fg(X + 1, Y)) edges.push_back({id(x + 1, y), id(x + 1, y + 1)});
      if (!fg(X, Y - 1)) edges.push_back({id(x, y), id(x + 1, y)});
      if (!fg(X, Y + 1)) edges.push_back({id(x, y + 1), id(x + 1, y + 1)});
    }
  for (const auto& e : edges) { verts.push_back(e.first); verts.push_back(e.second); }
  std::sort(verts.begin(), verts.end());
  std::vector<std::size_t> degree;
  std::vector<std::uint64_t> uniq;
  for (std::size_t i = 0; i < verts.size();) {
    std::size_t j = i;
    while (j < verts.size() && verts[j] == verts[i]) ++j;
    uniq.push_back(verts[i]);
    degree.push_back(j - i);
    i = j;
  }
  auto idx = [&](std::uint64_t v) { return std::size_t(std::lower_bound(uniq.begin(), uniq.end(), v) - uniq.begin()); };
  UnionFind uf(uniq.size());
  for (const auto& e : edges) uf.unite(idx(e.first), idx(e.second));
  MeshTopology t;
  std::vector<long long> cid(uniq.size(), -1);
  for (std::size_t v = 0; v < uniq.size(); ++v) {
    const std::size_t r = uf.find(v);
    if (cid[r] < 0) {
      cid[r] = (long long)t.components.size();
      t.components.emplace_back();
      t.components.back().manifold = t.components.back().closed = true;
      t.components.back().oriented = t.components.back().orientable = true;
      t.components.back().first_vertex = v;
    }
    auto& c = t.components[cid[r]];
    ++c.vertices;
    if (degree[v] != 2) { c.manifold = false; ++t.nonmanifold_vertices; }
  }
  for (const auto& e : edges) ++t.components[cid[uf.find(idx(e.first))]].edges;
  t.manifold = t.closed = t.oriented = true;
  for (auto& c : t.components) {
    c.euler = (long long)c.vertices - (long long)c.edges;
    c.genus = c.manifold ? 0 : -1;
    t.euler += c.euler;
    t.manifold = t.manifold && c.manifold;
  }
  std::stable_sort(t.components.begin(), t.components.end(),
                   [](const ComponentTopology& a, const ComponentTopology& b) { return a.edges > b.edges; });
  return t;
}

// bdCA(X) for X = {in(x, y, z)} on a grid of the given size (in is false
// outside it), X within the box [lo, hi].
template <class In>
VoxelBoundary voxel_boundary_of(const std::array<std::size_t, 3>& size, const std::array<std::size_t, 3>& lo,
                                const std::array<std::size_t, 3>& hi, In in) {
  const std::size_t nx = size[0], ny = size[1];
  VoxelBoundary vb;
  vb.lattice = {nx + 1, ny + 1, size[2] + 1};
  const std::uint64_t W = nx + 1, H = ny + 1;
  auto id = [&](std::size_t i, std::size_t j, std::size_t k) { return (std::uint64_t(k) * H + j) * W + i; };
  // Outward-oriented unit squares, each kept as its lowest corner and its
  // side (8 bytes a quad); the corners they touch a bit each on the lattice
  // of X's box, numbered by rank among them: ascending ids without sorting
  // four a quad, in a quarter byte a corner of the box (the callers hold a
  // byte a voxel of it or more).
  const std::uint64_t BW = hi[0] - lo[0] + 2, BH = hi[1] - lo[1] + 2, BS = BW * BH;
  auto local = [&](std::size_t i, std::size_t j, std::size_t k) {
    return (std::uint64_t(k - lo[2]) * BH + (j - lo[1])) * BW + (i - lo[0]);
  };
  RankedBits touched(BS * (hi[2] - lo[2] + 2));
  // Per side 2 axis + plus, a quad's other corners from its lowest,
  // counter-clockwise seen from outside ((e_u x e_v) points outward).
  const std::uint64_t step[6][3] = {{BS, BW + BS, BW}, {BW, BW + BS, BS}, {1, 1 + BS, BS},
                                    {BS, 1 + BS, 1},   {BW, 1 + BW, 1},   {1, 1 + BW, BW}};
  std::vector<std::uint64_t> quads;  // per quad: its lowest corner (local) * 8 + side
  for (std::size_t z = lo[2]; z <= hi[2]; ++z)
    for (std::size_t y = lo[1]; y <= hi[1]; ++y)
      for (std::size_t x = lo[0]; x <= hi[0]; ++x) {
        const std::ptrdiff_t X = std::ptrdiff_t(x), Y = std::ptrdiff_t(y), Z = std::ptrdiff_t(z);
        if (!in(X, Y, Z)) continue;
        auto quad = [&](int side, std::uint64_t q) {
          quads.push_back(q * 8 + std::uint64_t(side));
          touched.set(q);
          for (std::uint64_t d : step[side]) touched.set(q + d);
        };
        if (!in(X + 1, Y, Z)) quad(1, local(x + 1, y, z));
        if (!in(X - 1, Y, Z)) quad(0, local(x, y, z));
        if (!in(X, Y + 1, Z)) quad(3, local(x, y + 1, z));
        if (!in(X, Y - 1, Z)) quad(2, local(x, y, z));
        if (!in(X, Y, Z + 1)) quad(5, local(x, y, z + 1));
        if (!in(X, Y, Z - 1)) quad(4, local(x, y, z));
      }
  touched.rank();
  touched.list(vb.lattice_ids);
  for (std::uint64_t& c : vb.lattice_ids)  // box lattice -> grid lattice (the same order: z, y, x)
    c = id(lo[0] + c % BW, lo[1] + c / BW % BH, lo[2] + c / BS);
  vb.corners.resize(4 * quads.size());
  vb.faces.assign(vb.lattice_ids.size(), 0);
  for (std::size_t f = 0; f < quads.size(); ++f) {
    const std::uint64_t q = quads[f] / 8;
    const int side = int(quads[f] % 8), axis = side / 2;
    const int v = int(touched(q));
    vb.corners[4 * f] = v;
    for (std::size_t i = 0; i < 3; ++i) vb.corners[4 * f + i + 1] = int(touched(q + step[side][i]));
    vb.faces[std::size_t(v)] |= std::uint8_t((VoxelBoundary::kNormalAxis | (side % 2 ? VoxelBoundary::kPlus : 0)) << axis);
  }
  vb.offsets.resize(vb.corners.size() / 4 + 1);
  for (std::size_t f = 0; f < vb.offsets.size(); ++f) vb.offsets[f] = 4 * f;
  return vb;
}

} // namespace

std::array<std::size_t, 3> VoxelBoundary::corner(std::size_t v) const {
  const std::uint64_t id = lattice_ids[v];
  return {std::size_t(id % lattice[0]), std::size_t(id / lattice[0] % lattice[1]),
          std::size_t(id / lattice[0] / lattice[1])};
}

VoxelBoundary voxel_boundary(const BinaryImage& img) {
  if (img.count() == 0) return voxel_boundary_of(img.size, {1, 1, 1}, {0, 0, 0}, [](auto...) { return false; });
  return voxel_boundary_of(img.size, {0, 0, 0}, {img.size[0] - 1, img.size[1] - 1, img.size[2] - 1},
                           [&](std::ptrdiff_t x, std::ptrdiff_t y, std::ptrdiff_t z) { return img.at(x, y, z, 0) != 0; });
}

// Only the box of samples given can be inside (beyond it g reads +T).
VoxelBoundary voxel_boundary(const SampleGrid& g) {
  for (int a = 0; a < 3; ++a)
    if (g.box_hi()[a] < g.box_lo()[a]) return voxel_boundary_of(g.size, {1, 1, 1}, {0, 0, 0}, [](auto...) { return false; });
  std::array<std::size_t, 3> lo, hi, n;
  for (int a = 0; a < 3; ++a) {
    lo[a] = std::size_t(g.box_lo()[a]);
    hi[a] = std::size_t(g.box_hi()[a]);
    n[a] = hi[a] - lo[a] + 1;
  }
  if (g.dense())
    return voxel_boundary_of(g.size, lo, hi, [&](std::ptrdiff_t x, std::ptrdiff_t y, std::ptrdiff_t z) {
      return g.inside(x, y, z) && g.dense_data()[g.index(std::size_t(x), std::size_t(y), std::size_t(z))] < 0;
    });
  // Blocks: the signs of the box first, a byte a voxel (read 7 times each).
  std::vector<std::uint8_t> in(n[0] * n[1] * n[2]);
  for (std::size_t k = 0; k < n[2]; ++k)
    for (std::size_t j = 0; j < n[1]; ++j)
      for (std::size_t i = 0; i < n[0]; ++i) in[i + n[0] * (j + n[1] * k)] = g(lo[0] + i, lo[1] + j, lo[2] + k) < 0;
  return voxel_boundary_of(g.size, lo, hi, [&](std::ptrdiff_t x, std::ptrdiff_t y, std::ptrdiff_t z) {
    const std::ptrdiff_t i = x - std::ptrdiff_t(lo[0]), j = y - std::ptrdiff_t(lo[1]), k = z - std::ptrdiff_t(lo[2]);
    if (i < 0 || j < 0 || k < 0 || std::size_t(i) >= n[0] || std::size_t(j) >= n[1] || std::size_t(k) >= n[2]) return false;
    return in[std::size_t(i) + n[0] * (std::size_t(j) + n[1] * std::size_t(k))] != 0;
  });
}

MeshTopology mesh_topology(const VoxelBoundary& b) {
  return mesh_topology(b.lattice_ids.size(), b.corners, b.offsets);
}

MeshTopology voxel_boundary_topology(const BinaryImage& img) {
  bool any = false;
  for (auto v : img.data) if (v) { any = true; break; }
  if (!any) throw Error("the image has no foreground");
  if (img.dimension == 2 || img.size[2] == 1) return pixel_boundary_topology(img);
  return mesh_topology(voxel_boundary(img));
}

bool same_topology(const MeshTopology& a, const MeshTopology& b) { return a.sorted_euler() == b.sorted_euler(); }

MeshTopology mesh_topology(const SurfaceMesh& mesh) { return mesh_topology(mesh.points.size(), mesh.triangles); }

MeshTopology voxel_boundary_topology(const SampleGrid& g) { return mesh_topology(voxel_boundary(g)); }

} // namespace imgmesh
