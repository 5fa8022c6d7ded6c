// The interface complex K(X) on partitions whose topology is worked out by
// hand (the numbers in the comments), and on random well-composed ones
// against a brute force written here from the definitions (maps of faces,
// edges and corners, no scan).
#include "wellcomposed/interface_complex.hpp"

#include "label_images.hpp"

#include <catch2/catch.hpp>

#include <algorithm>
#include <map>
#include <set>
#include <tuple>
#include <vector>

using namespace imgmesh;
using namespace imgmesh::test;
using Patch = InterfaceComplex::Patch;

namespace {

std::vector<const Patch*> patches_of(const InterfaceComplex& k, std::int32_t a, std::int32_t b) {
  std::vector<const Patch*> out;
  for (const auto& p : k.patches)
    if (p.behind == std::max(a, b) && p.front == std::min(a, b)) out.push_back(&p);
  return out;
}

const Patch& one_patch(const InterfaceComplex& k, std::int32_t a, std::int32_t b) {
  const auto p = patches_of(k, a, b);
  REQUIRE(p.size() == 1);
  return *p[0];
}

// (faces, euler) of a label's components, sorted.
std::vector<std::pair<std::size_t, long long>> label_components(const InterfaceComplex& k, std::int32_t l) {
  std::vector<std::pair<std::size_t, long long>> out;
  const auto* b = k.find_label(l);
  REQUIRE(b != nullptr);
  for (const auto& c : b->components) out.emplace_back(c.faces, c.euler);
  std::sort(out.begin(), out.end());
  return out;
}

// --- Brute force from the definitions (3D) ---

struct Map {
  std::map<std::int64_t, std::int64_t> p;
  std::int64_t find(std::int64_t x) {
    if (!p.count(x)) p[x] = x;
    while (p[x] != x) x = p[x];
    return x;
  }
  void unite(std::int64_t a, std::int64_t b) { p[find(a)] = find(b); }
};

struct Brute {
  std::array<std::int64_t, 3> lat;
  std::map<std::uint64_t, std::pair<std::int32_t, std::int32_t>> faces;  // key (with the plus bit) -> (hi, lo)
  std::map<std::int64_t, std::vector<std::uint64_t>> edge_faces;          // edge key -> faces
  std::set<std::int64_t> curve_edges;
  std::int64_t corner(std::int64_t x, std::int64_t y, std::int64_t z) const { return x + lat[0] * (y + lat[1] * z); }
};

Brute brute_force(const LabelImage& img) {
  Brute b;
  for (int i = 0; i < 3; ++i) b.lat[std::size_t(i)] = std::int64_t(img.size[std::size_t(i)]) + 1;
  auto L = [&](std::int64_t x, std::int64_t y, std::int64_t z) { return img.at(x, y, z, 0); };
  for (std::int64_t z = 0; z < b.lat[2]; ++z)
    for (std::int64_t y = 0; y < b.lat[1]; ++y)
      for (std::int64_t x = 0; x < b.lat[0]; ++x)
        for (int n = 0; n < 3; ++n) {
          std::int64_t q[3] = {x, y, z};
          const std::int32_t front_side = L(x, y, z);
          --q[n];
          const std::int32_t back_side = L(q[0], q[1], q[2]);
          if (front_side == back_side) continue;
          const std::uint64_t key = (std::uint64_t(b.corner(x, y, z)) * 3 + std::uint64_t(n)) << 1 |
                                    std::uint64_t(back_side > front_side);
          b.faces[key] = {std::max(front_side, back_side), std::min(front_side, back_side)};
          // Its four edges: along the two other axes, at the corner and one step on.
          for (int e = 1; e < 3; ++e) {
            const int a = (n + e) % 3, o = (n + 3 - e) % 3;
            for (int s = 0; s < 2; ++s) {
              std::int64_t c[3] = {x, y, z};
              c[o] += s;
              b.edge_faces[b.corner(c[0], c[1], c[2]) * 3 + a].push_back(key);
            }
          }
        }
  for (const auto& e : b.edge_faces) {
    const std::int64_t c = e.first / 3;
    const int a = int(e.first % 3);
    std::int64_t p[3] = {c % b.lat[0], c / b.lat[0] % b.lat[1], c / b.lat[0] / b.lat[1]};
    std::set<std::int32_t> ls;
    for (int q = 0; q < 4; ++q) {
      std::int64_t v[3] = {p[0], p[1], p[2]};
      v[(a + 1) % 3] -= q & 1, v[(a + 2) % 3] -= q >> 1;
      ls.insert(L(v[0], v[1], v[2]));
    }
    if (ls.size() >= 3) b.curve_edges.insert(e.first);
  }
  return b;
}

// Corners of an edge key.
std::array<std::int64_t, 2> edge_corners(const Brute& b, std::int64_t e) {
  const std::int64_t c = e / 3;
  const int a = int(e % 3);
  const std::int64_t step[3] = {1, b.lat[0], b.lat[0] * b.lat[1]};
  return {c, c + step[a]};
}

// Every number of K(X) recomputed from the brute force; the properties of a
// well-composed partition's complex checked too when it is one.
void check_against_brute_force(const LabelImage& img, const InterfaceComplex& k) {
  const Brute b = brute_force(img);
  const bool wc = k.critical.total() == 0;
  // Faces, orientation included.
  REQUIRE(k.faces.size() == b.faces.size());
  std::size_t i = 0;
  for (const auto& f : b.faces) REQUIRE(k.faces[i++] == f.first);
  auto fid = [&](std::uint64_t key) { return std::size_t(std::lower_bound(k.faces.begin(), k.faces.end(), key) - k.faces.begin()); };
  // Patches: faces of one pair joined at edges.
  Map pu;
  for (const auto& e : b.edge_faces)
    for (auto f : e.second)
      for (auto g : e.second)
        if (b.faces.at(f) == b.faces.at(g)) pu.unite(std::int64_t(f), std::int64_t(g));
  std::map<std::int64_t, std::uint32_t> root_patch;
  for (const auto& f : b.faces) {
    const std::uint32_t p = k.face_patch[fid(f.first)];
    auto it = root_patch.emplace(pu.find(std::int64_t(f.first)), p).first;
    REQUIRE(it->second == p);  // one brute patch, one patch of K
    REQUIRE(k.patches[p].behind == f.second.first);
    REQUIRE(k.patches[p].front == f.second.second);
  }
  REQUIRE(root_patch.size() == k.patches.size());
  // V, E, boundary edges (on curves), loops per patch.
  std::vector<std::set<std::int64_t>> V(k.patches.size()), E(k.patches.size());
  std::vector<Map> loops(k.patches.size());
  std::vector<std::size_t> bd(k.patches.size(), 0);
  for (const auto& e : b.edge_faces) {
    std::map<std::uint32_t, int> count;
    for (auto f : e.second) ++count[k.face_patch[fid(f)]];
    for (const auto& c : count) {
      E[c.first].insert(e.first);
      for (auto v : edge_corners(b, e.first)) V[c.first].insert(v);
      if (c.second == 1) {
        REQUIRE(b.curve_edges.count(e.first));
        ++bd[c.first];
        const auto cs = edge_corners(b, e.first);
        loops[c.first].unite(-1 - cs[0], -1 - cs[1]);
      }
    }
    // Well-composed: a curve edge borders three patches or four.
    if (wc && b.curve_edges.count(e.first)) CHECK(count.size() >= 3);
  }
  for (std::size_t p = 0; p < k.patches.size(); ++p) {
    const Patch& q = k.patches[p];
    CHECK(q.vertices == V[p].size());
    CHECK(q.edges == E[p].size());
    CHECK(q.euler == (long long)V[p].size() - (long long)E[p].size() + (long long)q.faces);
    CHECK(q.boundary_edges == bd[p]);
    std::set<std::int64_t> roots;
    for (const auto& x : loops[p].p) roots.insert(loops[p].find(x.first));
    CHECK(q.boundary_loops == roots.size());
    // Orientable, so 2 - euler - loops is twice a genus (well-composed, not pinched).
    if (!wc || q.pinched_vertices) continue;
    CHECK((2 - q.euler - (long long)q.boundary_loops) % 2 == 0);
    CHECK(2 - q.euler - (long long)q.boundary_loops >= 0);
  }
  // Pinches: a patch's faces at a corner joined through the corner's edges
  // where both are the patch's; two classes or more at a corner.
  Map fans;  // (corner, face) pairs as corner * 2^32 + face id
  std::map<std::pair<std::uint32_t, std::int64_t>, std::set<std::int64_t>> at;  // (patch, corner) -> its faces
  for (const auto& e : b.edge_faces)
    for (auto f : e.second)
      for (auto v : edge_corners(b, e.first)) {
        const std::int64_t node = v * (std::int64_t(1) << 32) + std::int64_t(fid(f));
        at[{k.face_patch[fid(f)], v}].insert(node);
        for (auto g : e.second)
          if (k.face_patch[fid(g)] == k.face_patch[fid(f)])
            fans.unite(node, v * (std::int64_t(1) << 32) + std::int64_t(fid(g)));
      }
  std::vector<std::size_t> pinched(k.patches.size(), 0);
  std::set<std::uint64_t> pinches;
  for (const auto& a : at) {
    std::set<std::int64_t> roots;
    for (auto node : a.second) roots.insert(fans.find(node));
    if (roots.size() > 1) ++pinched[a.first.first], pinches.insert(std::uint64_t(a.first.second));
  }
  for (std::size_t p = 0; p < k.patches.size(); ++p) CHECK(k.patches[p].pinched_vertices == pinched[p]);
  CHECK(std::vector<std::uint64_t>(pinches.begin(), pinches.end()) == k.pinches);
  if (wc)
    for (auto c : k.pinches) CHECK(std::binary_search(k.junctions.begin(), k.junctions.end(), c));
  // Curve edges.
  REQUIRE(k.curve_edges.size() == b.curve_edges.size());
  i = 0;
  for (auto e : b.curve_edges) REQUIRE(k.curve_edges[i++] == std::uint64_t(e));
  // Loops: at each curve edge, the face of each patch with one face there.
  std::vector<std::size_t> loop_edges(k.patches.size(), 0), loops_of(k.patches.size(), 0);
  for (const auto& l : k.loops) loop_edges[l.patch] += l.edges, ++loops_of[l.patch];
  for (std::size_t p = 0; p < k.patches.size(); ++p) {
    CHECK(loop_edges[p] == k.patches[p].boundary_edges);
    CHECK(loops_of[p] == k.patches[p].boundary_loops);
  }
  REQUIRE(k.curve_edge_loop.size() == 4 * k.curve_edges.size());
  i = 0;
  for (auto e : b.curve_edges) {
    const int a = int(e % 3), bb = (a + 1) % 3, cc = (a + 2) % 3;
    const std::int64_t q = e / 3;
    const std::int64_t p[3] = {q % b.lat[0], q / b.lat[0] % b.lat[1], q / b.lat[0] / b.lat[1]};
    const int st[5][2] = {{0, 0}, {1, 0}, {1, 1}, {0, 1}, {0, 0}};
    std::map<std::uint32_t, int> count;
    std::array<std::uint32_t, 4> patch_at{};
    for (int f = 0; f < 4; ++f) {
      // Faces i: between voxels f, f + 1; its lowest corner is the higher voxel's position.
      std::int64_t hi[3] = {p[0], p[1], p[2]};
      const int n = st[f][0] != st[f + 1][0] ? bb : cc;
      hi[bb] -= 1 - std::max(st[f][0], st[f + 1][0]) * (n == bb) - st[f][0] * (n != bb);
      hi[cc] -= 1 - std::max(st[f][1], st[f + 1][1]) * (n == cc) - st[f][1] * (n != cc);
      const std::size_t id = k.find_face(std::uint64_t(b.corner(hi[0], hi[1], hi[2])), n);
      patch_at[std::size_t(f)] = id < k.faces.size() ? k.face_patch[id] : InterfaceComplex::kNoLoop;
      if (id < k.faces.size()) ++count[k.face_patch[id]];
    }
    for (int f = 0; f < 4; ++f) {
      const std::uint32_t loop = k.curve_edge_loop[4 * i + std::size_t(f)];
      const bool alone = patch_at[std::size_t(f)] != InterfaceComplex::kNoLoop && count[patch_at[std::size_t(f)]] == 1;
      CHECK((loop != InterfaceComplex::kNoLoop) == alone);
      if (alone) CHECK(k.loops[loop].patch == patch_at[std::size_t(f)]);
    }
    ++i;
  }
  // Junctions: corners with curve edges other than two of one label set.
  std::map<std::int64_t, std::vector<std::int64_t>> at_corner;
  for (auto e : b.curve_edges)
    for (auto v : edge_corners(b, e)) at_corner[v].push_back(e);
  auto label_set = [&](std::int64_t e) {
    std::set<std::int32_t> ls;
    for (auto f : b.edge_faces.at(e)) ls.insert(b.faces.at(f).first), ls.insert(b.faces.at(f).second);
    return ls;
  };
  std::vector<std::uint64_t> junctions;
  Map curves;
  for (const auto& c : at_corner) {
    if (c.second.size() == 2 && label_set(c.second[0]) == label_set(c.second[1]))
      curves.unite(c.second[0], c.second[1]);
    else
      junctions.push_back(std::uint64_t(c.first));
  }
  CHECK(junctions == k.junctions);
  // Curves: one of K's a class of curve edges; closed when no end is a junction.
  std::map<std::int64_t, std::uint32_t> root_curve;
  std::map<std::uint32_t, std::size_t> edges;
  i = 0;
  for (auto e : b.curve_edges) {
    const std::uint32_t c = k.curve_edge_curve[i++];
    CHECK(root_curve.emplace(curves.find(e), c).first->second == c);
    ++edges[c];
    CHECK(k.curves[c].labels[0] == *label_set(e).begin());
    CHECK(std::size_t(k.curves[c].label_count) == label_set(e).size());
  }
  CHECK(root_curve.size() == k.curves.size());
  std::vector<bool> open(k.curves.size(), false);
  i = 0;
  for (auto e : b.curve_edges) {
    const std::uint32_t c = k.curve_edge_curve[i++];
    for (auto v : edge_corners(b, e)) open[c] = open[c] || std::binary_search(junctions.begin(), junctions.end(), std::uint64_t(v));
  }
  for (std::size_t c = 0; c < k.curves.size(); ++c) CHECK(k.curves[c].closed == !open[c]);
  for (const auto& c : edges) CHECK(k.curves[c.first].edges == c.second);
  for (const auto& c : k.curves)
    if (c.closed) CHECK(c.ends == std::array<std::uint64_t, 2>{0, 0});
}

// Every label's bdCA: faces with it on a side, joined at edges; V - E + F.
void check_labels_against_brute_force(const LabelImage& img, const InterfaceComplex& k) {
  const Brute b = brute_force(img);
  std::size_t sum = 0;
  for (const auto& lb : k.labels) {
    const std::int32_t l = lb.label;
    Map u;
    for (const auto& e : b.edge_faces) {
      std::int64_t first = -1;
      for (auto f : e.second)
        if (b.faces.at(f).first == l || b.faces.at(f).second == l) {
          if (first >= 0) u.unite(first, std::int64_t(f));
          first = std::int64_t(f);
        }
    }
    std::map<std::int64_t, std::tuple<std::set<std::int64_t>, std::set<std::int64_t>, std::size_t>> comps;
    for (const auto& e : b.edge_faces)
      for (auto f : e.second)
        if (b.faces.at(f).first == l || b.faces.at(f).second == l) {
          auto& c = comps[u.find(std::int64_t(f))];
          std::get<0>(c).insert(e.first);
          for (auto v : edge_corners(b, e.first)) std::get<1>(c).insert(v);
        }
    for (const auto& f : b.faces)
      if (f.second.first == l || f.second.second == l) ++std::get<2>(comps[u.find(std::int64_t(f.first))]);
    std::vector<std::pair<std::size_t, long long>> expect;
    for (const auto& c : comps)
      expect.emplace_back(std::get<2>(c.second), (long long)std::get<1>(c.second).size() -
                                                     (long long)std::get<0>(c.second).size() +
                                                     (long long)std::get<2>(c.second));
    std::sort(expect.begin(), expect.end());
    CHECK(label_components(k, l) == expect);
    // The patches of pairs containing L hold bdCA(L)'s faces.
    std::size_t faces = 0;
    for (const auto& p : k.patches)
      if (p.behind == l || p.front == l) faces += p.faces;
    CHECK(faces == lb.faces);
    sum += lb.faces;
  }
  CHECK(sum == 2 * k.faces.size());
}

} // namespace

