// FacetCycle (thesis 8.2): a closed curve of S inside the Voronoi facet of
// a Delaunay edge, a piece of S that no Voronoi edge sees. Queries on the
// triangulation and f; DELMESH inserts the points they return.
#pragma once
#include "surface/cube_grid.hpp"
#include "surface/delaunay_types.hpp"

#include <cstddef>
#include <cstdint>
#include <utility>
#include <vector>

namespace imgmesh::surface_detail {

// Does S have a closed curve inside the Voronoi facet dual to edge e = pq?
// kCycle: x is a point of it (on S) far from p, e's first vertex; kSkipped:
// the facet is too large to rasterise now (not an answer).
// Thread-safe. `memo` (optional) keeps the circumcentres of the cells it
// was asked about, for later edges around them (W must not change meanwhile).
enum class FacetAnswer { kNone, kCycle, kSkipped };
// How the rows are walked: only the stretches near active cubes (where the
// cost says so, else every row cube by cube), every row cube by cube, or
// (tests) both, each compared with every sample's sign by definition (its
// cube's corner sign if inactive, else f's), throwing Error unless their
// runs agree: the walks are optimisations that must change no sign.
enum class FacetWalk { kSpans, kFull, kCompare };
// Open addressing on the cell's address, at most half full, emptied when
// full (128 KB): a cell has six edges, each checked once a pass.
struct CentreMemo {
  static constexpr std::size_t kSlots = 1 << 12;
  std::vector<std::pair<const void*, Vec3>> table;
  std::size_t used = 0;
  Vec3 operator()(const Tr& tr, Ch c);
};
FacetAnswer facet_cycle(const Tr& tr, const SurfaceSampler& f, const Tr::Edge& e, Vec3& x, FacetWalk how = FacetWalk::kSpans,
                        CentreMemo* memo = nullptr);

// One pass: FacetCycle on every edge at a vertex of `changed` (ids into
// `vertices`, null where deleted), each edge once, on `threads` threads.
// Returns the cycle points found, in edge order (by the ends' ids, lower
// first); `checks` counts the edges. Uses the vertices' stamps with
// `stamp` (DELMESH's counter). `skipped`: the first vertex of each edge
// FacetCycle skipped, to check again. The edges are found and checked
// `chunk` at a time (about; any chunk gives the same answer).
Candidates facet_cycle_points(const Tr& tr, const SurfaceSampler& f, const std::vector<Vh>& vertices, const IdSet& changed,
                              std::uint32_t& stamp, int threads, long long& checks, std::vector<int>& skipped,
                              FacetWalk how = FacetWalk::kSpans, std::size_t chunk = 1 << 15);

} // namespace imgmesh::surface_detail
