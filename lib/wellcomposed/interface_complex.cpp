// K(X) in 3D: two scans of the corners' 2x2x2 blocks (interface_complex.hpp).
// Block bit k is the voxel corner - (1, 1, 1) + (k & 1, (k >> 1) & 1,
// (k >> 2) & 1), as critical_configuration.hpp's codes.
#include "wellcomposed/interface_complex.hpp"

#include "wellcomposed/critical_configuration.hpp"
#include "wellcomposed/interface_complex_detail.hpp"

#include <algorithm>
#include <array>
#include <map>
#include <utility>

namespace imgmesh {
namespace {

using wellcomposed_detail::GrowingUnionFind;
using wellcomposed_detail::kNone;
using wellcomposed_detail::SmallSet;

// The 12 faces at a corner: slot = n * 4 + q, n the normal axis; between the
// block's voxels `owner` (bit n set) and owner ^ (1 << n); the face's lowest
// corner is this corner + delta (delta[n] = 0, the others 0 or -1).
struct LocalFace {
  int axis = 0, owner = 0, other = 0;
  std::array<int, 3> delta{0, 0, 0};
};
// The 6 edges at a corner: e = a * 2 + dir, along axis a, outgoing (dir 1: to
// corner + e_a) or incoming (dir 0: from corner - e_a). Its voxels (bit a =
// dir) in cyclic order, and face k between voxels k and k + 1 (a slot).
struct LocalEdge {
  int axis = 0, dir = 0;
  std::array<int, 4> voxel{}, face{};
};
struct Local {
  std::array<LocalFace, 12> face;
  std::array<LocalEdge, 6> edge;
  static int slot(int n, int w) { return n * 4 + ((w >> ((n + 1) % 3)) & 1) + 2 * ((w >> ((n + 2) % 3)) & 1); }
  Local() {
    for (int n = 0; n < 3; ++n)
      for (int q = 0; q < 4; ++q) {
        const int w = (1 << n) | ((q & 1) << ((n + 1) % 3)) | ((q >> 1) << ((n + 2) % 3));
        LocalFace& f = face[slot(n, w)];
        f.axis = n, f.owner = w, f.other = w ^ (1 << n);
        for (int i = 0; i < 3; ++i) f.delta[i] = ((w >> i) & 1) - 1;
      }
    for (int a = 0; a < 3; ++a)
      for (int dir = 0; dir < 2; ++dir) {
        const int b = (a + 1) % 3, c = (a + 2) % 3;
        LocalEdge& e = edge[a * 2 + dir];
        e.axis = a, e.dir = dir;
        const int v0 = dir << a, v1 = v0 | 1 << b, v2 = v1 | 1 << c, v3 = v0 | 1 << c;
        e.voxel = {v0, v1, v2, v3};
        e.face = {slot(b, v1), slot(c, v2), slot(b, v2), slot(c, v3)};
      }
  }
};
const Local& local() {
  static const Local l;
  return l;
}

// Ids of the cells (faces or curve edges) whose lowest corners lie on the
// current lattice plane and the one before: per corner, the first id and a
// bit per axis.
class PlaneIds {
public:
  explicit PlaneIds(std::size_t plane) : base_{std::vector<std::uint32_t>(plane), std::vector<std::uint32_t>(plane)},
                                         mask_{std::vector<std::uint8_t>(plane), std::vector<std::uint8_t>(plane)} {}
  void set(std::size_t in_plane, std::size_t z, std::uint32_t base, std::uint8_t mask) {
    base_[z & 1][in_plane] = base, mask_[z & 1][in_plane] = mask;
  }
  std::uint32_t id(std::size_t in_plane, std::size_t z, int axis) const {
    const std::uint8_t m = mask_[z & 1][in_plane];
    if (!((m >> axis) & 1)) return kNone;
    return base_[z & 1][in_plane] + std::uint32_t(__builtin_popcount(m & ((1u << axis) - 1)));
  }

private:
  std::vector<std::uint32_t> base_[2];
  std::vector<std::uint8_t> mask_[2];
};

// What a scan step sees: a corner, its block, the ids of its 12 faces and of
// its 6 edges when they are curve edges (kNone when absent).
struct Corner {
  std::array<std::size_t, 3> c{0, 0, 0};
  std::uint64_t id = 0;
  std::array<std::int32_t, 8> label{};
  std::array<std::uint32_t, 12> face{};
  std::array<std::uint32_t, 6> curve{};
  bool uniform = false;  // one label: no face, no edge
  std::uint8_t own_faces = 0, own_curves = 0;  // bits per axis: those at this corner
};

// Three or four labels among an edge's voxels.
int edge_labels(const Corner& k, const LocalEdge& e, std::array<std::int32_t, 4>& out) {
  int n = 0;
  for (int v : e.voxel) {
    const std::int32_t l = k.label[std::size_t(v)];
    if (std::find(out.begin(), out.begin() + n, l) == out.begin() + n) out[std::size_t(n++)] = l;
  }
  std::sort(out.begin(), out.begin() + n);
  return n;
}

// The 2x2x2 block of labels around corner k.c (0 beyond the grid).
void load_block(const LabelImage& img, Corner& k) {
  const std::size_t x = k.c[0], y = k.c[1], z = k.c[2];
  if (x == 0 || y == 0 || z == 0 || x >= img.size[0] || y >= img.size[1] || z >= img.size[2]) {
    for (int w = 0; w < 8; ++w)
      k.label[std::size_t(w)] = img.at(std::ptrdiff_t(x) - 1 + (w & 1), std::ptrdiff_t(y) - 1 + ((w >> 1) & 1),
                                       std::ptrdiff_t(z) - 1 + ((w >> 2) & 1), 0);
    return;
  }
  const std::int32_t* p = img.data.data() + img.index(x - 1, y - 1, z - 1);
  const std::size_t sy = img.size[0], sz = img.size[0] * img.size[1];
  k.label = {p[0], p[1], p[sy], p[sy + 1], p[sz], p[sz + 1], p[sz + sy], p[sz + sy + 1]};
}

// Visits every corner in id order (x fastest), numbering faces and curve
// edges at their lowest corners.
template <class Visit> void scan_corners(const LabelImage& img, const std::array<std::size_t, 3>& lat, Visit&& visit) {
  const Local& loc = local();
  const std::size_t plane = lat[0] * lat[1];
  PlaneIds faces(plane), curves(plane);
  std::uint32_t next_face = 0, next_curve = 0;
  Corner k;
  for (std::size_t z = 0; z < lat[2]; ++z)
    for (std::size_t y = 0; y < lat[1]; ++y)
      for (std::size_t x = 0; x < lat[0]; ++x, ++k.id) {
        k.c = {x, y, z};
        load_block(img, k);
        const std::size_t here = x + lat[0] * y;
        k.uniform = std::all_of(k.label.begin(), k.label.end(), [&](std::int32_t l) { return l == k.label[0]; });
        k.own_faces = k.own_curves = 0;
        if (!k.uniform) {
          for (int n = 0; n < 3; ++n)
            if (k.label[7] != k.label[std::size_t(7 ^ (1 << n))]) k.own_faces |= std::uint8_t(1 << n);
          for (int a = 0; a < 3; ++a) {
            std::array<std::int32_t, 4> l;
            if (edge_labels(k, loc.edge[std::size_t(a * 2 + 1)], l) >= 3) k.own_curves |= std::uint8_t(1 << a);
          }
        }
        faces.set(here, z, next_face, k.own_faces);
        curves.set(here, z, next_curve, k.own_curves);
        next_face += std::uint32_t(__builtin_popcount(k.own_faces));
        next_curve += std::uint32_t(__builtin_popcount(k.own_curves));
        if (!k.uniform) {
          for (std::size_t s = 0; s < 12; ++s) {
            const LocalFace& f = loc.face[s];
            k.face[s] = kNone;
            if (k.label[std::size_t(f.owner)] == k.label[std::size_t(f.other)]) continue;
            const std::size_t fx = x + std::size_t(f.delta[0]), fy = y + std::size_t(f.delta[1]);
            k.face[s] = faces.id(fx + lat[0] * fy, z + std::size_t(f.delta[2]), f.axis);
          }
          for (int a = 0; a < 3; ++a) {
            k.curve[std::size_t(a * 2 + 1)] = curves.id(here, z, a);
            std::size_t p[3] = {x, y, z};
            k.curve[std::size_t(a * 2)] = p[a] == 0 ? kNone : (--p[a], curves.id(p[0] + lat[0] * p[1], p[2], a));
          }
        }
        visit(k);
      }
}

// Scan 1's products besides the keys.
struct Joins {
  GrowingUnionFind faces, curves;
  // Sides (face << 1 | s, s = 0 the higher label's) to join for bdCA(L).
  wellcomposed_detail::SideJoins sides;
  std::vector<std::pair<std::uint32_t, std::uint64_t>> ends;  // (curve edge, junction corner)
  std::map<std::int32_t, CriticalCounts> critical;
};

std::uint64_t side_of(const Corner& k, std::uint32_t face, int slot, std::int32_t l) {
  const LocalFace& f = local().face[std::size_t(slot)];
  const std::int32_t hi = std::max(k.label[std::size_t(f.owner)], k.label[std::size_t(f.other)]);
  return std::uint64_t(face) << 1 | (l == hi ? 0u : 1u);
}

// An outgoing edge: faces of one pair joined (patches), sides of one label
// joined (bdCA(L)), C1s counted.
void join_at_edge(const Corner& k, const LocalEdge& e, Joins& j) {
  for (int i = 0; i < 4; ++i)
    for (int m = i + 1; m < 4; ++m) {
      const std::uint32_t fi = k.face[std::size_t(e.face[std::size_t(i)])],
                          fm = k.face[std::size_t(e.face[std::size_t(m)])];
      if (fi == kNone || fm == kNone) continue;
      auto pair = [&](int t) {
        const LocalFace& f = local().face[std::size_t(e.face[std::size_t(t)])];
        const std::int32_t a = k.label[std::size_t(f.owner)], b = k.label[std::size_t(f.other)];
        return std::make_pair(std::min(a, b), std::max(a, b));
      };
      const auto pi = pair(i), pm = pair(m);
      if (pi == pm) {
        j.faces.unite(fi, fm);  // one patch: their sides are the patch's
        continue;
      }
      // A label on both faces: their sides of it are one surface there.
      for (std::int32_t l : {pi.first, pi.second})
        if (l == pm.first || l == pm.second)
          j.sides.emplace_back(side_of(k, fi, e.face[std::size_t(i)], l), side_of(k, fm, e.face[std::size_t(m)], l));
    }
  std::array<std::int32_t, 4> v;
  for (int i = 0; i < 4; ++i) v[std::size_t(i)] = k.label[std::size_t(e.voxel[std::size_t(i)])];
  for (int i = 0; i < 2; ++i)
    if (v[std::size_t(i)] == v[std::size_t(i + 2)] && v[std::size_t(i + 1)] != v[std::size_t(i)] &&
        v[std::size_t((i + 3) % 4)] != v[std::size_t(i)])
      ++j.critical[v[std::size_t(i)]].c1;
}

// Curve edges at a corner joined unless it is a junction.
void join_curves(const Corner& k, std::vector<std::uint64_t>& junctions, Joins& j) {
  std::uint32_t ids[6];
  std::array<std::int32_t, 4> sets[6];
  int counts[6], n = 0;
  for (int e = 0; e < 6; ++e)
    if (k.curve[std::size_t(e)] != kNone) {
      ids[n] = k.curve[std::size_t(e)];
      counts[n] = edge_labels(k, local().edge[std::size_t(e)], sets[n]);
      ++n;
    }
  if (n == 0) return;
  const bool straight = n == 2 && counts[0] == counts[1] && std::equal(sets[0].begin(), sets[0].begin() + counts[0], sets[1].begin());
  if (straight) return j.curves.unite(ids[0], ids[1]);
  junctions.push_back(k.id);
  for (int i = 0; i < n; ++i) j.ends.emplace_back(ids[i], k.id);
}

void count_c2(const Corner& k, Joins& j) {
  SmallSet<std::int32_t, 8> seen;
  for (std::int32_t l : k.label)
    if (seen.insert(l)) {
      unsigned code = 0;
      for (int w = 0; w < 8; ++w) code |= unsigned(k.label[std::size_t(w)] == l) << w;
      if (wellcomposed_detail::critical_configurations(std::uint8_t(code)) & wellcomposed_detail::kC2)
        ++j.critical[l].c2;
    }
}

// Scan 1: keys, and the joins of patches, curves and sides.
Joins first_scan(const LabelImage& img, InterfaceComplex& out) {
  Joins j;
  scan_corners(img, out.lattice, [&](const Corner& k) {
    if (k.uniform) return;
    for (int n = 0; n < 3; ++n)
      if ((k.own_faces >> n) & 1) {
        const bool plus = k.label[std::size_t(7 ^ (1 << n))] > k.label[7];
        out.faces.push_back(InterfaceComplex::face_key(k.id, n, plus));
        j.faces.add();
      }
    for (int a = 0; a < 3; ++a)
      if ((k.own_curves >> a) & 1) {
        out.curve_edges.push_back(k.id * 3 + std::uint64_t(a));
        j.curves.add();
      }
    for (int a = 0; a < 3; ++a) join_at_edge(k, local().edge[std::size_t(a * 2 + 1)], j);
    join_curves(k, out.junctions, j);
    count_c2(k, j);
  });
  return j;
}

// Curves from the curve edges' union-find; their label sets and ends.
void make_curves(const LabelImage& img, InterfaceComplex& out, Joins& j) {
  const std::uint32_t n = j.curves.number_sets();
  out.curve_edge_curve = std::move(j.curves.p);
  out.curves.resize(n);
  std::vector<int> ends(n, 0);
  for (const auto& e : j.ends) {
    const std::uint32_t c = out.curve_edge_curve[e.first];
    if (ends[c] < 2) out.curves[c].ends[std::size_t(ends[c])] = e.second;
    ++ends[c];
  }
  std::vector<bool> seen(n, false);
  for (std::size_t e = 0; e < out.curve_edges.size(); ++e) {
    InterfaceComplex::Curve& c = out.curves[out.curve_edge_curve[e]];
    ++c.edges;
    if (seen[out.curve_edge_curve[e]]) continue;
    seen[out.curve_edge_curve[e]] = true;
    c.first_edge = e;
    const auto k = out.corner(out.curve_edges[e] / 3);
    const int a = int(out.curve_edges[e] % 3), b = (a + 1) % 3, d = (a + 2) % 3;
    for (int q = 0; q < 4; ++q) {
      std::ptrdiff_t p[3] = {std::ptrdiff_t(k[0]), std::ptrdiff_t(k[1]), std::ptrdiff_t(k[2])};
      p[b] -= q & 1, p[d] -= q >> 1;
      const std::int32_t l = img.at(p[0], p[1], p[2], 0);
      if (std::find(c.labels.begin(), c.labels.begin() + c.label_count, l) == c.labels.begin() + c.label_count)
        c.labels[std::size_t(c.label_count++)] = l;
    }
    std::sort(c.labels.begin(), c.labels.begin() + c.label_count);
  }
  for (std::uint32_t c = 0; c < n; ++c) {
    out.curves[c].closed = ends[c] == 0;
    if (out.curves[c].ends[0] > out.curves[c].ends[1]) std::swap(out.curves[c].ends[0], out.curves[c].ends[1]);
  }
}

// Scan 2 at one corner: V and E of patches and components, fans, boundary
// edges joined into loops.
struct Counting {
  InterfaceComplex& out;
  const std::vector<std::uint32_t>& side_comp;
  std::vector<InterfaceComplex::Component>& components;
  GrowingUnionFind loops;                 // per curve edge, 4 face positions
  std::vector<std::uint32_t> loop_patch;  // the patch of each position used