TEST_CASE("interface complex: nested shells are two spheres", "[interface_complex]") {
  // A 3^3 ball (label 2) in a 5^3 shell (label 1) in background. Patches
  // {1,0} and {2,1}: spheres, V = F + 2, E = 2F, F = 150 and 54; no curve.
  LabelImage img = label_grid(7, 7, 7);
  paint(img, {1, 1, 1}, {5, 5, 5}, 1);
  paint(img, {2, 2, 2}, {4, 4, 4}, 2);
  const InterfaceComplex k = interface_complex(img);
  REQUIRE(k.failed_guarantee().empty());
  REQUIRE(k.patches.size() == 2);
  const auto outer = patches_of(k, 1, 0), inner = patches_of(k, 2, 1);
  REQUIRE(outer.size() == 1);
  REQUIRE(inner.size() == 1);
  CHECK(outer[0]->faces == 150);
  CHECK(outer[0]->edges == 300);
  CHECK(outer[0]->vertices == 152);
  CHECK(outer[0]->euler == 2);
  CHECK(inner[0]->faces == 54);
  CHECK(inner[0]->euler == 2);
  CHECK(outer[0]->boundary_loops == 0);
  CHECK(k.curves.empty());
  CHECK(k.curve_edges.empty());
  CHECK(k.junctions.empty());
  // Label 1: the outer and the inner sphere; 0 and 2 one each.
  CHECK(label_components(k, 0) == std::vector<std::pair<std::size_t, long long>>{{150, 2}});
  CHECK(label_components(k, 1) == std::vector<std::pair<std::size_t, long long>>{{54, 2}, {150, 2}});
  CHECK(label_components(k, 2) == std::vector<std::pair<std::size_t, long long>>{{54, 2}});
  // Orientation out of the higher label: the shell's top face at the centre
  // points +z (label 1 below, 0 above), the ball's bottom face -z (2 above).
  const std::size_t top = k.find_face(3 + 8 * (3 + 8 * 6), 2), bottom = k.find_face(3 + 8 * (3 + 8 * 2), 2);
  REQUIRE(top < k.faces.size());
  CHECK(InterfaceComplex::face_corner(k.faces[top]) == 3 + 8 * (3 + 8 * 6));
  CHECK(InterfaceComplex::face_axis(k.faces[top]) == 2);
  CHECK(InterfaceComplex::face_plus(k.faces[top]));
  REQUIRE(bottom < k.faces.size());
  CHECK(!InterfaceComplex::face_plus(k.faces[bottom]));
  CHECK(k.find_face(0, 0) == k.faces.size());  // no face at the grid's corner
  CHECK(k.summary() == "interface complex: 2 patches, 0 curves, 0 junctions");
  check_against_brute_force(img, k);
}

