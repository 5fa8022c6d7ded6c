// The interfaces check of the multi-label certificate
// (interface_certificate.hpp): per label pair, the mesh's patches (its
// triangles of the pair joined along edges, each counted by mesh_topology)
// placed on K(X)'s patches of the pair by the votes of their triangles.
//
// Placing a triangle: the faces of K(X) near its centroid are found by
// their lowest corners in K(X)'s sorted face keys (a row of corners a
// lookup), and the distance to a face, a unit square of the lattice, is
// separable: clamp each index coordinate to the square, scale by the
// spacing (the direction matrix is orthonormal). First within a small
// radius (the nearest face there is the nearest of all), then within the
// tolerance.
#include "surfacenets/interface_certificate_detail.hpp"

#include "mesh/topology.hpp"
#include "util/error.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numeric>
#include <string>

namespace imgmesh::surfacenets_detail {
namespace {

using Cert = InterfaceCertificate;
using Pair = std::array<std::int32_t, 2>;  // (higher, lower), as K(X)'s patches
// A triangle's or vertex's id: 4 bytes (certify_interface_mesh takes no
// more than 2^32 triangles), the interfaces' lists at half the size.
using Id = std::uint32_t;

Pair pair_key(const Pair& p) { return {std::max(p[0], p[1]), std::min(p[0], p[1])}; }

class FaceSearch {
public:
  FaceSearch(const Geometry& grid, const InterfaceComplex& k)
      : grid_(grid), k_(k), row_begin_(k.lattice[1] * k.lattice[2] + 1, k.faces.size()) {
    // K(X)'s faces are sorted by lowest corner, z slowest: each lattice row
    // (y, z) a run of them, found without a search.
    for (std::size_t f = k.faces.size(); f-- > 0;)
      row_begin_[InterfaceComplex::face_corner(k.faces[f]) / k.lattice[0]] = f;
    for (std::size_t r = row_begin_.size() - 1; r-- > 0;) row_begin_[r] = std::min(row_begin_[r], row_begin_[r + 1]);
  }