  std::uint32_t patch(const Corner& k, int slot) const { return out.face_patch[k.face[std::size_t(slot)]]; }
  std::uint32_t comp(const Corner& k, int slot, int s) const {
    return side_comp[2 * patch(k, slot) + std::uint32_t(s)];
  }

  void count_cells(const Corner& k) {
    SmallSet<std::uint32_t, 12> patches;
    SmallSet<std::uint32_t, 24> comps;
    for (int s = 0; s < 12; ++s)
      if (k.face[std::size_t(s)] != kNone) {
        if (patches.insert(patch(k, s))) ++out.patches[patch(k, s)].vertices;
        for (int side = 0; side < 2; ++side)
          if (comps.insert(comp(k, s, side))) ++components[comp(k, s, side)].vertices;
      }
    for (int a = 0; a < 3; ++a) {
      const LocalEdge& e = local().edge[std::size_t(a * 2 + 1)];
      SmallSet<std::uint32_t, 4> ep;
      SmallSet<std::uint32_t, 8> ec;
      for (int f : e.face)
        if (k.face[std::size_t(f)] != kNone) {
          if (ep.insert(patch(k, f))) ++out.patches[patch(k, f)].edges;
          for (int side = 0; side < 2; ++side)
            if (ec.insert(comp(k, f, side))) ++components[comp(k, f, side)].edges;
        }
    }
  }