TEST_CASE("interface complex: a ring of two labels meets the background on two triple loops", "[interface_complex]") {
  // A square frame (x, y in 1..8 less the hole 4..5, z in 1..2), label 1
  // where x <= 4, label 2 where x >= 5: they meet on two 3x2 rectangles
  // (y 1..3 and 6..8): patch {2,1} two discs (V 12, E 17, F 6: chi 1, one
  // loop of 10 edges each); {1,0}, {2,0} annuli (chi 0, two loops); two
  // closed curves {0,1,2} of 10 edges; no junction. bdCA(0): the frame's
  // torus (chi 0); labels 1, 2: spheres.
  LabelImage img = label_grid(10, 10, 4);
  paint(img, {1, 1, 1}, {8, 8, 2}, 1);
  paint(img, {4, 4, 1}, {5, 5, 2}, 0);
  for (std::size_t z = 0; z < 4; ++z)
    for (std::size_t y = 0; y < 10; ++y)
      for (std::size_t x = 5; x < 10; ++x)
        if (img(x, y, z) == 1) img(x, y, z) = 2;
  const InterfaceComplex k = interface_complex(img);
  REQUIRE(k.failed_guarantee().empty());
  const auto discs = patches_of(k, 1, 2);
  REQUIRE(discs.size() == 2);
  for (const Patch* p : discs) {
    CHECK(p->faces == 6);
    CHECK(p->vertices == 12);
    CHECK(p->edges == 17);
    CHECK(p->euler == 1);
    CHECK(p->boundary_loops == 1);
    CHECK(p->boundary_edges == 10);
  }
  for (std::int32_t l : {1, 2}) {
    const auto annulus = patches_of(k, l, 0);
    REQUIRE(annulus.size() == 1);
    CHECK(annulus[0]->euler == 0);
    CHECK(annulus[0]->boundary_loops == 2);
    CHECK(annulus[0]->boundary_edges == 20);
  }
  REQUIRE(k.curves.size() == 2);
  for (const auto& c : k.curves) {
    CHECK(c.closed);
    CHECK(c.edges == 10);
    CHECK(c.label_count == 3);
    CHECK(c.labels == std::array<std::int32_t, 4>{0, 1, 2, 0});
  }
  CHECK(k.junctions.empty());
  CHECK(label_components(k, 0).size() == 1);
  CHECK(label_components(k, 0)[0].second == 0);
  CHECK(label_components(k, 1).size() == 1);
  CHECK(label_components(k, 1)[0].second == 2);
  CHECK(label_components(k, 2)[0].second == 2);
  check_against_brute_force(img, k);
  check_labels_against_brute_force(img, k);
}