  // The K(X) patch of the face of `pair` nearest to p (world) within r
  // (world), -1 when none; an exact tie goes to the lower face.
  long long nearest(const Vec3& p, const Pair& pair, double r) const {
    const Vec3 ci = grid_.continuous_index(p);
    double l[3];
    std::size_t lo[3], hi[3];
    for (int a = 0; a < 3; ++a) {
      l[a] = ci[std::size_t(a)] + 0.5;  // corner c sits at voxel index c - 1/2
      const double ra = r / grid_.spacing[std::size_t(a)], n = double(k_.lattice[std::size_t(a)]);
      if (!std::isfinite(l[a]) || !(l[a] + ra >= 0) || !(l[a] - ra - 1 <= n)) return -1;
      lo[a] = std::size_t(std::max(0.0, std::ceil(l[a] - ra) - 1));
      hi[a] = std::size_t(std::min(n - 1, std::floor(l[a] + ra)));
      if (lo[a] > hi[a]) return -1;
    }
    double best = r * r;
    long long found = -1;
    const std::uint64_t nx = k_.lattice[0], ny = k_.lattice[1];
    for (std::size_t z = lo[2]; z <= hi[2]; ++z)
      for (std::size_t y = lo[1]; y <= hi[1]; ++y) {
        const std::uint64_t row = nx * (y + ny * z), end = InterfaceComplex::face_key(row + hi[0] + 1, 0, false);
        const auto row_end = k_.faces.begin() + std::ptrdiff_t(row_begin_[y + ny * z + 1]);
        auto it = std::lower_bound(k_.faces.begin() + std::ptrdiff_t(row_begin_[y + ny * z]), row_end,
                                   InterfaceComplex::face_key(row + lo[0], 0, false));
        for (; it != row_end && *it < end; ++it) {
          const std::size_t f = std::size_t(it - k_.faces.begin());
          const auto& patch = k_.patches[k_.face_patch[f]];
          if (patch.behind != pair[0] || patch.front != pair[1]) continue;
          const int axis = InterfaceComplex::face_axis(*it);
          const auto q = k_.corner(InterfaceComplex::face_corner(*it));
          double d2 = 0;
          for (int x = 0; x < 3; ++x) {
            const double from = double(q[std::size_t(x)]), to = x == axis ? from : from + 1;
            const double d = (l[x] - std::clamp(l[x], from, to)) * grid_.spacing[std::size_t(x)];
            d2 += d * d;
          }
          if (d2 < best || (found < 0 && d2 <= best)) best = d2, found = (long long)k_.face_patch[f];
        }
      }
    return found;
  }

private:
  const Geometry& grid_;
  const InterfaceComplex& k_;
  std::vector<std::size_t> row_begin_;  // per lattice row y + ny z: its first face (faces.size() past the last)
};

// The triangles ts (ascending ids) joined along edges: per triangle of ts
// its patch, numbered in the order of their first triangles.
std::vector<Id> edge_components(const std::vector<std::array<int, 3>>& triangles, const std::vector<Id>& ts,
                                std::size_t& count) {
  std::vector<std::array<Id, 3>> edges;  // (lo, hi, index in ts)
  edges.reserve(3 * ts.size());
  for (std::size_t i = 0; i < ts.size(); ++i)
    for (int e = 0; e < 3; ++e) {
      const int a = triangles[ts[i]][std::size_t(e)], b = triangles[ts[i]][std::size_t((e + 1) % 3)];
      edges.push_back({Id(std::min(a, b)), Id(std::max(a, b)), Id(i)});
    }
  std::sort(edges.begin(), edges.end());
  std::vector<Id> parent(ts.size());
  std::iota(parent.begin(), parent.end(), Id(0));
  auto find = [&](Id x) {
    while (parent[x] != x) x = parent[x] = parent[parent[x]];
    return x;
  };
  for (std::size_t i = 1; i < edges.size(); ++i)
    if (edges[i][0] == edges[i - 1][0] && edges[i][1] == edges[i - 1][1]) {
      const Id a = find(edges[i][2]), b = find(edges[i - 1][2]);
      parent[std::max(a, b)] = std::min(a, b);  // a root is its set's first triangle
    }
  std::vector<Id> id(ts.size()), of(ts.size());
  count = 0;
  for (Id i = 0; i < ts.size(); ++i) of[i] = find(i) == i ? (id[i] = Id(count++)) : id[find(i)];
  return of;
}

// The counts of one mesh patch (its triangles, vertices renumbered through
// `local`, left all -1 again).
void count_patch(const std::vector<std::array<int, 3>>& triangles, const std::vector<Id>& ts,
                 std::vector<int>& local, Cert::Patch& p) {
  std::vector<int> used;
  std::vector<std::array<int, 3>> tris(ts.size());
  for (std::size_t i = 0; i < ts.size(); ++i)
    for (int c = 0; c < 3; ++c) {
      int& v = local[std::size_t(triangles[ts[i]][std::size_t(c)])];
      if (v < 0) v = int(used.size()), used.push_back(triangles[ts[i]][std::size_t(c)]);
      tris[i][std::size_t(c)] = v;
    }
  for (int v : used) local[std::size_t(v)] = -1;
  const MeshTopology t = mesh_topology(used.size(), tris);
  const ComponentTopology& c = t.components.at(0);  // joined along edges: one component
  p.first_triangle = ts.front();
  p.triangles = ts.size();
  p.vertices = c.vertices;
  p.edges = c.edges;
  p.euler = c.euler;
  p.boundary_loops = c.boundary_loops;
  p.nonmanifold_edges = t.nonmanifold_edges;
  p.pinched_vertices = t.nonmanifold_vertices;
}

std::string number_text(double x) {
  char b[32];
  std::snprintf(b, sizeof b, "%.6g", x);
  return b;
}

// Each patch's verdict, beyond the correspondence's (unplaced, matched
// twice, euler differs); the interface's first failure.
void settle(Cert::Interface& in, const ComponentCorrespondence& r, const InterfaceComplex& k, double tolerance) {
  const std::string name = "interface " + in.name() + ": ";
  if (in.patches.size() != in.complex_patches.size())
    in.why = name + std::to_string(in.patches.size()) + " patch" + (in.patches.size() == 1 ? "" : "es") + ", K(X) has " +
             std::to_string(in.complex_patches.size());
  for (std::size_t m = 0; m < in.patches.size(); ++m) {
    Cert::Patch& p = in.patches[m];
    p.placed = r.mesh[m].placed;
    const int b = r.mesh[m].boundary;
    if (b >= 0) p.complex_patch = (long long)in.complex_patches[std::size_t(b)];
    const std::string of = name + "the patch of triangle " + std::to_string(p.first_triangle);
    const std::string its = b >= 0 ? ", its K(X) patch " + std::to_string(p.complex_patch) + " has " : "";
    const auto* kp = b >= 0 ? &k.patches[std::size_t(p.complex_patch)] : nullptr;
    std::string why;
    p.verdict = r.mesh[m].verdict;
    if (p.verdict == "unplaced") {
      why = of + " (" + std::to_string(p.triangles) + " triangles): none within " + number_text(tolerance) +
            " (the place tolerance) of a face of " + in.name();
    } else if (p.verdict == "matched twice") {
      why = name + "the patches of triangles";
      for (int o : r.boundary[std::size_t(b)].matched_by) why += " " + std::to_string(in.patches[std::size_t(o)].first_triangle);
      why += " lie on one K(X) patch, " + std::to_string(p.complex_patch);
    } else if (p.nonmanifold_edges) {
      p.verdict = "not a surface";
      why = of + " has " + std::to_string(p.nonmanifold_edges) + " edge(s) in three of its triangles or more";
    } else if (p.verdict == "euler differs") {
      why = of + " has Euler characteristic " + std::to_string(p.euler) + its + std::to_string(kp->euler);
    } else if (p.boundary_loops != kp->boundary_loops) {
      p.verdict = "loops differ";
      why = of + " has " + std::to_string(p.boundary_loops) + " boundary loop(s)" + its + std::to_string(kp->boundary_loops);
    } else if (p.pinched_vertices != kp->pinched_vertices) {
      p.verdict = "pinches differ";
      why = of + " has " + std::to_string(p.pinched_vertices) + " pinched vertex(es)" + its +
            std::to_string(kp->pinched_vertices);
    }
    if (in.why.empty()) in.why = why;
  }
}

// One interface: the mesh's triangles of the pair (ts, ascending) against
// K(X)'s patches of it.
// The triangles ts (ascending ids) of one pair as its mesh patches: per
// patch its triangles, in the order of their first triangles.
std::vector<std::vector<Id>> patch_members(const std::vector<std::array<int, 3>>& triangles, const std::vector<Id>& ts,
                                           std::vector<Id>& of) {
  std::size_t n = 0;
  of = edge_components(triangles, ts, n);
  std::vector<std::vector<Id>> members(n);
  for (std::size_t i = 0; i < ts.size(); ++i) members[of[i]].push_back(ts[i]);
  return members;
}

void certify_interface(Cert::Interface& in, const std::vector<Vec3>& points,
                       const std::vector<std::array<int, 3>>& triangles, const std::vector<Id>& ts,
                       const FaceSearch& search, const InterfaceComplex& k, double small, double tolerance,
                       std::vector<int>& local) {
  std::vector<Id> of;
  const std::vector<std::vector<Id>> members = patch_members(triangles, ts, of);
  const std::size_t n = members.size();
  in.patches.resize(n);
  ComponentCorrespondence r;
  r.mesh.resize(n);
  r.boundary.resize(in.complex_patches.size());
  for (std::size_t m = 0; m < n; ++m) {
    count_patch(triangles, members[m], local, in.patches[m]);
    r.mesh[m].euler = in.patches[m].euler;
  }
  for (std::size_t b = 0; b < in.complex_patches.size(); ++b) r.boundary[b].euler = k.patches[in.complex_patches[b]].euler;
  std::vector<std::pair<int, int>> votes;
  const Pair pair{in.behind, in.front};
  for (std::size_t i = 0; i < ts.size(); ++i) {
    Vec3 c{0, 0, 0};
    for (int v : triangles[ts[i]])
      for (int a = 0; a < 3; ++a) c[std::size_t(a)] += points[std::size_t(v)][std::size_t(a)] / 3;
    long long patch = search.nearest(c, pair, small);
    if (patch < 0 && small < tolerance) patch = search.nearest(c, pair, tolerance);
    if (patch < 0) continue;
    const auto at = std::lower_bound(in.complex_patches.begin(), in.complex_patches.end(), std::size_t(patch));
    votes.push_back({int(of[i]), int(at - in.complex_patches.begin())});
  }
  tally_votes(r, votes);
  settle(in, r, k, tolerance);
}

} // namespace

std::vector<std::vector<std::uint32_t>> interface_patch_triangles(const std::vector<std::array<int, 3>>& triangles,
                                                                  const std::vector<std::array<std::int32_t, 2>>& pairs,
                                                                  std::int32_t behind, std::int32_t front) {
  std::vector<Id> ts, of;
  for (std::size_t t = 0; t < triangles.size(); ++t)
    if (pair_key(pairs[t]) == Pair{behind, front}) ts.push_back(Id(t));
  return patch_members(triangles, ts, of);
}

std::vector<InterfaceCertificate::Interface> certify_interfaces(const std::vector<Vec3>& points,
                                                                const std::vector<std::array<int, 3>>& triangles,
                                                                const std::vector<std::array<std::int32_t, 2>>& pairs,
                                                                const Geometry& grid, const InterfaceComplex& k,
                                                                double tolerance, unsigned threads) {
  // (pair, id) of every triangle and of every K(X) patch, each by pair.
  std::vector<std::pair<Pair, Id>> mesh(triangles.size());
  std::vector<std::pair<Pair, std::size_t>> complex(k.patches.size());
  for (std::size_t t = 0; t < triangles.size(); ++t) mesh[t] = {pair_key(pairs[t]), Id(t)};
  for (std::size_t p = 0; p < k.patches.size(); ++p) complex[p] = {Pair{k.patches[p].behind, k.patches[p].front}, p};
  std::sort(mesh.begin(), mesh.end());
  std::sort(complex.begin(), complex.end());
  // Per pair, its runs in both: mesh[i0, i1), complex[j0, j1).
  struct Run {
    Pair pair;
    std::size_t i0, i1, j0, j1;
  };
  std::vector<Run> runs;
  for (std::size_t i = 0, j = 0; i < mesh.size() || j < complex.size();) {
    const Pair p = i == mesh.size() ? complex[j].first
                   : j == complex.size() ? mesh[i].first
                                         : std::min(mesh[i].first, complex[j].first);
    Run r{p, i, i, j, j};
    while (i < mesh.size() && mesh[i].first == p) ++i;
    while (j < complex.size() && complex[j].first == p) ++j;
    r.i1 = i;
    r.j1 = j;
    runs.push_back(r);
  }
  const FaceSearch search(grid, k);
  const double small = std::min(tolerance, 0.75 * std::min({grid.spacing[0], grid.spacing[1], grid.spacing[2]}));
  std::vector<Cert::Interface> out(runs.size());
  std::vector<std::vector<int>> local(std::max(1u, threads));  // per thread, -1 a vertex when idle
  for_each_index(runs.size(), threads, [&](std::size_t r, unsigned w) {
    const Run& run = runs[r];
    Cert::Interface& in = out[r];
    in.behind = run.pair[0];
    in.front = run.pair[1];
    std::vector<Id> ts;
    ts.reserve(run.i1 - run.i0);
    for (std::size_t i = run.i0; i < run.i1; ++i) {
      ts.push_back(mesh[i].second);
      in.reversed += pairs[mesh[i].second][0] < pairs[mesh[i].second][1];
    }
    for (std::size_t j = run.j0; j < run.j1; ++j) in.complex_patches.push_back(complex[j].second);
    in.triangles = ts.size();
    if (local[w].empty()) local[w].assign(points.size(), -1);
    certify_interface(in, points, triangles, ts, search, k, small, tolerance, local[w]);
  });
  return out;
}

} // namespace imgmesh::surfacenets_detail