  // Faces of a patch at this corner joined through its edges here: more than
  // one fan is a pinch. Its boundary edges here joined into one loop.
  void count_fans_and_loops(const Corner& k) {
    std::array<int, 12> fan;
    for (int s = 0; s < 12; ++s) fan[std::size_t(s)] = s;
    auto root = [&](int s) { while (fan[std::size_t(s)] != s) s = fan[std::size_t(s)]; return s; };
    SmallSet<std::uint32_t, 12> pinched;
    std::array<std::pair<std::uint32_t, std::uint32_t>, 24> bd;  // (patch, loop position)
    std::size_t nb = 0;
    for (int e = 0; e < 6; ++e) {
      const LocalEdge& le = local().edge[std::size_t(e)];
      for (int i = 0; i < 4; ++i) {
        const int fi = le.face[std::size_t(i)];
        if (k.face[std::size_t(fi)] == kNone) continue;
        int same = 0;
        for (int m = 0; m < 4; ++m) {
          const int fm = le.face[std::size_t(m)];
          if (m == i || k.face[std::size_t(fm)] == kNone || patch(k, fm) != patch(k, fi)) continue;
          ++same;
          fan[std::size_t(root(fi))] = root(fm);
        }
        if (same == 0 && k.curve[std::size_t(e)] != kNone) {
          const std::uint32_t pos = k.curve[std::size_t(e)] * 4 + std::uint32_t(i);
          bd[nb++] = {patch(k, fi), pos};
          loop_patch[pos] = patch(k, fi);
          if (le.dir == 1) ++out.patches[patch(k, fi)].boundary_edges;
        }
      }
    }
    SmallSet<std::pair<std::uint32_t, int>, 12> fans;
    for (int s = 0; s < 12; ++s)
      if (k.face[std::size_t(s)] != kNone && fans.insert({patch(k, s), root(s)})) {
        for (std::size_t t = 0; t + 1 < fans.n; ++t)
          if (fans.v[t].first == patch(k, s)) pinched.insert(patch(k, s));
      }
    for (std::size_t i = 0; i < nb; ++i)
      for (std::size_t m = i + 1; m < nb; ++m)
        if (bd[m].first == bd[i].first) loops.unite(bd[i].second, bd[m].second);
    for (std::size_t i = 0; i < pinched.n; ++i) ++out.patches[pinched.v[i]].pinched_vertices;
    if (pinched.n) out.pinches.push_back(k.id);
  }
};

void second_scan(const LabelImage& img, InterfaceComplex& out, const std::vector<std::uint32_t>& side_comp,
                 std::vector<InterfaceComplex::Component>& components) {
  Counting c{out, side_comp, components, {}, std::vector<std::uint32_t>(4 * out.curve_edges.size(), kNone)};
  for (std::size_t i = 0; i < 4 * out.curve_edges.size(); ++i) c.loops.add();
  scan_corners(img, out.lattice, [&](const Corner& k) {
    if (k.uniform) return;
    c.count_cells(k);
    c.count_fans_and_loops(k);
  });
  // Loops numbered in the order of their first curve edges.
  out.curve_edge_loop.assign(c.loop_patch.size(), kNone);
  for (std::uint32_t pos = 0; pos < c.loop_patch.size(); ++pos) {
    if (c.loop_patch[pos] == kNone) continue;
    const std::uint32_t root = c.loops.find(pos);
    if (root == pos) {
      out.loops.push_back({c.loop_patch[pos], 0, pos / 4});
      ++out.patches[c.loop_patch[pos]].boundary_loops;
    }
    // A root is its set's first position: numbered already.
    out.curve_edge_loop[pos] = root == pos ? std::uint32_t(out.loops.size() - 1) : out.curve_edge_loop[root];
    ++out.loops[out.curve_edge_loop[pos]].edges;
  }
  for (auto& p : out.patches) p.euler = (long long)(p.vertices) - (long long)(p.edges) + (long long)(p.faces);
  for (auto& m : components) m.euler = (long long)(m.vertices) - (long long)(m.edges) + (long long)(m.faces);
}

} // namespace

namespace wellcomposed_detail {

// The two labels of a face, (higher, lower), from the image.
static std::pair<std::int32_t, std::int32_t> face_labels(const LabelImage& img, const InterfaceComplex& out,
                                                         std::uint64_t key) {
  const auto c = out.corner(InterfaceComplex::face_corner(key));
  const int n = InterfaceComplex::face_axis(key);
  std::ptrdiff_t p[3] = {std::ptrdiff_t(c[0]), std::ptrdiff_t(c[1]), std::ptrdiff_t(c[2])};
  const std::int32_t a = img.at(p[0], p[1], p[2], 0);
  --p[n];
  const std::int32_t b = img.at(p[0], p[1], p[2], 0);
  return {std::max(a, b), std::min(a, b)};
}

// Patches from the faces' union-find (face_patch), their pairs.
void make_patches(const LabelImage& img, InterfaceComplex& out, GrowingUnionFind& faces) {
  const std::uint32_t n = faces.number_sets();
  out.face_patch = std::move(faces.p);
  out.patches.resize(n);
  std::vector<bool> seen(n, false);
  for (std::size_t f = 0; f < out.faces.size(); ++f) {
    InterfaceComplex::Patch& p = out.patches[out.face_patch[f]];
    ++p.faces;
    if (seen[out.face_patch[f]]) continue;
    seen[out.face_patch[f]] = true;
    p.first_face = f;
    std::tie(p.behind, p.front) = face_labels(img, out, out.faces[f]);
  }
}

// bdCA(L)'s components: the sides of patches (2p: the higher label's, 2p + 1
// the lower's) joined where scan 1 saw one label on two faces.
std::vector<std::uint32_t> side_components(const InterfaceComplex& out, const SideJoins& joins,
                                           std::vector<InterfaceComplex::Component>& components) {
  GrowingUnionFind u;
  for (std::size_t s = 0; s < 2 * out.patches.size(); ++s) u.add();
  auto side = [&](std::uint64_t fs) { return 2 * out.face_patch[fs >> 1] + std::uint32_t(fs & 1); };
  for (const auto& s : joins) u.unite(side(s.first), side(s.second));
  // Sides in the order of their patches' first faces, so components are too.
  std::vector<std::uint32_t> comp(u.p.size());
  std::vector<std::uint32_t> root_comp(u.p.size(), kNone);
  for (std::size_t s = 0; s < u.p.size(); ++s) {
    const std::uint32_t r = u.find(std::uint32_t(s));
    if (root_comp[r] == kNone) {
      root_comp[r] = std::uint32_t(components.size());
      components.emplace_back();
      components.back().first_face = out.patches[s / 2].first_face;
    }
    comp[s] = root_comp[r];
    components[comp[s]].faces += out.patches[s / 2].faces;
  }
  return comp;
}

void fill_labels(InterfaceComplex& k, const std::vector<std::uint32_t>& side_comp,
                 const std::vector<InterfaceComplex::Component>& components) {
  std::vector<std::int32_t> ls{0};
  for (const auto& p : k.patches) ls.push_back(p.behind), ls.push_back(p.front);
  std::sort(ls.begin(), ls.end());
  ls.erase(std::unique(ls.begin(), ls.end()), ls.end());
  k.labels.resize(ls.size());
  for (std::size_t i = 0; i < ls.size(); ++i) k.labels[i].label = ls[i];
  std::vector<std::int32_t> comp_label(components.size(), 0);
  for (std::size_t s = 0; s < side_comp.size(); ++s)
    comp_label[side_comp[s]] = s % 2 ? k.patches[s / 2].front : k.patches[s / 2].behind;
  for (std::size_t c = 0; c < components.size(); ++c) {
    auto& l = k.labels[std::size_t(std::lower_bound(ls.begin(), ls.end(), comp_label[c]) - ls.begin())];
    l.components.push_back(components[c]);
    l.faces += components[c].faces;
  }
}

InterfaceComplex interface_complex_3d(const LabelImage& img) {
  InterfaceComplex out;
  out.dimension = 3;
  for (int i = 0; i < 3; ++i) out.lattice[std::size_t(i)] = img.size[std::size_t(i)] + 1;
  Joins j = first_scan(img, out);
  make_patches(img, out, j.faces);
  make_curves(img, out, j);
  std::vector<InterfaceComplex::Component> components;
  const auto side_comp = side_components(out, j.sides, components);
  second_scan(img, out, side_comp, components);
  fill_labels(out, side_comp, components);
  for (const auto& c : j.critical) {
    for (auto& l : out.labels)
      if (l.label == c.first) l.critical = c.second;
    out.critical.c1 += c.second.c1, out.critical.c2 += c.second.c2;
  }
  return out;
}
} // namespace wellcomposed_detail

InterfaceComplex interface_complex(const LabelImage& img) {
  return img.dimension == 2 ? wellcomposed_detail::interface_complex_2d(img)
                            : wellcomposed_detail::interface_complex_3d(img);
}

std::array<std::size_t, 3> InterfaceComplex::corner(std::uint64_t id) const {
  return {std::size_t(id % lattice[0]), std::size_t(id / lattice[0] % lattice[1]),
          std::size_t(id / lattice[0] / lattice[1])};
}

std::size_t InterfaceComplex::find_face(std::uint64_t corner, int axis) const {
  const auto it = std::lower_bound(faces.begin(), faces.end(), face_key(corner, axis, false));
  return it != faces.end() && (*it >> 1) == (face_key(corner, axis, false) >> 1) ? std::size_t(it - faces.begin())
                                                                                 : faces.size();
}

const InterfaceComplex::LabelBoundary* InterfaceComplex::find_label(std::int32_t label) const {
  for (const auto& l : labels)
    if (l.label == label) return &l;
  return nullptr;
}

std::size_t InterfaceComplex::closed_curves() const {
  return std::size_t(std::count_if(curves.begin(), curves.end(), [](const Curve& c) { return c.closed; }));
}

std::size_t InterfaceComplex::pinched_vertices() const {
  std::size_t n = 0;
  for (const auto& p : patches) n += p.pinched_vertices;
  return n;
}

std::string InterfaceComplex::summary() const {
  return "interface complex: " + std::to_string(patches.size()) + " patches, " + std::to_string(curves.size()) +
         " curves, " + std::to_string(junctions.size()) + " junctions";
}

Json InterfaceComplex::to_json() const {
  Json j = Json::object();
  j["dimension"] = dimension;
  j["labels"] = labels.size();
  j["faces"] = faces.size();
  j["patches"] = patches.size();
  j["boundary_loops"] = loops.size();
  j["curve_edges"] = curve_edges.size();
  j["curves"] = curves.size();
  j["closed_curves"] = closed_curves();
  j["junctions"] = junctions.size();
  j["c1"] = critical.c1;
  j["c2"] = critical.c2;
  j["pinched_vertices"] = pinched_vertices();
  j["pinches"] = pinches.size();
  return j;
}

std::string InterfaceComplex::failed_guarantee() const {
  if (!critical.total()) return "";
  return "the label image is not well-composed (" + std::to_string(critical.total()) +
         " critical configurations over its labels)";
}

} // namespace imgmesh