TEST_CASE("interface complex: four columns meet on an axis between two junctions", "[interface_complex]") {
  // A 4^3 box of four 2x2x4 columns (labels 1..4 by quadrant) in
  // background. The axis: 4 edges where 1, 2, 3, 4 meet. Each interface of
  // neighbouring quadrants meets the background on an arc top centre -> side
  // -> bottom centre (2 + 4 + 2 edges, labels {0, a, b}). Junctions: the top
  // and bottom centres (five curve edges each); the arcs bend at the sides
  // without a junction (two edges, one label set). Patches: {a, b} 2x4
  // rectangles (chi 1, loop of 12 edges), {a, 0} the column's surface less
  // two sides (24 faces, chi 1, loop of 16 edges).
  LabelImage img = label_grid(6, 6, 6);
  paint(img, {1, 1, 1}, {2, 2, 4}, 1);
  paint(img, {3, 1, 1}, {4, 2, 4}, 2);
  paint(img, {3, 3, 1}, {4, 4, 4}, 3);
  paint(img, {1, 3, 1}, {2, 4, 4}, 4);
  const InterfaceComplex k = interface_complex(img);
  REQUIRE(k.failed_guarantee().empty());
  REQUIRE(k.patches.size() == 8);
  for (auto ab : {std::make_pair(1, 2), std::make_pair(2, 3), std::make_pair(3, 4), std::make_pair(4, 1)}) {
    const auto p = patches_of(k, ab.first, ab.second);
    REQUIRE(p.size() == 1);
    CHECK(p[0]->faces == 8);
    CHECK(p[0]->euler == 1);
    CHECK(p[0]->boundary_edges == 12);
    CHECK(p[0]->boundary_loops == 1);
  }
  CHECK(patches_of(k, 1, 3).empty());
  for (std::int32_t a = 1; a <= 4; ++a) {
    const auto p = patches_of(k, a, 0);
    REQUIRE(p.size() == 1);
    CHECK(p[0]->faces == 24);
    CHECK(p[0]->euler == 1);
    CHECK(p[0]->boundary_edges == 16);
    CHECK(p[0]->boundary_loops == 1);
    CHECK(label_components(k, a) == std::vector<std::pair<std::size_t, long long>>{{40, 2}});
  }
  CHECK(k.curve_edges.size() == 36);
  REQUIRE(k.junctions.size() == 2);
  CHECK(k.corner(k.junctions[0]) == std::array<std::size_t, 3>{3, 3, 1});
  CHECK(k.corner(k.junctions[1]) == std::array<std::size_t, 3>{3, 3, 5});
  REQUIRE(k.curves.size() == 5);
  std::multiset<std::size_t> lengths;
  for (const auto& c : k.curves) {
    CHECK(!c.closed);
    CHECK(c.ends == std::array<std::uint64_t, 2>{k.junctions[0], k.junctions[1]});
    lengths.insert(c.edges);
    CHECK(c.label_count == (c.edges == 4 ? 4 : 3));
  }
  CHECK(lengths == std::multiset<std::size_t>{4, 8, 8, 8, 8});
  CHECK(k.summary() == "interface complex: 8 patches, 5 curves, 2 junctions");
  const Json j = k.to_json();
  CHECK(j.at("faces").integer() == 128);
  CHECK(j.at("boundary_loops").integer() == 8);
  CHECK(j.at("curves").integer() == 5);
  CHECK(j.at("closed_curves").integer() == 0);
  CHECK(j.at("junctions").integer() == 2);
  CHECK(j.at("c1").integer() + j.at("c2").integer() + j.at("pinches").integer() == 0);
  check_against_brute_force(img, k);
  check_labels_against_brute_force(img, k);
}

