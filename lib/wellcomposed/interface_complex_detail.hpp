// Pieces the 3D and 2D halves of the interface complex share
// (interface_complex.cpp, interface_complex_planar.cpp). Internal to the
// wellcomposed module.
#pragma once
#include "util/error.hpp"
#include "wellcomposed/interface_complex.hpp"

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <utility>
#include <vector>

namespace imgmesh::wellcomposed_detail {

constexpr std::uint32_t kNone = 0xffffffffu;

// 32-bit parents that grow as elements are added; the smaller id stays the
// root, so a root is its set's first member.
struct GrowingUnionFind {
  std::vector<std::uint32_t> p;
  std::uint32_t add() {
    if (p.size() >= kNone) throw Error("interface complex: more than 2^32 faces or curve edges");
    p.push_back(std::uint32_t(p.size()));
    return p.back();
  }
  std::uint32_t find(std::uint32_t x) {
    while (p[x] != x) { p[x] = p[p[x]]; x = p[x]; }
    return x;
  }
  void unite(std::uint32_t a, std::uint32_t b) {
    a = find(a); b = find(b);
    if (a != b) p[std::max(a, b)] = std::min(a, b);
  }
  // Replaces each parent by its set's number, sets numbered in the order of
  // their first members; returns how many.
  std::uint32_t number_sets() {
    std::uint32_t n = 0;
    for (std::size_t x = 0; x < p.size(); ++x) p[x] = p[x] == x ? n++ : p[p[x]];
    return n;
  }
};

// At most a few distinct values (a corner's patches): linear search.
template <class T, std::size_t N> struct SmallSet {
  T v[N];
  std::size_t n = 0;
  bool insert(T x) {
    for (std::size_t i = 0; i < n; ++i)
      if (v[i] == x) return false;
    v[n++] = x;
    return true;
  }
};

// Sides of faces (face << 1 | s, s = 0 the higher label's side, 1 the
// lower's) that are one surface at an edge (2D: a corner).
using SideJoins = std::vector<std::pair<std::uint64_t, std::uint64_t>>;

// Patches from the faces' union-find (moved into face_patch): their faces,
// first faces and pairs (read from the image).
void make_patches(const LabelImage& img, InterfaceComplex& out, GrowingUnionFind& faces);

// bdCA(L)'s components: the sides of patches (2p the higher label's, 2p + 1
// the lower's) joined by `joins`; returns each side's component, components
// numbered in the order of their first faces, with their faces counted.
std::vector<std::uint32_t> side_components(const InterfaceComplex& out, const SideJoins& joins,
                                           std::vector<InterfaceComplex::Component>& components);

// Labels of the patches' pairs and 0, ascending, with their face counts and
// the components given (per side of each patch: its component, numbered in
// the order of first faces; components per label in that order).
void fill_labels(InterfaceComplex& k, const std::vector<std::uint32_t>& side_component,
                 const std::vector<InterfaceComplex::Component>& components);

InterfaceComplex interface_complex_3d(const LabelImage& labels);
InterfaceComplex interface_complex_2d(const LabelImage& labels);

} // namespace imgmesh::wellcomposed_detail
