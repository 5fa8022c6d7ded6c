#include "tri2quad_test_support.hpp"

#include "quad/quality.hpp"

#include <CGAL/Constrained_Delaunay_triangulation_2.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Triangulation_face_base_with_info_2.h>

#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <list>
#include <map>
#include <set>

using namespace imgmesh;

namespace tri2quad_test {

long small_excess_q = -1000000, small_excess_s = -1000000;

double poly_area(const std::vector<P2>& v) {
  double a = 0;
  for (std::size_t i = 0; i < v.size(); ++i)
    a += v[i][0] * v[(i + 1) % v.size()][1] - v[(i + 1) % v.size()][0] * v[i][1];
  return a / 2;
}

// A random simple (star-shaped) polygon around the origin.
std::vector<P2> random_star(std::mt19937& g, int n, double rmin, double rmax) {
  std::uniform_real_distribution<double> U(0, 1);
  std::vector<double> ang;
  for (int i = 0; i < n; ++i) ang.push_back(U(g) * 2 * kPi);
  std::sort(ang.begin(), ang.end());
  std::vector<P2> v;
  for (double a : ang) {
    const double r = rmin + (rmax - rmin) * U(g);
    v.push_back({r * std::cos(a), r * std::sin(a)});
  }
  return v;
}


void check_result(const Tri2QuadInput& in, const Tri2QuadResult& r, bool allow_outside) {
  const auto& P = r.points;
  REQUIRE(P.size() == in.points.size() + r.steiner);
  for (std::size_t i = 0; i < in.points.size(); ++i) REQUIRE(P[i] == in.points[i]);
  std::size_t non_convex = 0;
  double qa = 0, ta = 0;
  std::map<std::pair<int, int>, int> directed;
  std::set<int> used;
  for (const auto& q : r.quads) {
    non_convex += !is_strictly_convex(P[q[0]], P[q[1]], P[q[2]], P[q[3]]);
    qa += quad_area(P[q[0]], P[q[1]], P[q[2]], P[q[3]]);
    for (int k = 0; k < 4; ++k) {
      ++directed[{q[k], q[(k + 1) % 4]}];
      used.insert(q[k]);
    }
  }
  CHECK(non_convex == 0);
  for (const auto& t : in.triangles) {
    ta += std::fabs(poly_area({in.points[t[0]], in.points[t[1]], in.points[t[2]]}));
    for (int v : t) CHECK(used.count(v) == 1);
  }
  // With --allow-outside one quad per outer component may stick out.
  if (!allow_outside) CHECK(qa == Approx(ta).epsilon(1e-9));
  else CHECK(qa >= ta * (1 - 1e-9));
  std::size_t repeated = 0, boundary = 0;
  std::map<int, std::vector<int>> adj;
  for (const auto& [e, n] : directed) {
    repeated += n > 1;
    if (!directed.count({e.second, e.first})) ++boundary;
    adj[e.first].push_back(e.second);
    adj[e.second].push_back(e.first);
  }
  CHECK(repeated == 0);
  // Every constraint / boundary edge of the input is a chain of quad edges
  // through points on the segment.
  std::set<std::pair<int, int>> input_boundary;
  {
    std::map<std::pair<int, int>, int> te;
    for (const auto& t : in.triangles)
      for (int k = 0; k < 3; ++k) ++te[{std::min(t[k], t[(k + 1) % 3]), std::max(t[k], t[(k + 1) % 3])}];
    for (const auto& [e, n] : te) if (n == 1) input_boundary.insert(e);
  }
  std::vector<std::array<int, 2>> segs = in.constraints;
  for (const auto& e : input_boundary) segs.push_back({e.first, e.second});
  std::size_t lost = 0;
  double boundary_len_in = 0;
  for (const auto& s : segs) {
    const P2 a = P[s[0]], b = P[s[1]];
    const double len2 = (b[0] - a[0]) * (b[0] - a[0]) + (b[1] - a[1]) * (b[1] - a[1]);
    int cur = s[0], prev = -1, steps = 0;
    while (cur != s[1] && steps < 50) {
      int next = -1;
      for (int w : adj[cur]) {
        if (w == prev) continue;
        if (w == s[1]) { next = w; break; }
        const P2 p = P[w];
        const double cr = (b[0] - a[0]) * (p[1] - a[1]) - (b[1] - a[1]) * (p[0] - a[0]);
        const double t = ((p[0] - a[0]) * (b[0] - a[0]) + (p[1] - a[1]) * (b[1] - a[1])) / len2;
        const double tc = ((P[cur][0] - a[0]) * (b[0] - a[0]) + (P[cur][1] - a[1]) * (b[1] - a[1])) / len2;
        if (std::size_t(w) >= in.points.size() && std::fabs(cr) <= 1e-9 * len2 && t > tc && t < 1) next = w;
      }
      if (next < 0) break;
      prev = cur;
      cur = next;
      ++steps;
    }
    lost += cur != s[1];
  }
  for (const auto& e : input_boundary)
    boundary_len_in += std::hypot(P[e.second][0] - P[e.first][0], P[e.second][1] - P[e.first][1]);
  CHECK(lost <= r.steiner_outside);
  double boundary_len_out = 0;
  for (const auto& [e, n] : directed)
    if (!directed.count({e.second, e.first}))
      boundary_len_out += std::hypot(P[e.second][0] - P[e.first][0], P[e.second][1] - P[e.first][1]);
  if (!allow_outside) CHECK(boundary_len_out == Approx(boundary_len_in).epsilon(1e-9));
  // The size bounds of the thesis, for every t (small meshes included).
  CHECK(r.quads.size() <= r.quad_bound());
  CHECK(r.steiner <= r.steiner_bound(allow_outside));
  small_excess_q = std::max(small_excess_q, long(r.quads.size()) - long(r.quad_bound()));
  small_excess_s = std::max(small_excess_s, long(r.steiner) - long(r.steiner_bound(allow_outside)));
  if (!allow_outside) CHECK(r.steiner_outside == 0);
}

struct FaceInfo { int nesting = -1; int region = 0; bool in_domain() const { return nesting % 2 == 1; } };
using K = CGAL::Exact_predicates_inexact_constructions_kernel;
using Fbb = CGAL::Triangulation_face_base_with_info_2<FaceInfo, K>;
using Fb = CGAL::Constrained_triangulation_face_base_2<K, Fbb>;
using Tds = CGAL::Triangulation_data_structure_2<CGAL::Triangulation_vertex_base_2<K>, Fb>;
using CDT = CGAL::Constrained_Delaunay_triangulation_2<K, Tds, CGAL::Exact_predicates_tag>;

// Nesting levels across the outer boundary and holes (odd = domain); the
// interior loops are constraints that do not change the level (they only
// give the faces a different region attribute).
void mark(CDT& cdt, const std::set<std::pair<K::Point_2, K::Point_2>>& walls,
          const std::set<std::pair<K::Point_2, K::Point_2>>& loops) {
  for (auto f = cdt.all_faces_begin(); f != cdt.all_faces_end(); ++f) f->info().nesting = -1;
  std::list<std::pair<CDT::Face_handle, std::pair<int, int>>> border;
  border.push_back({cdt.infinite_face(), {0, 0}});
  while (!border.empty()) {
    auto [start, lv] = border.front();
    border.pop_front();
    if (start->info().nesting != -1) continue;
    std::list<std::pair<CDT::Face_handle, int>> q{{start, lv.second}};
    while (!q.empty()) {
      auto [f, reg] = q.front();
      q.pop_front();
      if (f->info().nesting != -1) continue;
      f->info().nesting = lv.first;
      f->info().region = reg;
      for (int i = 0; i < 3; ++i) {
        auto n = f->neighbor(i);
        if (n->info().nesting != -1) continue;
        const auto a = f->vertex(f->cw(i))->point(), b = f->vertex(f->ccw(i))->point();
        const auto key = a < b ? std::make_pair(a, b) : std::make_pair(b, a);
        if (walls.count(key)) border.push_back({n, {lv.first + 1, 0}});
        else if (loops.count(key)) border.push_front({n, {lv.first, reg + 1}});
        else q.push_back({n, reg});
      }
    }
  }
}

Tri2QuadInput random_cdt(std::mt19937& g, int npoints, int nholes, int nloops) {
  std::uniform_real_distribution<double> U(0, 1);
  CDT cdt;
  std::set<std::pair<K::Point_2, K::Point_2>> walls, loops;
  auto add_loop = [&](const std::vector<P2>& v, double cx, double cy, bool wall) {
    for (std::size_t i = 0; i < v.size(); ++i) {
      K::Point_2 a(cx + v[i][0], cy + v[i][1]), b(cx + v[(i + 1) % v.size()][0], cy + v[(i + 1) % v.size()][1]);
      cdt.insert_constraint(a, b);
      (wall ? walls : loops).insert(a < b ? std::make_pair(a, b) : std::make_pair(b, a));
    }
  };
  add_loop(random_star(g, 5 + int(U(g) * 10), 0.38, 0.5), 0.5, 0.5, true);
  // Four slots for holes and loops, well apart.
  const double sx[4] = {0.35, 0.65, 0.35, 0.65}, sy[4] = {0.35, 0.35, 0.65, 0.65};
  int slot = 0;
  for (int h = 0; h < nholes && slot < 4; ++h, ++slot) add_loop(random_star(g, 3 + int(U(g) * 4), 0.04, 0.1), sx[slot], sy[slot], true);
  for (int l = 0; l < nloops && slot < 4; ++l, ++slot) add_loop(random_star(g, 3 + int(U(g) * 5), 0.05, 0.11), sx[slot], sy[slot], false);
  for (int i = 0; i < npoints; ++i) {
    const double r = 0.36 * std::sqrt(U(g)), a = 2 * kPi * U(g);
    cdt.insert(K::Point_2(0.5 + r * std::cos(a), 0.5 + r * std::sin(a)));
  }
  mark(cdt, walls, loops);
  Tri2QuadInput in;
  std::map<CDT::Vertex_handle, int> id;
  auto vid = [&](CDT::Vertex_handle v) {
    auto it = id.find(v);
    if (it != id.end()) return it->second;
    const int k = int(in.points.size());
    id[v] = k;
    in.points.push_back({v->point().x(), v->point().y()});
    return k;
  };
  for (auto f = cdt.finite_faces_begin(); f != cdt.finite_faces_end(); ++f) {
    if (!f->info().in_domain()) continue;
    in.triangles.push_back({vid(f->vertex(0)), vid(f->vertex(1)), vid(f->vertex(2))});
    in.region.push_back(f->info().region);
  }
  // Interior constraint edges (the loops, as the CDT split them).
  for (auto e = cdt.finite_edges_begin(); e != cdt.finite_edges_end(); ++e) {
    if (!cdt.is_constrained(*e)) continue;
    const auto f = e->first;
    const auto n = f->neighbor(e->second);
    if (!f->info().in_domain() || cdt.is_infinite(n) || !n->info().in_domain()) continue;
    in.constraints.push_back({id.at(f->vertex(f->cw(e->second))), id.at(f->vertex(f->ccw(e->second)))});
  }
  return in;
}

} // namespace tri2quad_test