TEST_CASE("interface complex: labels filling the grid meet beyond it", "[interface_complex]") {
  // Labels 1 (x 0..1) and 2 (x 2..3) fill a 4^3 grid; beyond it is 0. {2,1}:
  // the 4x4 square x = 2 (disc); {1,0}, {2,0}: discs of 64 - 16 faces; one closed
  // curve {0,1,2} of 16 edges on the grid's sides; bdCA(0) the grid's
  // surface (96 faces, chi 2).
  LabelImage img = label_grid(4, 4, 4);
  paint(img, {0, 0, 0}, {1, 3, 3}, 1);
  paint(img, {2, 0, 0}, {3, 3, 3}, 2);
  const InterfaceComplex k = interface_complex(img);
  REQUIRE(k.failed_guarantee().empty());
  CHECK(one_patch(k, 2, 1).faces == 16);
  CHECK(one_patch(k, 2, 1).euler == 1);
  CHECK(one_patch(k, 1, 0).faces == 48);
  CHECK(one_patch(k, 1, 0).euler == 1);
  REQUIRE(k.curves.size() == 1);
  CHECK(k.curves[0].closed);
  CHECK(k.curves[0].edges == 16);
  CHECK(label_components(k, 0) == std::vector<std::pair<std::size_t, long long>>{{96, 2}});
  check_against_brute_force(img, k);
  check_labels_against_brute_force(img, k);
  // One label filling the grid: the grid's surface, one patch; none at all:
  // an empty complex with label 0 alone.
  paint(img, {0, 0, 0}, {3, 3, 3}, 5);
  const InterfaceComplex one = interface_complex(img);
  CHECK(one.patches.size() == 1);
  CHECK(one_patch(one, 5, 0).euler == 2);
  CHECK(one.labels.size() == 2);
  paint(img, {0, 0, 0}, {3, 3, 3}, 0);
  const InterfaceComplex none = interface_complex(img);
  CHECK(none.faces.empty());
  REQUIRE(none.labels.size() == 1);
  CHECK(none.labels[0].components.empty());
  CHECK(none.summary() == "interface complex: 0 patches, 0 curves, 0 junctions");
}

