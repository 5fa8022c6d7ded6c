// TopoDisk (thesis 7.6.1): do the restricted facets around a vertex form one
// closed disk? A query on the triangulation; TOPOLOGY inserts the surface
// centre of the worst facet when not.
#pragma once
#include "surface/delaunay_types.hpp"

#include <utility>
#include <vector>

namespace imgmesh::surface_detail {

// The restricted facets incident to v, each once (cells: scratch).
void restricted_around(const Tr& tr, Vh v, std::vector<Facet>& facets, std::vector<Ch>& cells);

class TopoDisk {
public:
  // True if v's restricted facets form one closed disk (or v has none).
  // Else false, and *worst is the one with the largest surface Delaunay ball.
  bool operator()(const Tr& tr, Vh v, Facet* worst);
  // The link of a vertex, as edges between vertex ids, is one cycle: every
  // link vertex in two link edges, and the edges one closed walk.
  bool one_cycle(const std::vector<std::pair<int, int>>& link);
  // The restricted facets at the vertex last checked (restricted_around's).
  const std::vector<Facet>& facets() const { return facets_; }

private:
  // Scratch (no allocation per check).
  std::vector<Facet> facets_;
  std::vector<Ch> cells_;
  std::vector<std::pair<int, int>> link_;
  std::vector<int> ends_;
  std::vector<char> used_;
};

} // namespace imgmesh::surface_detail
