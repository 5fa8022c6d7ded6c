// poly2tri's graded square lattice on random star polygons in a box (fixed
// seeds): the lattice coarsens away from the curves, each triangle no larger
// than the size field asks, neighbouring triangles within a factor of each
// other, and the angle bound, segments and area as without it.
#include "planar/triangulate.hpp"

#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <map>
#include <random>

using namespace imgmesh;

namespace {

// The box [0, 100]^2 with a star polygon of n vertices around (50, 50), radii
// in [15, 35] (a hole with `hole`, else a second region).
PlanarMesh star_in_box(unsigned seed, bool hole) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> R(15, 35);
  PlanarMesh p;
  p.points = {{0, 0}, {100, 0}, {100, 100}, {0, 100}};
  p.segments = {{0, 1}, {1, 2}, {2, 3}, {3, 0}};
  const int n = 40 + int(seed % 5) * 10;
  for (int k = 0; k < n; ++k) {
    const double a = 2 * M_PI * k / n, r = R(rng);
    p.points.push_back({50 + r * std::cos(a), 50 + r * std::sin(a)});
    p.segments.push_back({4 + k, 4 + (k + 1) % n});
  }
  if (hole) p.holes = {{50, 50}};
  return p;
}

double distance_to_segment(const Point2& p, const Point2& a, const Point2& b) {
  const double dx = b[0] - a[0], dy = b[1] - a[1], l2 = dx * dx + dy * dy;
  const double t = std::clamp(((p[0] - a[0]) * dx + (p[1] - a[1]) * dy) / l2, 0.0, 1.0);
  return std::hypot(a[0] + t * dx - p[0], a[1] + t * dy - p[1]);
}

double longest_edge(const PlanarMesh& m, const std::vector<int>& e) {
  double l = 0;
  for (int i = 0; i < 3; ++i) {
    const Point2 &a = m.points[e[i]], &b = m.points[e[(i + 1) % 3]];
    l = std::max(l, std::hypot(b[0] - a[0], b[1] - a[1]));
  }
  return l;
}

} // namespace

TEST_CASE("triangulate: a graded square lattice follows the distance to the curves", "[lattice]") {
  for (unsigned seed = 1; seed <= 8; ++seed) {
    const PlanarMesh pslg = star_in_box(seed, seed % 2);
    TriangulateOptions opt;
    opt.lattice = 1;
    opt.square_lattice = true;
    opt.grading = seed % 3 ? 0.25 : 0.5;
    opt.max_side = 16;
    const TriangulateResult graded = triangulate_pslg(pslg, opt);
    const double G = opt.grading;
    opt.grading = 0;
    const TriangulateResult uniform = triangulate_pslg(pslg, opt);
    const PlanarMesh& m = graded.mesh;
    CAPTURE(seed, G, graded.mesh.points.size(), uniform.mesh.points.size());
    INFO(graded.failed_guarantee());
    CHECK(graded.failed_guarantee().empty());
    // Coarser away from the curves: far fewer points than the uniform lattice.
    CHECK(2 * graded.mesh.points.size() < uniform.mesh.points.size());
    // Each triangle within the size field at its centroid, f = the least over
    // the segments of their length (in [1, 16]) + G d: a lattice cell of side
    // s was kept at corners where s <= f, and f grows by at most G s from a
    // corner to the centroid, so s <= f_c / (1 - G) (10% more for the
    // distance transform's error); its longest edge is the diagonal, and
    // the refinement's triangles along a segment are at most its length.
    std::map<std::pair<int, int>, std::vector<double>> sizes;  // edge -> its triangles' longest edges
    for (const auto& e : m.elements) {
      const Point2 c{(m.points[e[0]][0] + m.points[e[1]][0] + m.points[e[2]][0]) / 3,
                     (m.points[e[0]][1] + m.points[e[1]][1] + m.points[e[2]][1]) / 3};
      double f = 1e300;
      for (const auto& sg : pslg.segments) {
        const Point2 &a = pslg.points[sg[0]], &b = pslg.points[sg[1]];
        const double len = std::clamp(std::hypot(b[0] - a[0], b[1] - a[1]), 1.0, 16.0);
        f = std::min(f, len + G * distance_to_segment(c, a, b));
      }
      const double l = longest_edge(m, e);
      CAPTURE(c[0], c[1], f, l);
      CHECK(l <= std::sqrt(2.0) * std::min(1.1 * f / (1 - G), 16.0) * (1 + 1e-9));
      for (int i = 0; i < 3; ++i) sizes[std::minmax(e[i], e[(i + 1) % 3])].push_back(l);
    }
    // Neighbours within a factor of about 2: the lattice doubles at most
    // once from a cell to the next (a factor 2 between its triangles); the
    // triangles of the band along the curves sit in between. So 99% of the
    // neighbours within 2.5, and none 4 apart (two levels at once).
    std::vector<double> ratios;
    double worst = 1;
    Point2 at{0, 0};
    for (const auto& [edge, ls] : sizes)
      if (ls.size() == 2) {
        ratios.push_back(std::max(ls[0], ls[1]) / std::min(ls[0], ls[1]));
        if (ratios.back() > worst) worst = ratios.back(), at = m.points[edge.first];
      }
    std::sort(ratios.begin(), ratios.end());
    const double p99 = ratios[std::size_t(0.99 * double(ratios.size() - 1))];
    CAPTURE(worst, at[0], at[1], p99);
    CHECK(worst < 4);
    CHECK(p99 <= 2.5);
    // The grading did coarsen: some cells are at least 4 times the finest.
    double largest = 0;
    for (const auto& e : m.elements) largest = std::max(largest, longest_edge(m, e));
    CHECK(largest >= 4 * std::sqrt(2.0));
  }
}

TEST_CASE("triangulate: with narrow, the square lattice fits a row of half-side cells into a slot narrower than its side", "[lattice]") {
  // The box [0, 40]^2 and a slot [5, 35] x [19, 20.6] inside it, 0.8 of
  // the lattice side 2 across: no node of side 2 is half a side from both
  // of its long sides, a node of side 1 is (at y = 20). No refinement, so
  // the Steiner points are the lattice's.
  PlanarMesh p;
  p.points = {{0, 0}, {40, 0}, {40, 40}, {0, 40}, {5, 19}, {35, 19}, {35, 20.6}, {5, 20.6}};
  p.segments = {{0, 1}, {1, 2}, {2, 3}, {3, 0}, {4, 5}, {5, 6}, {6, 7}, {7, 4}};
  TriangulateOptions opt;
  opt.min_angle = 0;
  opt.lattice = 2;
  opt.square_lattice = true;
  opt.grading = 0.25;
  opt.max_side = 8;
  const auto in_slot = [&](const TriangulateResult& r) {
    int n = 0;
    for (const auto& q : r.mesh.points) {
      if (!(q[0] > 5 && q[0] < 35 && q[1] > 19 && q[1] < 20.6)) continue;
      ++n;
      // Half the finer side from every segment, as any lattice node.
      for (const auto& s : p.segments) CHECK(distance_to_segment(q, p.points[s[0]], p.points[s[1]]) >= 0.5 - 1e-9);
    }
    return n;
  };
  const TriangulateResult wide = triangulate_pslg(p, opt);
  opt.narrow = true;
  const TriangulateResult narrow = triangulate_pslg(p, opt);
  CHECK(in_slot(wide) == 0);
  CHECK(in_slot(narrow) >= 25);  // a node every 1 along the slot's 30
}