TEST_CASE("interface complex: one-voxel labels, alone and on an interface", "[interface_complex]") {
  // Two 4x4x4 boxes 1 | 2 in background; voxel 3 inside box 1 (a cube:
  // patch {3,1} of 6 faces, V 8, E 12, chi 2) and voxel 4 in box 1 against
  // the interface (patch {4,1}: 5 faces, a disc; {4,2}: one face; the
  // interface {2,1} an annulus, chi 0, two loops; a closed curve {1,2,4} of
  // 4 edges around the face and the curve {0,1,2} of 16 around the
  // interface).
  LabelImage img = label_grid(10, 6, 6);
  paint(img, {1, 1, 1}, {4, 4, 4}, 1);
  paint(img, {5, 1, 1}, {8, 4, 4}, 2);
  img(2, 2, 2) = 3;
  img(4, 3, 3) = 4;
  const InterfaceComplex k = interface_complex(img);
  REQUIRE(k.failed_guarantee().empty());
  const auto cube = patches_of(k, 3, 1);
  REQUIRE(cube.size() == 1);
  CHECK(cube[0]->faces == 6);
  CHECK(cube[0]->vertices == 8);
  CHECK(cube[0]->edges == 12);
  CHECK(cube[0]->euler == 2);
  CHECK(one_patch(k, 4, 1).faces == 5);
  CHECK(one_patch(k, 4, 1).euler == 1);
  CHECK(one_patch(k, 4, 2).faces == 1);
  CHECK(one_patch(k, 4, 2).euler == 1);
  CHECK(one_patch(k, 4, 2).boundary_edges == 4);
  CHECK(one_patch(k, 2, 1).faces == 15);
  CHECK(one_patch(k, 2, 1).euler == 0);
  CHECK(one_patch(k, 2, 1).boundary_loops == 2);
  REQUIRE(k.curves.size() == 2);
  std::multiset<std::size_t> lengths;
  for (const auto& c : k.curves) {
    lengths.insert(c.edges);
    CHECK(c.closed);
  }
  CHECK(lengths == std::multiset<std::size_t>{4, 16});
  CHECK(label_components(k, 3) == std::vector<std::pair<std::size_t, long long>>{{6, 2}});
  CHECK(label_components(k, 1).size() == 2);  // the box's surface and the cavity of voxel 3
  check_against_brute_force(img, k);
  check_labels_against_brute_force(img, k);
}

