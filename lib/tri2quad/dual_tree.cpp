// The dual graph of the triangle mesh, its components cut at the constraint
// edges and the tree T^c they form (thesis 3.3), and the driver: T^c
// bottom-up, in each component a BFS spanning tree of the dual graph pruned
// bottom-up (levels V_d .. V_0, 3.2.1). No recursion: BFS orders are
// explicit arrays, so meshes of 10^7 triangles run in linear time and
// bounded stack.
#include "tri2quad/conversion.hpp"

#include "util/error.hpp"

#include <algorithm>
#include <cmath>

namespace imgmesh::tri2quad_detail {

// The input's checks and its mesh: counter-clockwise triangles, their
// neighbours, the constraint and boundary edges with their markers, and the
// input restriction of 3.3.
void Conversion::build_mesh() {
  orient_triangles();
  const VertexTriangles around = triangles_around_vertices();
  find_neighbours(around);
  mark_constraints(around);
  check_input_restriction();
  result.input_points = input.points.size();
  result.triangles = triangles.size();
}

// The input's triangles, counter-clockwise, with their regions; ids in
// range, coordinates finite, no triangle degenerate.
void Conversion::orient_triangles() {
  const std::size_t n = input.points.size();
  if (input.triangles.empty()) throw Error("the triangle mesh has no triangles", input.path);
  if (n > std::size_t(1) << 30 || input.triangles.size() > std::size_t(1) << 29)
    throw Error("mesh too large", input.path);
  points = input.points;
  for (const P2& p : points)
    if (!std::isfinite(p[0]) || !std::isfinite(p[1])) throw Error("non-finite coordinate", input.path);
  triangles.resize(input.triangles.size());
  has_regions = input.region.size() == input.triangles.size();
  attribute.assign(triangles.size(), 0.0);
  for (std::size_t t = 0; t < triangles.size(); ++t) {
    auto tr = input.triangles[t];
    for (int v : tr)
      if (v < 0 || std::size_t(v) >= n)
        throw Error("triangle " + std::to_string(t + input.index_base) + " has a vertex id out of range", input.path);
    const int o = orientation(points[tr[0]], points[tr[1]], points[tr[2]]);
    if (o == 0)
      throw Error("triangle " + std::to_string(t + input.index_base) + " (" + vid(tr[0]) + ", " + vid(tr[1]) +
                      ", " + vid(tr[2]) + ") is degenerate (zero area)",
                  input.path);
    if (o < 0) std::swap(tr[1], tr[2]);
    triangles[t] = tr;
    if (has_regions) attribute[t] = input.region[t];
  }
}

// Edge adjacency through the triangles around each vertex (CSR, 4 bytes
// a corner): less memory and time than sorting the 3t edges.
Conversion::VertexTriangles Conversion::triangles_around_vertices() const {
  const std::size_t n = input.points.size();
  VertexTriangles vt;
  std::vector<std::uint32_t>& start = vt.start;
  start.assign(n + 1, 0);
  vt.around.resize(3 * triangles.size());
  for (const auto& tr : triangles) for (int v : tr) ++start[v + 1];
  for (std::size_t v = 0; v < n; ++v) start[v + 1] += start[v];
  std::vector<std::uint32_t> pos(start.begin(), start.end() - 1);
  for (std::size_t t = 0; t < triangles.size(); ++t) for (int v : triangles[t]) vt.around[pos[v]++] = std::uint32_t(t);
  return vt;
}

// Slot of the edge (x, y) or (y, x) in triangle w, or -1.
int Conversion::slot_of(int w, int x, int y) const {
  for (int k = 0; k < 3; ++k) {
    const int p = triangles[w][k], q = triangles[w][(k + 1) % 3];
    if ((p == x && q == y) || (p == y && q == x)) return k;
  }
  return -1;
}

// The triangle across each edge; an edge in three triangles or with both
// triangles on one side is refused.
void Conversion::find_neighbours(const VertexTriangles& around) {
  neighbours.assign(triangles.size(), {-1, -1, -1});
  for (std::size_t t = 0; t < triangles.size(); ++t)
    for (int j = 0; j < 3; ++j) {
      const int a = triangles[t][j], b = triangles[t][(j + 1) % 3];
      int found = 0;
      for (std::uint32_t i = around.start[a]; i < around.start[a + 1]; ++i) {
        const int w = int(around.around[i]);
        if (std::size_t(w) == t) continue;
        const int k = slot_of(w, a, b);
        if (k < 0) continue;
        if (++found > 1)
          throw Error("edge " + edge_name(a, b) + " is shared by more than two triangles (not a 2-manifold)", input.path);
        if (triangles[w][k] == a)
          throw Error("triangles on both sides of edge " + edge_name(a, b) + " overlap (folded mesh)", input.path);
        neighbours[t][j] = w;
      }
    }
}

// The constraint segments (each an edge of the mesh) and every boundary
// edge: the constrained bits and the segments with their markers.
void Conversion::mark_constraints(const VertexTriangles& around) {
  const std::size_t n = input.points.size();
  constrained.assign(triangles.size(), 0);
  for (std::size_t k = 0; k < input.constraints.size(); ++k) {
    const auto s = input.constraints[k];
    const int marker = k < input.constraint_markers.size() ? input.constraint_markers[k] : 1;
    if (s[0] < 0 || s[1] < 0 || std::size_t(s[0]) >= n || std::size_t(s[1]) >= n)
      throw Error("constraint segment " + std::to_string(k + input.index_base) + " has a vertex id out of range", input.path);
    bool edge = false;
    for (std::uint32_t i = around.start[s[0]]; i < around.start[s[0] + 1]; ++i) {
      const int w = int(around.around[i]);
      const int j = slot_of(w, s[0], s[1]);
      if (j >= 0) { constrained[w] |= std::uint8_t(1u << j); edge = true; }
    }
    if (!edge)
      throw Error("constraint segment " + edge_name(s[0], s[1]) + " is not an edge of the triangle mesh", input.path);
    segments[edge_key(s[0], s[1])] = marker;
  }
  for (std::size_t t = 0; t < triangles.size(); ++t)
    for (int j = 0; j < 3; ++j)
      if (neighbours[t][j] < 0) {
        constrained[t] |= std::uint8_t(1u << j);
        segments.emplace(edge_key(triangles[t][j], triangles[t][(j + 1) % 3]), 1);
      }
}

// Input restriction (3.3): the constraint complex has no dangling end.
void Conversion::check_input_restriction() const {
  std::vector<std::uint8_t> deg(input.points.size(), 0);
  for (std::size_t t = 0; t < triangles.size(); ++t)
    for (int j = 0; j < 3; ++j)
      if ((constrained[t] >> j & 1) && (neighbours[t][j] < 0 || std::size_t(neighbours[t][j]) > t)) {
        for (int v : {triangles[t][j], triangles[t][(j + 1) % 3]}) deg[v] = std::uint8_t(std::min(deg[v] + 1, 3));
      }
  for (std::size_t t = 0; t < triangles.size(); ++t)
    for (int j = 0; j < 3; ++j)
      if (constrained[t] >> j & 1)
        for (int v : {triangles[t][(j + 1) % 3], triangles[t][j]})
          if (deg[v] == 1)
            throw Error("constraint edge " + edge_name(triangles[t][j], triangles[t][(j + 1) % 3]) +
                            " dangles at vertex " + vid(v) +
                            " (no other constraint or boundary edge ends there): the input restriction of "
                            "thesis 3.3 (Fig. 3.26) is not met",
                        input.path);
}

void Conversion::build_component_tree() {
  component.assign(triangles.size(), -1);
  std::vector<int> q;
  q.reserve(triangles.size());
  int h = 0;
  for (std::size_t s = 0; s < triangles.size(); ++s) {
    if (component[s] >= 0) continue;
    component[s] = h;
    component_seed.push_back(int(s));
    q.clear();
    q.push_back(int(s));
    for (std::size_t i = 0; i < q.size(); ++i) {
      const int t = q[i];
      for (int j = 0; j < 3; ++j) {
        const int u = neighbours[t][j];
        if (u >= 0 && !(constrained[t] >> j & 1) && component[u] < 0) { component[u] = h; q.push_back(u); }
      }
    }
    ++h;
  }
  for (std::size_t t = 0; t < triangles.size(); ++t)
    for (int j = 0; j < 3; ++j)
      if ((constrained[t] >> j & 1) && neighbours[t][j] >= 0 && component[neighbours[t][j]] == component[t])
        throw Error("constraint edge " + edge_name(triangles[t][j], triangles[t][(j + 1) % 3]) +
                        " has the same region on both sides (an open constraint curve): the input "
                        "restriction of thesis 3.3 (Fig. 3.26) is not met",
                    input.path);
  result.components = std::size_t(h);
  // Triangles of each component (CSR), then T^c by BFS from components
  // with a boundary edge.
  std::vector<int> start(h + 1, 0), list(triangles.size());
  for (int c : component) ++start[c + 1];
  for (int c = 0; c < h; ++c) start[c + 1] += start[c];
  {
    std::vector<int> pos(start.begin(), start.end() - 1);
    for (std::size_t t = 0; t < triangles.size(); ++t) list[pos[component[t]]++] = int(t);
  }
  component_parent.assign(h, -2);
  // With edges to avoid, roots of T^c go first to a boundary edge that
  // may take a point.
  auto free_boundary = [&](std::size_t t) {
    for (int j = 0; j < 3; ++j)
      if (neighbours[t][j] < 0 &&
          !(avoid_edges && avoid_edges->count(edge_key(triangles[t][j], triangles[t][(j + 1) % 3]))))
        return true;
    return false;
  };
  for (std::size_t i = 0; i < 2 * triangles.size(); ++i) {
    const std::size_t t = i % triangles.size();
    const bool boundary = i < triangles.size() ? free_boundary(t)
                                               : (neighbours[t][0] < 0 || neighbours[t][1] < 0 || neighbours[t][2] < 0);
    if (!boundary || component_parent[component[t]] != -2) continue;
    const std::size_t first = component_order.size();
    component_parent[component[t]] = -1;
    component_order.push_back(component[t]);
    for (std::size_t i = first; i < component_order.size(); ++i) {
      const int c = component_order[i];
      for (int k = start[c]; k < start[c + 1]; ++k) {
        const int u = list[k];
        for (int j = 0; j < 3; ++j) {
          const int w = neighbours[u][j];
          if (w >= 0 && component_parent[component[w]] == -2) {
            component_parent[component[w]] = c;
            component_order.push_back(component[w]);
          }
        }
      }
    }
  }
}

void Conversion::convert_components() {
  build_component_tree();
  parent.assign(triangles.size(), -1);
  parent_slot.assign(triangles.size(), 0);
  leftover.assign(triangles.size(), Leftover{});
  std::vector<int> order;
  for (auto ci = component_order.rbegin(); ci != component_order.rend(); ++ci) {
    const int C = *ci, PC = component_parent[C];
    // Collect the component (it may have grown by repairs), find the root.
    order.clear();
    order.push_back(component_seed[C]);
    parent[component_seed[C]] = -2;
    for (std::size_t i = 0; i < order.size(); ++i) {
      const int t = order[i];
      for (int j = 0; j < 3; ++j) {
        const int w = neighbours[t][j];
        if (w >= 0 && !(constrained[t] >> j & 1) && parent[w] == -1) { parent[w] = -2; order.push_back(w); }
      }
    }
    // The root edge: the first candidate, or the root_pick-th one (the
    // size-bound retry in tri2quad() tries other spanning trees).
    int root = -1, rslot = -1, seen_roots = 0;
    for (int strict = avoid_edges ? 1 : 0; strict >= 0 && root < 0; --strict)
      for (int t : order) {
        for (int j = 0; j < 3; ++j) {
          const int w = neighbours[t][j];
          if (strict && w < 0 && avoid_edges->count(edge_key(triangles[t][j], triangles[t][(j + 1) % 3]))) continue;
          if ((PC < 0 && w < 0) || (PC >= 0 && w >= 0 && (constrained[t] >> j & 1) && component[w] == PC)) {
            if (root < 0 || seen_roots <= root_pick) { root = t; rslot = j; }
            ++seen_roots;
          }
        }
        if (root >= 0 && seen_roots > root_pick) break;
      }
    if (root < 0) throw Error("internal error: component without a root edge", input.path);
    for (int t : order) parent[t] = -1;
    // BFS tree from the root over non-constraint dual edges.
    order.clear();
    order.push_back(root);
    parent[root] = -3;
    parent_slot[root] = std::int8_t(rslot);
    for (std::size_t i = 0; i < order.size(); ++i) {
      const int t = order[i];
      for (int j = 0; j < 3; ++j) {
        const int w = neighbours[t][j];
        if (w >= 0 && !(constrained[t] >> j & 1) && parent[w] == -1) {
          parent[w] = t;
          for (int k = 0; k < 3; ++k)
            if (neighbours[w][k] == t && triangles[w][k] == triangles[t][(j + 1) % 3]) parent_slot[w] = std::int8_t(k);
          order.push_back(w);
        }
      }
    }
    // Bottom-up: reverse BFS order visits the levels V_d, ..., V_0.
    for (std::size_t i = order.size(); i-- > 1;) process_node(order[i], false);
    process_node(root, true);
  }
}

} // namespace imgmesh::tri2quad_detail
