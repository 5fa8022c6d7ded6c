// Pieces the two halves of the topology module share (topology.cpp in 3D,
// topology_planar.cpp in 2D). Internal to lib/mesh.
#pragma once
#include "mesh/topology.hpp"
#include "util/error.hpp"

#include <algorithm>
#include <cstdint>
#include <numeric>
#include <utility>
#include <vector>

namespace imgmesh::mesh_detail {

// 32-bit parents: half the memory (a surface mesh's corners, an image's
// pixels); more than 2^32 elements is refused.
struct UnionFind {
  std::vector<std::uint32_t> p;
  explicit UnionFind(std::size_t n) : p(checked(n)) { std::iota(p.begin(), p.end(), std::uint32_t(0)); }
  std::size_t find(std::size_t x) {
    while (p[x] != x) { p[x] = p[p[x]]; x = p[x]; }
    return x;
  }
  // The smaller id stays the root, so a root is its set's smallest member.
  void unite(std::size_t a, std::size_t b) {
    a = find(a); b = find(b);
    if (a != b) p[std::max(a, b)] = std::uint32_t(std::min(a, b));
  }
  static std::size_t checked(std::size_t n) {
    if (n > 0xffffffffu) throw Error("topology: more than 2^32 elements");
    return n;
  }
};

} // namespace imgmesh::mesh_detail