TEST_CASE("interface complex: a torus label inside another", "[interface_complex]") {
  // A square frame (label 2, x, y 2..7 less 4..5, z 2..3) inside a box of
  // label 1: patch {2,1} a torus (chi 0, no boundary), {1,0} a sphere;
  // bdCA(1) both.
  LabelImage img = label_grid(10, 10, 6);
  paint(img, {1, 1, 1}, {8, 8, 4}, 1);
  paint(img, {2, 2, 2}, {7, 7, 3}, 2);
  paint(img, {4, 4, 2}, {5, 5, 3}, 1);
  const InterfaceComplex k = interface_complex(img);
  REQUIRE(k.failed_guarantee().empty());
  CHECK(one_patch(k, 2, 1).euler == 0);
  CHECK(one_patch(k, 2, 1).boundary_loops == 0);
  CHECK(one_patch(k, 1, 0).euler == 2);
  const auto l1 = label_components(k, 1);
  REQUIRE(l1.size() == 2);
  CHECK(std::set<long long>{l1[0].second, l1[1].second} == std::set<long long>{0, 2});
  check_against_brute_force(img, k);
}

TEST_CASE("interface complex: a well-composed block where a patch pinches at a junction", "[interface_complex]") {
  // The header's example: bit k the voxel (k & 1, k >> 1 & 1, k >> 2 & 1) of
  // a 2x2x2 grid, labels 0 0 0 1 2 0 3 3. Label 3 is the bar y = z = 1; its
  // faces around the centre corner (1,1,1) read 3|0, 3|2, 3|0, 3|1: patch
  // {3,0} (8 faces: the bar's 10 less the two to 1 and 2, which touch at the
  // centre only) is two fans there. V 12 - E 20 + F 8 = 0 (a sphere less two
  // squares sharing a corner), one component of boundary edges.
  LabelImage img = label_grid(2, 2, 2);
  const std::int32_t v[8] = {0, 0, 0, 1, 2, 0, 3, 3};
  for (int i = 0; i < 8; ++i) img.data[std::size_t(i)] = v[i];
  const InterfaceComplex k = interface_complex(img);
  REQUIRE(k.failed_guarantee().empty());
  const Patch& p = *patches_of(k, 3, 0)[0];
  CHECK(p.faces == 8);
  CHECK(p.vertices == 12);
  CHECK(p.edges == 20);
  CHECK(p.euler == 0);
  CHECK(p.pinched_vertices == 1);
  CHECK(p.boundary_edges == 8);
  CHECK(p.boundary_loops == 1);
  REQUIRE(k.pinches.size() == 1);
  CHECK(k.corner(k.pinches[0]) == std::array<std::size_t, 3>{1, 1, 1});
  CHECK(std::binary_search(k.junctions.begin(), k.junctions.end(), k.pinches[0]));
  CHECK(k.pinched_vertices() == 1);
  check_against_brute_force(img, k);
  check_labels_against_brute_force(img, k);
}

TEST_CASE("interface complex: a C1 or C2 is counted and fails the guarantee", "[interface_complex]") {
  // Two voxels of label 1 sharing only an edge: one C1 of 1 (and of 0, whose
  // indicator is X != 0's complement: the same square).
  LabelImage img = label_grid(4, 4, 3);
  img(1, 1, 1) = 1;
  img(2, 2, 1) = 1;
  InterfaceComplex k = interface_complex(img);
  CHECK(k.find_label(1)->critical.c1 == 1);
  CHECK(k.find_label(0)->critical.c1 == 1);
  CHECK(!k.failed_guarantee().empty());
  // Sharing only a vertex: a C2.
  img(2, 2, 1) = 0;
  img(2, 2, 2) = 1;
  k = interface_complex(img);
  CHECK(k.find_label(1)->critical.c2 == 1);
  CHECK(k.find_label(1)->critical.c1 == 0);
  CHECK(!k.failed_guarantee().empty());
  // Two labels on the diagonals (a b / b a around an edge): C1 of both, their
  // four faces one patch, counted not hidden.
  img = label_grid(2, 2, 1);
  img(0, 0, 0) = 1, img(1, 1, 0) = 1, img(1, 0, 0) = 2, img(0, 1, 0) = 2;
  k = interface_complex(img);
  CHECK(k.find_label(1)->critical.c1 >= 1);
  CHECK(k.find_label(2)->critical.c1 >= 1);
  CHECK(patches_of(k, 1, 2).size() == 1);
  CHECK(one_patch(k, 1, 2).faces == 4);
}

