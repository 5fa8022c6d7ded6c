#include "smooth_test_support.hpp"

#include "quad/predicates.hpp"
#include "quad/quality.hpp"
#include "tri2quad/tri2quad.hpp"

#include <catch2/catch.hpp>

#include <algorithm>
#include <map>
#include <random>

using namespace imgmesh;

namespace quadsmooth_test {

PlanarMesh jittered_grid(int n, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> U(-0.3, 0.3);
  PlanarMesh m;
  for (int j = 0; j <= n; ++j)
    for (int i = 0; i <= n; ++i) {
      const bool in = i > 0 && i < n && j > 0 && j < n;
      m.points.push_back({(i + (in ? U(rng) : 0)) / n, (j + (in ? U(rng) : 0)) / n});
    }
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      const int a = j * (n + 1) + i;
      m.elements.push_back({a, a + 1, a + n + 2, a + n + 1});
    }
  return m;
}

double region_area(const PlanarMesh& m, double region) {
  double s = 0;
  for (std::size_t e = 0; e < m.elements.size(); ++e) {
    if (m.element_attributes[e][0] != region) continue;
    const auto& el = m.elements[e];
    s += quad_area(m.points[el[0]], m.points[el[1]], m.points[el[2]], m.points[el[3]]);
  }
  return s;
}

PlanarMesh tri2quad_mesh(int n, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> U(-0.25, 0.25);  // no triangle folds
  std::bernoulli_distribution coin(0.5);
  Tri2QuadInput in;
  auto id = [&](int i, int j) { return j * (n + 1) + i; };
  for (int j = 0; j <= n; ++j)
    for (int i = 0; i <= n; ++i) {
      const bool inside = i > 0 && i < n && j > 0 && j < n;
      in.points.push_back({(i + (inside && 2 * i != n ? U(rng) : 0)) / n, (j + (inside ? U(rng) : 0)) / n});
    }
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      const int a = id(i, j), b = id(i + 1, j), c = id(i + 1, j + 1), d = id(i, j + 1);
      if (coin(rng)) in.triangles.insert(in.triangles.end(), {{a, b, c}, {a, c, d}});
      else in.triangles.insert(in.triangles.end(), {{a, b, d}, {b, c, d}});
      in.region.insert(in.region.end(), 2, 2 * i < n ? 1.0 : 2.0);
    }
  for (int j = 0; j < n; ++j) {
    in.constraints.push_back({id(n / 2, j), id(n / 2, j + 1)});
    in.constraint_markers.push_back(2);
  }
  const Tri2QuadResult r = tri2quad(in);
  PlanarMesh m;
  m.points = r.points;
  for (std::size_t q = 0; q < r.quads.size(); ++q) {
    m.elements.push_back({r.quads[q][0], r.quads[q][1], r.quads[q][2], r.quads[q][3]});
    m.element_attributes.push_back({r.region[q]});
  }
  m.segments = r.segments;
  m.segment_markers = r.segment_markers;
  for (std::size_t v = 0; v < m.points.size(); ++v) m.point_attributes.push_back({double(v + 1)});
  return m;
}

State snapshot(const QuadMesh& qm) {
  return {qm.quads,       qm.vertex_quads, qm.points, qm.quad_sin_mu,
          qm.quad_dead,   qm.vertex_dead,  qm.mesh.elements.size()};
}

void check_same(const State& a, const State& b) {
  CHECK(a.quads == b.quads);
  CHECK(a.stars == b.stars);
  CHECK(a.points == b.points);
  CHECK(a.sines == b.sines);
  CHECK(a.quad_dead == b.quad_dead);
  CHECK(a.vertex_dead == b.vertex_dead);
  CHECK(a.elements == b.elements);
}

bool live_quads_strictly_convex(const QuadMesh& qm) {
  for (std::size_t q = 0; q < qm.quads.size(); ++q) {
    const auto& c = qm.quads[q];
    if (!qm.quad_dead[q] && !is_strictly_convex(qm.points[c[0]], qm.points[c[1]], qm.points[c[2]], qm.points[c[3]]))
      return false;
  }
  return true;
}

double quad_mu(const PlanarMesh& m, const std::vector<int>& e) {
  return joe_mu(m.points[e[0]], m.points[e[1]], m.points[e[2]], m.points[e[3]]);
}

double total_area(const PlanarMesh& m) {
  double s = 0;
  for (const auto& e : m.elements) s += quad_area(m.points[e[0]], m.points[e[1]], m.points[e[2]], m.points[e[3]]);
  return s;
}

std::set<std::pair<int, int>> boundary_edges(const PlanarMesh& m) {
  std::map<std::pair<int, int>, int> uses;
  for (const auto& e : m.elements)
    for (std::size_t i = 0; i < e.size(); ++i) ++uses[std::minmax(e[i], e[(i + 1) % e.size()])];
  std::set<std::pair<int, int>> s;
  for (const auto& [k, c] : uses)
    if (c == 1) s.insert(k);
  return s;
}

} // namespace quadsmooth_test
