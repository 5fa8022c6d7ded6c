// TopoDisk (7.6.1) alone: on link cycles given by hand, and on every vertex
// of triangulations DELMESH built, against a count of the restricted facets
// around each vertex done another way (all finite facets, union-find).
#include "shapes.hpp"
#include "surface/delmesh.hpp"
#include "surface/topo_disk.hpp"

#include <catch2/catch.hpp>

#include <functional>
#include <map>
#include <set>

using namespace imgmesh;
using namespace imgmesh::surface_detail;

namespace {
// v's restricted facets form one disk: their link edges (opposite v) make
// each link vertex of degree two and are connected.
bool star_is_disk(const Tr& tr, Vh v) {
  std::vector<std::pair<int, int>> link;
  for (auto it = tr.finite_facets_begin(); it != tr.finite_facets_end(); ++it) {
    if (!(it->first->facet[it->second].state & kRestricted)) continue;
    std::vector<int> others;
    bool has_v = false;
    for (int m = 1; m < 4; ++m) {
      const Vh w = it->first->vertex((it->second + m) & 3);
      if (w == v) has_v = true;
      else others.push_back(w->info().id);
    }
    if (has_v) link.emplace_back(others[0], others[1]);
  }
  if (link.empty()) return true;
  std::map<int, int> degree, parent;
  std::function<int(int)> find = [&](int a) { return parent[a] == a ? a : parent[a] = find(parent[a]); };
  for (auto [a, b] : link) {
    ++degree[a];
    ++degree[b];
    parent.emplace(a, a);
    parent.emplace(b, b);
  }
  for (auto [a, b] : link) parent[find(a)] = find(b);
  std::set<int> roots;
  for (auto& [a, d] : degree) {
    if (d != 2) return false;
    roots.insert(find(a));
  }
  return roots.size() == 1;
}
} // namespace

TEST_CASE("TopoDisk::one_cycle: a cycle yes; a bowtie, two cycles, a path or nothing no") {
  TopoDisk t;
  CHECK(t.one_cycle({{1, 2}, {2, 3}, {3, 4}, {4, 5}, {5, 1}}));
  CHECK(t.one_cycle({{7, 3}, {1, 2}, {3, 1}, {2, 7}}));  // in any order
  CHECK_FALSE(t.one_cycle({{1, 2}, {2, 3}, {3, 1}, {1, 4}, {4, 5}, {5, 1}}));  // two disks at one point
  CHECK_FALSE(t.one_cycle({{1, 2}, {2, 3}, {3, 1}, {4, 5}, {5, 6}, {6, 4}}));  // two disks
  CHECK_FALSE(t.one_cycle({{1, 2}, {2, 3}, {3, 4}}));                          // a boundary
  CHECK_FALSE(t.one_cycle({}));
}

TEST_CASE("TopoDisk on a triangulation: false exactly where the restricted facets around a vertex are not one disk") {
  // A thin torus: after the seeds alone, many stars are not disks; after
  // DELMESH, all are.
  const Vec3 c{11.6, 11.3, 4.6};
  FunctionSurface s(test::box(24, 24, 10), [&](const Vec3& p) { return test::torus_f(p, c, 8.1, 1.1); });
  RestrictedDelaunayOptions o;
  DelMesh m(s, o);
  m.prepare();
  m.seeds();
  TopoDisk topo_disk;
  int not_disk = 0, disk = 0;
  for (Vh v : m.vertices()) {
    Facet worst;
    const bool ok = topo_disk(m.triangulation(), v, &worst);
    CHECK(ok == star_is_disk(m.triangulation(), v));
    (ok ? disk : not_disk) += 1;
    if (!ok) {
      // The worst facet is one of v's restricted facets.
      CHECK((worst.first->facet[worst.second].state & kRestricted));
      bool at_v = false;
      for (int k = 1; k < 4; ++k) at_v = at_v || worst.first->vertex((worst.second + k) & 3) == v;
      CHECK(at_v);
    }
  }
  CHECK(not_disk > 0);
  m.refine();
  for (Vh v : m.vertices()) {
    if (v == Vh()) continue;
    Facet worst;
    CHECK(topo_disk(m.triangulation(), v, &worst));
    CHECK(star_is_disk(m.triangulation(), v));
  }
}

// The side a facet is taken from (the insertion's hint when TopoDisk or
// SMOOTH refines there, which decides the new cells' layout) depends on the
// data only: the side whose opposite vertex has the smaller id. By address,
// the mesh depended on where the allocator put the cells.
TEST_CASE("restricted_around: each facet once, from the side opposite its smaller-id vertex") {
  const Vec3 c{11.6, 11.3, 4.6};
  FunctionSurface s(test::box(24, 24, 10), [&](const Vec3& p) { return test::torus_f(p, c, 8.1, 1.1); });
  RestrictedDelaunayOptions o;
  DelMesh m(s, o);
  m.prepare();
  m.seeds();
  m.refine();
  std::vector<Facet> facets;
  std::vector<Ch> cells;
  long long checked = 0;
  for (Vh v : m.vertices()) {
    restricted_around(m.triangulation(), v, facets, cells);
    for (const Facet& f : facets) {
      const Ch n = f.first->neighbor(f.second);
      CHECK(f.first->vertex(f.second)->info().id < n->vertex(n->index(f.first))->info().id);
      ++checked;
    }
  }
  CHECK(checked > 100);
}
