// What lib/surfacenets' files share (surfacenets_detail): one quad's split,
// and the local crossing search the untangling runs incrementally.
#pragma once
#include "surfacenets/surface_nets.hpp"

#include <array>
#include <cstddef>
#include <cstdint>
#include <vector>

namespace imgmesh::surfacenets_detail {

// Quad f split along its better diagonal (split_quads, for one quad).
void split_quad(InterfaceMesh& mesh, std::size_t f);

// Whether the grid's direction matrix reflects (a negative determinant):
// index space's counter-clockwise is then world space's clockwise.
bool reflects(const Geometry& grid);

// The crossing pairs of an InterfaceMesh's triangles, each quad tested
// against the quads of its lattice neighbourhood only (crossings.cpp says
// why no crossing is missed). Holds a reference to the mesh: after moving a
// quad's vertices (and splitting it again), call update() for it.
class CrossingSearch {
public:
  // Throws Error when a vertex lies outside its cell, or a quad is not a
  // voxel face (its corners more than one lattice step apart). threads:
  // how many search a long list of quads, each a slice (same pairs).
  explicit CrossingSearch(const InterfaceMesh& mesh, unsigned threads = 1);
  void update(std::size_t quad);
  // The pairs with a triangle of one of `quads` (distinct quad ids), each
  // pair ascending, sorted; (t, t) for a degenerate triangle.
  std::vector<std::array<std::size_t, 2>> pairs(const std::vector<std::size_t>& quads) const;
  std::vector<std::array<std::size_t, 2>> all_pairs() const;

private:
  // forward: only the quads after it in order_ (all_pairs: each pair from its first quad).
  template <class Visit> void for_each_neighbour(std::size_t quad, bool forward, Visit&& visit) const;
  std::vector<std::array<std::size_t, 2>> search(const std::vector<std::size_t>& quads, bool all) const;
  void search_quad(std::size_t f, const std::vector<std::uint8_t>& listed, bool all,
                   std::vector<std::array<std::size_t, 2>>& out) const;
  int reach_of(std::size_t vertex) const;

  const InterfaceMesh& m_;
  unsigned threads_;
  // How far beyond a quad's corner box its neighbours' start: 0 while every
  // vertex lies strictly inside its cell, 1 once one lies on a cell's side
  // (crossings.cpp).
  int reach_ = 0;
  std::vector<std::array<std::int32_t, 3>> lo_, hi_;  // per quad: its corners' lattice box
  std::vector<std::uint32_t> order_;                  // quads by lowest corner (z, y, x)
  std::vector<std::uint32_t> position_;               // per quad: its entry in order_
  std::vector<std::size_t> row_begin_;                // per lattice row y + ny z: its first entry in order_
  std::vector<std::array<float, 6>> box_;             // per quad: its points' box, rounded outward
  std::vector<std::uint8_t> degenerate_;              // per triangle
};

} // namespace imgmesh::surfacenets_detail
