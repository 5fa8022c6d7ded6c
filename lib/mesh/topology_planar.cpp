// The topology certificate by correspondence for planar meshes against a 2D
// label image (the 2D half of the topology module; the 3D half and the
// shared result, ComponentCorrespondence, are in topology.cpp).
//
// Why regions and not curves: img2poly's output covers the image rectangle,
// and its curves are where two labels meet; matching each region of one
// label (faces joined by edges) to the pixel region it lies on, one to one,
// with the same Euler characteristic (1 - holes), fixes which curves bound
// it. A disk placed where an annulus is lies on the annulus's pixels
// (euler 1 against 0); a missing hole changes the Euler characteristic; a
// doubled or dropped region breaks the one-to-one match. Sorted Euler lists
// alone cannot see a swap.
//
// Placing by face centroids: a face's centroid is inside the face, and the
// face is inside the simplified region, within img2poly's tolerance E of the
// pixel region; so the nearest pixel centre of the face's label is less than
// E + 1 pixels away. A majority vote per mesh region absorbs the faces that
// a coarse simplification pushes across a thin part.
#include "mesh/topology.hpp"

#include "mesh/topology_detail.hpp"

#include "util/error.hpp"

#include <algorithm>
#include <cmath>

namespace imgmesh {

using mesh_detail::UnionFind;

namespace {

// Counts a cell once per distinct region among the (up to four) pixels
// around it: the closed squares of a region share its corners and edges.
void count_cell(std::vector<long long>& count, const int* around, int n, long long sign) {
  for (int i = 0; i < n; ++i) {
    if (around[i] < 0) continue;
    bool first = true;
    for (int k = 0; k < i; ++k) first = first && around[k] != around[i];
    if (first) count[std::size_t(around[i])] += sign;
  }
}

} // namespace

PixelRegions pixel_regions(const LabelImage& img) {
  if (img.dimension == 3 && img.size[2] != 1) throw Error("pixel regions need a 2D image");
  const std::size_t W = img.size[0], H = img.size[1];
  PixelRegions r;
  r.grid = img.geometry();
  UnionFind f(W * H);
  for (std::size_t y = 0; y < H; ++y)
    for (std::size_t x = 0; x < W; ++x) {
      const std::int32_t l = img(x, y);
      if (!l) continue;
      if (x + 1 < W && img(x + 1, y) == l) f.unite(x + W * y, x + 1 + W * y);
      if (y + 1 < H && img(x, y + 1) == l) f.unite(x + W * y, x + W * (y + 1));
    }
  r.region_of.assign(W * H, -1);
  for (std::size_t i = 0; i < W * H; ++i) {
    if (!img.data[i]) continue;
    const std::size_t root = f.find(i);
    if (root == i) {  // roots are the smallest index: regions in scan order
      r.region_of[i] = int(r.label.size());
      r.label.push_back(img.data[i]);
      r.pixels.push_back(0);
    } else {
      r.region_of[i] = r.region_of[root];
    }
    ++r.pixels[std::size_t(r.region_of[i])];
  }
  // V - E + F of each region's closed squares.
  r.euler.assign(r.label.size(), 0);
  auto reg = [&](std::ptrdiff_t x, std::ptrdiff_t y) {
    return x < 0 || y < 0 || x >= std::ptrdiff_t(W) || y >= std::ptrdiff_t(H) ? -1 : r.region_of[std::size_t(x) + W * std::size_t(y)];
  };
  for (std::ptrdiff_t j = 0; j <= std::ptrdiff_t(H); ++j)
    for (std::ptrdiff_t i = 0; i <= std::ptrdiff_t(W); ++i) {
      const int corner[4] = {reg(i - 1, j - 1), reg(i, j - 1), reg(i - 1, j), reg(i, j)};
      count_cell(r.euler, corner, 4, +1);
      const int horizontal[2] = {reg(i, j - 1), reg(i, j)};  // the edge from corner (i, j) to (i + 1, j)
      count_cell(r.euler, horizontal, 2, -1);
      const int vertical[2] = {reg(i - 1, j), reg(i, j)};    // from (i, j) to (i, j + 1)
      count_cell(r.euler, vertical, 2, -1);
    }
  for (std::size_t k = 0; k < r.label.size(); ++k) r.euler[k] += (long long)r.pixels[k];
  return r;
}

MeshRegions mesh_regions(std::size_t nv, const std::vector<std::vector<int>>& faces,
                         const std::vector<std::int32_t>& face_labels) {
  if (!face_labels.empty() && face_labels.size() != faces.size()) throw Error("mesh_regions: one label per face");
  auto label = [&](std::size_t f) { return face_labels.empty() ? 1 : face_labels[f]; };
  // Edges as (min, max, face), sorted: faces of one label across an edge join.
  struct Side { int a, b; std::size_t face; };
  std::vector<Side> sides;
  for (std::size_t f = 0; f < faces.size(); ++f) {
    const auto& c = faces[f];
    if (c.size() < 3) throw Error("face " + std::to_string(f) + " has fewer than 3 corners");
    for (std::size_t i = 0; i < c.size(); ++i) {
      const int a = c[i], b = c[(i + 1) % c.size()];
      if (a < 0 || b < 0 || std::size_t(a) >= nv || std::size_t(b) >= nv)
        throw Error("face " + std::to_string(f) + ": vertex id out of range");
      if (label(f)) sides.push_back({std::min(a, b), std::max(a, b), f});
    }
  }
  std::sort(sides.begin(), sides.end(), [](const Side& x, const Side& y) {
    return x.a != y.a ? x.a < y.a : x.b != y.b ? x.b < y.b : x.face < y.face;
  });
  UnionFind forest(faces.size());
  for (std::size_t i = 0; i < sides.size();) {
    std::size_t j = i;
    while (j < sides.size() && sides[j].a == sides[i].a && sides[j].b == sides[i].b) ++j;
    for (std::size_t k = i + 1; k < j; ++k)
      for (std::size_t m = i; m < k; ++m)
        if (label(sides[k].face) == label(sides[m].face)) forest.unite(sides[k].face, sides[m].face);
    i = j;
  }
  MeshRegions r;
  r.region_of.assign(faces.size(), -1);
  for (std::size_t f = 0; f < faces.size(); ++f) {
    if (!label(f)) continue;
    const std::size_t root = forest.find(f);
    if (root == f) {
      r.region_of[f] = int(r.label.size());
      r.label.push_back(label(f));
      r.faces.push_back(0);
    } else {
      r.region_of[f] = r.region_of[root];
    }
    ++r.faces[std::size_t(r.region_of[f])];
  }
  // V - E + F per region: distinct (region, vertex) and (region, edge) pairs.
  r.euler.assign(r.label.size(), 0);
  std::vector<std::pair<int, int>> vertices;
  for (std::size_t f = 0; f < faces.size(); ++f)
    if (r.region_of[f] >= 0)
      for (int v : faces[f]) vertices.push_back({r.region_of[f], v});
  std::sort(vertices.begin(), vertices.end());
  vertices.erase(std::unique(vertices.begin(), vertices.end()), vertices.end());
  for (const auto& v : vertices) ++r.euler[std::size_t(v.first)];
  std::vector<std::array<int, 3>> edges;
  for (const auto& s : sides) edges.push_back({r.region_of[s.face], s.a, s.b});
  std::sort(edges.begin(), edges.end());
  edges.erase(std::unique(edges.begin(), edges.end()), edges.end());
  for (const auto& e : edges) --r.euler[std::size_t(e[0])];
  for (std::size_t k = 0; k < r.label.size(); ++k) r.euler[k] += (long long)r.faces[k];
  return r;
}

ComponentCorrespondence match_regions(const MeshRegions& mesh, const std::vector<Vec3>& points,
                                      const std::vector<std::vector<int>>& faces, const PixelRegions& image,
                                      double reach) {
  if (mesh.region_of.size() != faces.size()) throw Error("match_regions: region labels do not fit the faces");
  if (!(reach > 0)) throw Error("match_regions: the reach must be positive");
  ComponentCorrespondence r;
  r.planar = true;
  r.mesh.resize(mesh.label.size());
  r.boundary.resize(image.label.size());
  for (std::size_t c = 0; c < r.mesh.size(); ++c) { r.mesh[c].euler = mesh.euler[c]; r.mesh[c].label = mesh.label[c]; }
  for (std::size_t c = 0; c < r.boundary.size(); ++c) {
    r.boundary[c].euler = image.euler[c];
    r.boundary[c].label = image.label[c];
  }
  const auto W = std::ptrdiff_t(image.grid.size[0]), H = std::ptrdiff_t(image.grid.size[1]);
  const auto R = std::ptrdiff_t(std::ceil(reach));
  // The pixel region a face lies on, -1 when no pixel of its label is in reach.
  auto place = [&](std::size_t f, std::int32_t label) {
    Vec3 c{0, 0, 0};
    for (int v : faces[f])
      for (int a = 0; a < 3; ++a) c[a] += points[std::size_t(v)][a] / double(faces[f].size());
    const Vec3 ci = image.grid.continuous_index(c);
    if (!(std::abs(ci[0]) < 1e9 && std::abs(ci[1]) < 1e9)) return -1;  // far off (or NaN)
    const auto x0 = std::ptrdiff_t(std::lround(ci[0])), y0 = std::ptrdiff_t(std::lround(ci[1]));
    int found = -1;
    double best = reach * reach;
    for (std::ptrdiff_t y = std::max<std::ptrdiff_t>(0, y0 - R); y <= std::min(H - 1, y0 + R); ++y)
      for (std::ptrdiff_t x = std::max<std::ptrdiff_t>(0, x0 - R); x <= std::min(W - 1, x0 + R); ++x) {
        const int k = image.region_of[std::size_t(x + W * y)];
        if (k < 0 || image.label[std::size_t(k)] != label) continue;
        const double d = (ci[0] - double(x)) * (ci[0] - double(x)) + (ci[1] - double(y)) * (ci[1] - double(y));
        if (d < best) { best = d; found = k; }
      }
    return found;
  };
  std::vector<std::pair<int, int>> votes;  // (mesh region, pixel region) per placed face
  for (std::size_t f = 0; f < faces.size(); ++f) {
    const int m = mesh.region_of[f];
    if (m < 0) continue;
    ++r.mesh[std::size_t(m)].vertices;
    const int k = place(f, mesh.label[std::size_t(m)]);
    if (k >= 0) votes.push_back({m, k});
  }
  tally_votes(r, votes);
  return r;
}

} // namespace imgmesh