TEST_CASE("interface complex: random well-composed partitions against the brute force", "[interface_complex]") {
  std::mt19937_64 rng(20261205);
  for (int i = 0; i < 20; ++i) {
    const LabelImage img = random_well_composed(rng, 3, 1 + i % 6);
    const InterfaceComplex k = interface_complex(img);
    INFO("case " << i << ": " << k.summary());
    REQUIRE(k.failed_guarantee().empty());
    check_against_brute_force(img, k);
    check_labels_against_brute_force(img, k);
    // Curves: every edge on one, arcs end at junctions.
    std::size_t edges = 0;
    for (const auto& c : k.curves) {
      edges += c.edges;
      if (!c.closed)
        for (auto e : c.ends) CHECK(std::binary_search(k.junctions.begin(), k.junctions.end(), e));
    }
    CHECK(edges == k.curve_edges.size());
  }
}

TEST_CASE("interface complex: every 2x2x2 partition against the brute force", "[interface_complex]") {
  // All well-composed ones, a sixteenth of the others (time).
  std::size_t n = 0;
  for_each_block_partition([&](const LabelImage& img) {
    INFO("partition " << ++n);
    const InterfaceComplex k = interface_complex(img);
    if (k.critical.total() && n % 16) return;
    check_against_brute_force(img, k);
    if (k.critical.total() == 0) check_labels_against_brute_force(img, k);
  });
  CHECK(n == 4140);
}

TEST_CASE("interface complex: 2D, two labels filling the grid and a one-pixel label", "[interface_complex]") {
  // A 6x4 image: label 1 at x 0..2, 2 at x 3..5, beyond is 0; pixel (1, 1)
  // label 3. Pixel edges: {2,1} the line x = 3 (4 edges, V 5: an arc, chi 1,
  // two ends); {1,0}, {2,0} the grid's sides (10 edges each, arcs); {3,1} a
  // loop of 4 (chi 0). Junctions where 0, 1, 2 meet: corners (3, 0), (3, 4).
  // Every label's boundary: loops (chi 0); label 1 two of them.
  LabelImage img = label_grid(6, 4, 1, 2);
  paint(img, {0, 0, 0}, {2, 3, 0}, 1);
  paint(img, {3, 0, 0}, {5, 3, 0}, 2);
  img(1, 1, 0) = 3;
  const InterfaceComplex k = interface_complex(img);
  REQUIRE(k.dimension == 2);
  REQUIRE(k.failed_guarantee().empty());
  CHECK(k.faces.size() == 28);
  const Patch& line = *patches_of(k, 2, 1)[0];
  CHECK(line.faces == 4);
  CHECK(line.vertices == 5);
  CHECK(line.euler == 1);
  CHECK(line.boundary_edges == 2);
  for (std::int32_t l : {1, 2}) {
      CHECK(one_patch(k, l, 0).faces == 10);
    CHECK(one_patch(k, l, 0).euler == 1);
    CHECK(one_patch(k, l, 0).boundary_edges == 2);
  }
  CHECK(one_patch(k, 3, 1).euler == 0);
  CHECK(one_patch(k, 3, 1).boundary_edges == 0);
  REQUIRE(k.junctions.size() == 2);
  CHECK(k.corner(k.junctions[0]) == std::array<std::size_t, 3>{3, 0, 0});
  CHECK(k.corner(k.junctions[1]) == std::array<std::size_t, 3>{3, 4, 0});
  CHECK(k.curves.empty());
  CHECK(label_components(k, 0) == std::vector<std::pair<std::size_t, long long>>{{20, 0}});
  CHECK(label_components(k, 1) == std::vector<std::pair<std::size_t, long long>>{{4, 0}, {14, 0}});
  CHECK(label_components(k, 2) == std::vector<std::pair<std::size_t, long long>>{{14, 0}});
  // Orientation out of the higher label: the edge x = 3, y 0..1 between 1
  // (minus side) and 2: its normal points -x.
  const std::size_t e = k.find_face(3, 0);
  REQUIRE(e < k.faces.size());
  CHECK(!InterfaceComplex::face_plus(k.faces[e]));
  // A diagonal pair: C1 of 1 and of 2, one patch of 4 edges pinched.
  img = label_grid(2, 2, 1, 2);
  img(0, 0, 0) = 1, img(1, 1, 0) = 1, img(1, 0, 0) = 2, img(0, 1, 0) = 2;
  const InterfaceComplex d = interface_complex(img);
  CHECK(d.find_label(1)->critical.c1 == 1);
  CHECK(d.find_label(2)->critical.c1 == 1);
  CHECK(one_patch(d, 1, 2).pinched_vertices == 1);
  CHECK(!d.failed_guarantee().empty());
}
