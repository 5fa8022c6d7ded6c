// K(X) in 2D (interface_complex.hpp): the 3D scans one dimension down. A
// corner's 2x2 block, bit k the pixel corner - (1, 1) + (k & 1, k >> 1); its
// four pixel edges in cyclic order (0|1, 1|3, 3|2, 2|0), each a face known by
// its lowest corner and normal axis.
#include "wellcomposed/interface_complex.hpp"

#include "wellcomposed/interface_complex_detail.hpp"

#include <algorithm>
#include <array>
#include <map>
#include <utility>

namespace imgmesh::wellcomposed_detail {
namespace {

struct PlanarFace {
  int axis, owner, other, dx, dy;  // the lowest corner is the corner + (dx, dy)
};
constexpr PlanarFace kFaces[4] = {{0, 1, 0, 0, -1}, {1, 3, 1, 0, 0}, {0, 3, 2, 0, 0}, {1, 2, 0, -1, 0}};

struct PlanarCorner {
  std::size_t x = 0, y = 0;
  std::uint64_t id = 0;
  std::array<std::int32_t, 4> label{};
  std::array<std::uint32_t, 4> face{};
  std::uint8_t own = 0;  // bits per axis
  bool uniform = false;
};

template <class Visit> void scan_corners_2d(const LabelImage& img, const std::array<std::size_t, 3>& lat, Visit&& visit) {
  std::vector<std::uint32_t> base[2] = {std::vector<std::uint32_t>(lat[0]), std::vector<std::uint32_t>(lat[0])};
  std::vector<std::uint8_t> mask[2] = {std::vector<std::uint8_t>(lat[0]), std::vector<std::uint8_t>(lat[0])};
  std::uint32_t next = 0;
  PlanarCorner k;
  for (std::size_t y = 0; y < lat[1]; ++y)
    for (std::size_t x = 0; x < lat[0]; ++x, ++k.id) {
      k.x = x, k.y = y;
      for (int w = 0; w < 4; ++w)
        k.label[std::size_t(w)] = img.at(std::ptrdiff_t(x) - 1 + (w & 1), std::ptrdiff_t(y) - 1 + (w >> 1), 0, 0);
      k.uniform = std::all_of(k.label.begin(), k.label.end(), [&](std::int32_t l) { return l == k.label[0]; });
      k.own = std::uint8_t((k.label[3] != k.label[2] ? 1 : 0) | (k.label[3] != k.label[1] ? 2 : 0));
      base[y & 1][x] = next, mask[y & 1][x] = k.own;
      next += std::uint32_t(__builtin_popcount(k.own));
      for (std::size_t s = 0; s < 4; ++s) {
        const PlanarFace& f = kFaces[s];
        k.face[s] = kNone;
        if (k.label[std::size_t(f.owner)] == k.label[std::size_t(f.other)]) continue;
        const std::size_t fx = x + std::size_t(f.dx), fy = y + std::size_t(f.dy);
        const std::uint8_t m = mask[fy & 1][fx];
        k.face[s] = base[fy & 1][fx] + std::uint32_t(f.axis == 1 && (m & 1));
      }
      visit(k);
    }
}

std::pair<std::int32_t, std::int32_t> face_pair(const PlanarCorner& k, std::size_t s) {
  const std::int32_t a = k.label[std::size_t(kFaces[s].owner)], b = k.label[std::size_t(kFaces[s].other)];
  return {std::max(a, b), std::min(a, b)};
}

struct PlanarJoins {
  GrowingUnionFind faces;
  SideJoins sides;
  std::map<std::int32_t, CriticalCounts> critical;
};

// Faces of one pair at a corner joined; sides of one label joined across
// pairs; the diagonal C1 counted.
void join_at_corner(const PlanarCorner& k, PlanarJoins& j) {
  for (std::size_t i = 0; i < 4; ++i)
    for (std::size_t m = i + 1; m < 4; ++m) {
      if (k.face[i] == kNone || k.face[m] == kNone) continue;
      const auto pi = face_pair(k, i), pm = face_pair(k, m);
      if (pi == pm) {
        j.faces.unite(k.face[i], k.face[m]);
        continue;
      }
      for (std::int32_t l : {pi.first, pi.second})
        if (l == pm.first || l == pm.second)
          j.sides.emplace_back(std::uint64_t(k.face[i]) << 1 | (l == pi.first ? 0u : 1u),
                               std::uint64_t(k.face[m]) << 1 | (l == pm.first ? 0u : 1u));
    }
  const auto& v = k.label;
  if (v[0] == v[3] && v[1] != v[0] && v[2] != v[0]) ++j.critical[v[0]].c1;
  if (v[1] == v[2] && v[0] != v[1] && v[3] != v[1]) ++j.critical[v[1]].c1;
}

// Scan 2: V of patches and components; a patch's ends (one edge at a
// corner) and pinches (four: a C1).
void count_corners(const PlanarCorner& k, InterfaceComplex& out, const std::vector<std::uint32_t>& side_comp,
                   std::vector<InterfaceComplex::Component>& components) {
  SmallSet<std::uint32_t, 4> patches;
  SmallSet<std::uint32_t, 8> comps;
  std::array<int, 4> edges{0, 0, 0, 0};
  for (std::size_t s = 0; s < 4; ++s) {
    if (k.face[s] == kNone) continue;
    const std::uint32_t p = out.face_patch[k.face[s]];
    if (patches.insert(p)) ++out.patches[p].vertices;
    for (std::size_t t = 0; t < patches.n; ++t) edges[t] += patches.v[t] == p;
    for (std::uint32_t side = 0; side < 2; ++side)
      if (comps.insert(side_comp[2 * p + side])) ++components[side_comp[2 * p + side]].vertices;
  }
  for (std::size_t t = 0; t < patches.n; ++t) {
    if (edges[t] == 1) ++out.patches[patches.v[t]].boundary_edges;
    if (edges[t] > 2) ++out.patches[patches.v[t]].pinched_vertices;
    if (edges[t] > 2 && (out.pinches.empty() || out.pinches.back() != k.id)) out.pinches.push_back(k.id);
  }
}

} // namespace

InterfaceComplex interface_complex_2d(const LabelImage& img) {
  InterfaceComplex out;
  out.dimension = 2;
  out.lattice = {img.size[0] + 1, img.size[1] + 1, 1};
  PlanarJoins j;
  scan_corners_2d(img, out.lattice, [&](const PlanarCorner& k) {
    if (k.uniform) return;
    for (int n = 0; n < 2; ++n)
      if ((k.own >> n) & 1) {
        const bool plus = k.label[std::size_t(3 ^ (1 << n))] > k.label[3];
        out.faces.push_back(InterfaceComplex::face_key(k.id, n, plus));
        j.faces.add();
      }
    join_at_corner(k, j);
    SmallSet<std::int32_t, 4> labels;
    for (std::int32_t l : k.label) labels.insert(l);
    if (labels.n >= 3) out.junctions.push_back(k.id);
  });
  make_patches(img, out, j.faces);
  std::vector<InterfaceComplex::Component> components;
  const auto side_comp = side_components(out, j.sides, components);
  scan_corners_2d(img, out.lattice, [&](const PlanarCorner& k) {
    if (!k.uniform) count_corners(k, out, side_comp, components);
  });
  for (auto& p : out.patches) p.euler = (long long)p.vertices - (long long)p.faces;
  for (auto& c : components) c.euler = (long long)c.vertices - (long long)c.faces;
  fill_labels(out, side_comp, components);
  for (const auto& c : j.critical) {
    for (auto& l : out.labels)
      if (l.label == c.first) l.critical = c.second;
    out.critical.c1 += c.second.c1;
  }
  return out;
}

} // namespace imgmesh::wellcomposed_detail
