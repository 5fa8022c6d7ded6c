// A vertex's star (star.hpp) against CGAL's own walks: the same cells and
// vertices in the same order, on every vertex of a triangulation with
// small stars and large ones (a point inside a sphere of points, and the
// infinite vertex: the address sets grow); the nearest vertex as CGAL's.
#include "surface/star.hpp"

#include <catch2/catch.hpp>

#include <cmath>
#include <cstdint>
#include <iterator>
#include <vector>

using namespace imgmesh::surface_detail;

TEST_CASE("star: the cells and vertices around each vertex, in CGAL's order") {
  Tr tr;
  std::uint64_t s = 12345;
  auto unit = [&s] {  // deterministic in [0, 1)
    s = s * 6364136223846793005ull + 1442695040888963407ull;
    return double(s >> 11) * 0x1.0p-53;
  };
  for (int k = 0; k < 300; ++k) tr.insert(Point(4 * unit(), 4 * unit(), 4 * unit()));
  for (int k = 0; k < 200; ++k) {  // a sphere around (2, 2, 2), its centre a vertex of ~400 cells
    const double z = 2 * unit() - 1, a = 2 * M_PI * unit(), r = std::sqrt(1 - z * z);
    tr.insert(Point(2 + 0.5 * r * std::cos(a), 2 + 0.5 * r * std::sin(a), 2 + 0.5 * z));
  }
  tr.insert(Point(2, 2, 2));
  REQUIRE(tr.dimension() == 3);
  std::size_t largest = 0;
  std::vector<Vh> all{tr.infinite_vertex()};
  for (auto v = tr.finite_vertices_begin(); v != tr.finite_vertices_end(); ++v) all.push_back(v);
  for (Vh v : all) {
    std::vector<Ch> cgal, ours{Ch()};  // ours appends
    tr.incident_cells(v, std::back_inserter(cgal));
    star_cells(tr, v, ours);
    REQUIRE(std::vector<Ch>(ours.begin() + 1, ours.end()) == cgal);
    cgal.clear(), ours.clear();
    tr.incident_cells_threadsafe(v, std::back_inserter(cgal));
    star_cells_threadsafe(tr, v, ours);
    REQUIRE(ours == cgal);
    largest = std::max(largest, ours.size());
    std::vector<Vh> cgal_v, ours_v;
    tr.adjacent_vertices_threadsafe(v, std::back_inserter(cgal_v));
    star_vertices_threadsafe(tr, v, ours_v);
    REQUIRE(ours_v == cgal_v);
    cgal_v.clear(), ours_v.clear();
    tr.adjacent_vertices(v, std::back_inserter(cgal_v));
    star_vertices(tr, v, ours_v);
    REQUIRE(ours_v == cgal_v);
  }
  CHECK(largest > 256);
  // nearest_vertex: random points, grid points (on facets and edges of
  // cells: ties) and the vertices themselves, from every fiftieth cell.
  std::vector<Point> queries;
  for (int k = 0; k < 200; ++k) queries.emplace_back(5 * unit() - 0.5, 5 * unit() - 0.5, 5 * unit() - 0.5);
  for (int x = 0; x < 5; ++x)
    for (int y = 0; y < 5; ++y)
      for (int z = 0; z < 5; ++z) queries.emplace_back(x, y, z);
  for (int k = 0; k < 20; ++k) queries.push_back(all[std::size_t(1 + 7 * k)]->point());
  int n = 0;
  for (auto c = tr.all_cells_begin(); c != tr.all_cells_end(); ++c)
    if (n++ % 50 == 0)
      for (const Point& q : queries) REQUIRE(nearest_vertex(tr, q, c) == tr.nearest_vertex(q, c));
  // The marks star_cells sets are cleared: CGAL's walk after it sees them all.
  for (auto c = tr.all_cells_begin(); c != tr.all_cells_end(); ++c) REQUIRE(c->tds_data().is_clear());
}
