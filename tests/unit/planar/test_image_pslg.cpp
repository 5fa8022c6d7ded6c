// img2poly + poly2tri engines on generated images: the promises of issue 4,
// checked by independent code (no expected output tuned to the code).
#include "planar/image_pslg.hpp"
#include "planar/triangulate.hpp"
#include "util/error.hpp"

#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <functional>
#include <map>
#include <numeric>
#include <random>
#include <set>

using namespace imgmesh;

namespace {

LabelImage make_image(std::size_t W, std::size_t H, const std::function<int(int, int)>& f,
                      Vec3 spacing = {1, 1, 1}, Vec3 origin = {0, 0, 0}) {
  Geometry g;
  g.dimension = 2;
  g.size = {W, H, 1};
  g.spacing = spacing;
  g.origin = origin;
  LabelImage img(g);
  for (std::size_t y = 0; y < H; ++y)
    for (std::size_t x = 0; x < W; ++x) img(x, y) = f(int(x), int(y));
  return img;
}

struct Seg { Point2 a, b; };

double seg_dist(const Point2& p, const Point2& a, const Point2& b) {
  const double dx = b[0] - a[0], dy = b[1] - a[1];
  const double l2 = dx * dx + dy * dy;
  double t = l2 > 0 ? ((p[0] - a[0]) * dx + (p[1] - a[1]) * dy) / l2 : 0;
  t = std::clamp(t, 0.0, 1.0);
  return std::hypot(p[0] - a[0] - t * dx, p[1] - a[1] - t * dy);
}

// bdCA of a label image in index coordinates: unit edges between 4-adjacent
// pixels of different labels.
std::vector<Seg> pixel_boundary(const LabelImage& L) {
  std::vector<Seg> out;
  for (std::size_t y = 0; y < L.size[1]; ++y)
    for (std::size_t x = 0; x < L.size[0]; ++x) {
      if (x + 1 < L.size[0] && L(x, y) != L(x + 1, y))
        out.push_back({{x + 0.5, y - 0.5}, {x + 0.5, y + 0.5}});
      if (y + 1 < L.size[1] && L(x, y) != L(x, y + 1))
        out.push_back({{x - 0.5, y + 0.5}, {x + 0.5, y + 0.5}});
    }
  return out;
}

Point2 to_index(const LabelImage& L, const Point2& w) {
  const Vec3 c = L.continuous_index({w[0], w[1], L.origin[2]});
  return {c[0], c[1]};
}

// Connected components of a set of segments (shared endpoints join them).
std::size_t components(const std::vector<Seg>& segs) {
  std::map<Point2, int> id;
  std::vector<int> parent;
  auto get = [&](const Point2& p) {
    auto [it, fresh] = id.emplace(p, int(parent.size()));
    if (fresh) parent.push_back(int(parent.size()));
    return it->second;
  };
  std::function<int(int)> find = [&](int i) { return parent[i] == i ? i : parent[i] = find(parent[i]); };
  for (const auto& s : segs) {
    const int a = find(get(s.a)), b = find(get(s.b));
    parent[a] = b;
  }
  std::size_t n = 0;
  for (std::size_t i = 0; i < parent.size(); ++i) n += find(int(i)) == int(i);
  return n;
}

double min_angle_deg(const Point2& a, const Point2& b, const Point2& c) {
  auto ang = [](const Point2& p, const Point2& q, const Point2& r) {
    const double ux = q[0] - p[0], uy = q[1] - p[1], vx = r[0] - p[0], vy = r[1] - p[1];
    return std::atan2(std::abs(ux * vy - uy * vx), ux * vx + uy * vy) * 180 / M_PI;
  };
  return std::min({ang(a, b, c), ang(b, c, a), ang(c, a, b)});
}

// Everything issue 4 promises for IN -> img2poly -> poly2tri.
void check_pipeline(const LabelImage& img, double E) {
  ImagePslgOptions opt;
  opt.tolerance = E;
  const ImagePslgResult r = image_to_pslg(img, opt);
  const LabelImage& L = r.labels;
  const PlanarMesh& p = r.pslg;

  // The repaired image: no two-label diagonal 2x2 block; labels only raised.
  for (std::size_t y = 0; y + 1 < L.size[1]; ++y)
    for (std::size_t x = 0; x + 1 < L.size[0]; ++x) {
      const bool diag = L(x, y) == L(x + 1, y + 1) && L(x + 1, y) == L(x, y + 1) && L(x, y) != L(x + 1, y);
      REQUIRE_FALSE(diag);
    }
  for (std::size_t y = 0; y < img.size[1]; ++y)
    for (std::size_t x = 0; x < img.size[0]; ++x)
      REQUIRE(L(x, y) >= img(x, y));

  // Curves in index coordinates, rectangle apart.
  std::vector<Seg> curves, box;
  for (std::size_t s = 0; s < p.segments.size(); ++s) {
    const Seg g{to_index(L, p.points[p.segments[s][0]]), to_index(L, p.points[p.segments[s][1]])};
    (p.segment_markers[s] == 1 ? box : curves).push_back(g);
  }
  REQUIRE(box.size() >= 4);
  // The rectangle is the image's extent.
  for (const auto& g : box)
    for (const Point2& q : {g.a, g.b}) {
      const bool on_x = std::abs(q[0] + 0.5) < 1e-9 || std::abs(q[0] - (L.size[0] - 0.5)) < 1e-9;
      const bool on_y = std::abs(q[1] + 0.5) < 1e-9 || std::abs(q[1] - (L.size[1] - 0.5)) < 1e-9;
      CHECK((on_x || on_y));
    }
  const std::vector<Seg> bd = pixel_boundary(L);
  // Same number of curves (connected pieces) as bdCA.
  CHECK(components(curves) == components(bd));
  // Hausdorff both ways, within E: bdCA corners to the curves, and points
  // along the curves to bdCA.
  double h1 = 0, h2 = 0;
  for (const auto& e : bd)
    for (const Point2& q : {e.a, e.b}) {
      double d = 1e300;
      for (const auto& c : curves) d = std::min(d, seg_dist(q, c.a, c.b));
      h1 = std::max(h1, d);
    }
  for (const auto& c : curves)
    for (int k = 0; k <= 8; ++k) {
      const Point2 q{c.a[0] + (c.b[0] - c.a[0]) * k / 8.0, c.a[1] + (c.b[1] - c.a[1]) * k / 8.0};
      double d = 1e300;
      for (const auto& e : bd) d = std::min(d, seg_dist(q, e.a, e.b));
      h2 = std::max(h2, d);
    }
  CHECK(h1 <= E + 1e-6);
  CHECK(h2 <= E + 1e-6);
  CHECK(r.hausdorff <= E + 1e-9);
  // The reported smallest angle between segments at a vertex is the real one.
  {
    double smallest = 180;
    for (std::size_t s1 = 0; s1 < p.segments.size(); ++s1)
      for (std::size_t s2 = s1 + 1; s2 < p.segments.size(); ++s2)
        for (int i : {0, 1})
          for (int j : {0, 1}) {
            if (p.segments[s1][i] != p.segments[s2][j]) continue;
            const Point2 o = p.points[p.segments[s1][i]];
            const Point2 a = p.points[p.segments[s1][1 - i]], b = p.points[p.segments[s2][1 - j]];
            const double ux = a[0] - o[0], uy = a[1] - o[1], vx = b[0] - o[0], vy = b[1] - o[1];
            smallest = std::min(smallest, std::atan2(std::abs(ux * vy - uy * vx), ux * vx + uy * vy) * 180 / M_PI);
          }
    CHECK(r.smallest_angle == Approx(smallest).margin(1e-9));
  }
  // One regional point per region, each on a pixel of its label.
  for (const auto& reg : p.regions) {
    const Point2 q = to_index(L, reg.point);
    CHECK(L(std::size_t(std::lround(q[0])), std::size_t(std::lround(q[1]))) == reg.attribute);
  }

  const TriangulateResult t = triangulate_pslg(p, {});
  const PlanarMesh& m = t.mesh;
  CHECK(t.regions_outside_domain == 0);
  // The rectangle is covered: total area.
  double area = 0;
  const double box_area = double(L.size[0]) * L.spacing[0] * double(L.size[1]) * L.spacing[1];
  std::set<std::pair<int, int>> mesh_edges;
  for (std::size_t i = 0; i < m.elements.size(); ++i) {
    const auto& e = m.elements[i];
    const Point2 &a = m.points[e[0]], &b = m.points[e[1]], &c = m.points[e[2]];
    const double cr = (b[0] - a[0]) * (c[1] - a[1]) - (c[0] - a[0]) * (b[1] - a[1]);
    REQUIRE(cr > 0);  // counter-clockwise, non-degenerate
    area += cr / 2;
    for (int k = 0; k < 3; ++k) mesh_edges.insert({std::min(e[k], e[(k + 1) % 3]), std::max(e[k], e[(k + 1) % 3])});
    // Region attribute = the label under the centroid, except within E of bdCA.
    const Point2 g = to_index(L, {(a[0] + b[0] + c[0]) / 3, (a[1] + b[1] + c[1]) / 3});
    const auto px = std::size_t(std::lround(g[0])), py = std::size_t(std::lround(g[1]));
    if (m.element_attributes[i][0] != L(px, py)) {
      double d = 1e300;
      for (const auto& s : bd) d = std::min(d, seg_dist(g, s.a, s.b));
      CHECK(d <= E + 1e-6);
    }
  }
  CHECK(std::abs(area - box_area) < 1e-6 * box_area);
  // Conformity: every PSLG segment is a chain of mesh edges.
  for (const auto& s : p.segments) {
    const Point2 a = p.points[s[0]], b = p.points[s[1]];
    const double len = std::hypot(b[0] - a[0], b[1] - a[1]);
    std::vector<std::pair<double, int>> on;
    for (std::size_t v = 0; v < m.points.size(); ++v)
      if (seg_dist(m.points[v], a, b) < 1e-9 * len)
        on.push_back({((m.points[v][0] - a[0]) * (b[0] - a[0]) + (m.points[v][1] - a[1]) * (b[1] - a[1])) / len, int(v)});
    std::sort(on.begin(), on.end());
    REQUIRE(on.size() >= 2);
    for (std::size_t k = 0; k + 1 < on.size(); ++k)
      CHECK(mesh_edges.count({std::min(on[k].second, on[k + 1].second), std::max(on[k].second, on[k + 1].second)}));
  }
  // Smallest angle >= 20.7 degrees except near small input angles: a vertex
  // in the disc around an apex where two segments meet at < 60 degrees, of
  // radius the shorter of the two.
  std::vector<std::vector<int>> at(p.points.size());
  for (std::size_t s = 0; s < p.segments.size(); ++s) {
    at[p.segments[s][0]].push_back(int(s));
    at[p.segments[s][1]].push_back(int(s));
  }
  std::vector<std::pair<Point2, double>> apex;
  for (std::size_t v = 0; v < p.points.size(); ++v)
    for (int s1 : at[v])
      for (int s2 : at[v]) {
        if (s1 >= s2) continue;
        const int w1 = p.segments[s1][0] == int(v) ? p.segments[s1][1] : p.segments[s1][0];
        const int w2 = p.segments[s2][0] == int(v) ? p.segments[s2][1] : p.segments[s2][0];
        const Point2 o = p.points[v], a = p.points[w1], b = p.points[w2];
        const double ux = a[0] - o[0], uy = a[1] - o[1], vx = b[0] - o[0], vy = b[1] - o[1];
        if (std::atan2(std::abs(ux * vy - uy * vx), ux * vx + uy * vy) * 180 / M_PI < 60)
          apex.push_back({o, std::min(std::hypot(ux, uy), std::hypot(vx, vy))});
      }
  std::size_t exempt = 0;
  for (const auto& e : m.elements) {
    const double mn = min_angle_deg(m.points[e[0]], m.points[e[1]], m.points[e[2]]);
    if (mn >= 20.7 - 1e-6) continue;
    bool near = false;
    for (int k = 0; k < 3; ++k)
      for (const auto& [o, r] : apex)
        near |= std::hypot(m.points[e[k]][0] - o[0], m.points[e[k]][1] - o[1]) <= r * (1 + 1e-9);
    CHECK(near);
    ++exempt;
  }
  CHECK(exempt <= m.elements.size() / 10);
}

} // namespace

TEST_CASE("binary: discs, a ring and specks, anisotropic spacing") {
  std::mt19937 rng(7);
  std::uniform_int_distribution<int> u(0, 999);
  std::set<std::pair<int, int>> specks;
  for (int k = 0; k < 12; ++k) specks.insert({u(rng) % 60, u(rng) % 50});
  const LabelImage img = make_image(
      60, 50,
      [&](int x, int y) {
        const double r1 = std::hypot(x - 20.3, y - 24.7), r2 = std::hypot(x - 45.1, y - 20.2);
        if (r1 < 12 && r1 > 5) return 1;  // ring
        if (r2 < 8.5) return 1;
        if (y > 40 && x > 38) return 1;  // touches the border
        return specks.count({x, y}) ? 1 : 0;
      },
      {0.7, 1.3, 1}, {-10, 5, 0});
  for (double E : {0.0, 0.75, 1.5, 3.0}) {
    INFO("E = " << E);
    check_pipeline(img, E);
  }
}

TEST_CASE("binary: a checkerboard corner (critical configuration) is repaired") {
  const LabelImage img = make_image(12, 12, [](int x, int y) {
    return (x == 4 && y == 4) || (x == 5 && y == 5) || (x >= 7 && x <= 9 && y >= 6 && y <= 8 && (x + y) % 2 == 0);
  });
  const ImagePslgResult r = image_to_pslg(img, {});
  CHECK(r.critical_configurations > 0);
  CHECK(r.changed_pixels > 0);
  check_pipeline(img, 1.0);
}

TEST_CASE("labels: three labels with junctions of degree 3 and 4") {
  const LabelImage img = make_image(40, 36, [](int x, int y) {
    if (std::hypot(x - 20.0, y - 18.0) < 9) return 3;
    if (x < 20) return y < 18 ? 1 : 2;
    return y < 18 ? 2 : 5;
  });
  const ImagePslgResult r = image_to_pslg(img, {});
  CHECK(r.junctions > 0);
  // One marker per pair of touching labels.
  std::set<std::pair<int, int>> pairs;
  for (const auto& f : r.interfaces) pairs.insert({f.a, f.b});
  CHECK(pairs.count({1, 2}) == 1);
  CHECK(pairs.count({2, 3}) == 1);
  CHECK(pairs.count({3, 5}) == 1);
  // Exactly the pairs of 4-adjacent labels of the repaired image.
  std::set<std::pair<int, int>> adjacent;
  const LabelImage& L = r.labels;
  for (std::size_t y = 0; y < L.size[1]; ++y)
    for (std::size_t x = 0; x < L.size[0]; ++x) {
      if (x + 1 < L.size[0] && L(x, y) != L(x + 1, y))
        adjacent.insert({std::min(L(x, y), L(x + 1, y)), std::max(L(x, y), L(x + 1, y))});
      if (y + 1 < L.size[1] && L(x, y) != L(x, y + 1))
        adjacent.insert({std::min(L(x, y), L(x, y + 1)), std::max(L(x, y), L(x, y + 1))});
    }
  CHECK(pairs == adjacent);
  check_pipeline(img, 1.0);
  check_pipeline(img, 2.5);
}

TEST_CASE("labels: random blobs, repair of two-label diagonals") {
  std::mt19937 rng(11);
  std::uniform_int_distribution<int> u(0, 3);
  const std::size_t W = 24, H = 20;
  std::vector<int> v(W * H);
  for (auto& x : v) x = u(rng);
  // Smooth a little so that regions are blobs, not noise.
  const LabelImage img = make_image(W, H, [&](int x, int y) { return v[(x / 3) * 3 + W * ((y / 3) * 3)]; });
  check_pipeline(img, 1.0);
}

TEST_CASE("a single label: the rectangle and one region") {
  const LabelImage img = make_image(5, 4, [](int, int) { return 7; });
  const ImagePslgResult r = image_to_pslg(img, {});
  CHECK(r.curves == 0);
  CHECK(r.pslg.segments.size() == 4);
  CHECK(r.junctions == 0);
  REQUIRE(r.pslg.regions.size() == 1);
  CHECK(r.pslg.regions[0].attribute == 7);
  const TriangulateResult t = triangulate_pslg(r.pslg, {});
  for (const auto& a : t.mesh.element_attributes) CHECK(a[0] == 7);
}

TEST_CASE("image_to_pslg rejects bad input") {
  Geometry g;
  g.dimension = 3;
  g.size = {4, 4, 3};
  CHECK_THROWS_AS(image_to_pslg(LabelImage(g)), Error);
  const LabelImage img = make_image(4, 4, [](int x, int) { return x > 1; });
  ImagePslgOptions opt;
  opt.tolerance = std::nan("");
  CHECK_THROWS_AS(image_to_pslg(img, opt), Error);
}

TEST_CASE("triangulate: holes, regions, markers, size bounds") {
  PlanarMesh p;
  p.points = {{0, 0}, {10, 0}, {10, 10}, {0, 10}, {4, 4}, {6, 4}, {6, 6}, {4, 6}, {0, 2}, {10, 2}};
  p.segments = {{0, 1}, {1, 9}, {9, 2}, {2, 3}, {3, 8}, {8, 0}, {4, 5}, {5, 6}, {6, 7}, {7, 4}, {8, 9}};
  p.segment_markers = {1, 1, 1, 1, 1, 1, 2, 2, 2, 2, 3};
  p.holes = {{5, 5}};
  p.regions = {{{1, 1}, 10, -1}, {{1, 9}, 20, -1}};
  TriangulateOptions opt;
  opt.max_area = 0.5;
  const TriangulateResult t = triangulate_pslg(p, opt);
  const PlanarMesh& m = t.mesh;
  double area = 0;
  for (std::size_t i = 0; i < m.elements.size(); ++i) {
    const auto& e = m.elements[i];
    const Point2 &a = m.points[e[0]], &b = m.points[e[1]], &c = m.points[e[2]];
    const double A = ((b[0] - a[0]) * (c[1] - a[1]) - (c[0] - a[0]) * (b[1] - a[1])) / 2;
    REQUIRE(A > 0);
    CHECK(A <= 0.5 + 1e-12);
    area += A;
    CHECK(min_angle_deg(a, b, c) >= 20.7 - 1e-6);  // no small input angle here
    const double cy = (a[1] + b[1] + c[1]) / 3;
    CHECK(m.element_attributes[i][0] == (cy < 2 ? 10 : 20));
    const double cx = (a[0] + b[0] + c[0]) / 3;
    CHECK_FALSE((cx > 4 && cx < 6 && cy > 4 && cy < 6));  // the hole is empty
  }
  CHECK(std::abs(area - 96) < 1e-9);  // 10 x 10 minus the 2 x 2 hole
  // Subsegments carry their segment's marker, and so do their inner vertices.
  std::map<int, std::set<int>> vertices_of_marker;
  REQUIRE(m.segments.size() == m.segment_markers.size());
  for (std::size_t s = 0; s < m.segments.size(); ++s) {
    const Point2 a = m.points[m.segments[s][0]], b = m.points[m.segments[s][1]];
    const int mk = m.segment_markers[s];
    const double mx = (a[0] + b[0]) / 2, my = (a[1] + b[1]) / 2;
    if (mk == 2) CHECK(std::max(std::abs(mx - 5), std::abs(my - 5)) == Approx(1.0));
    if (mk == 3) CHECK(my == Approx(2.0));
  }
  for (std::size_t v = 0; v < m.points.size(); ++v) {
    const Point2 q = m.points[v];
    const bool on_box = q[0] == 0 || q[0] == 10 || q[1] == 0 || q[1] == 10;
    const bool on_hole = std::abs(std::max(std::abs(q[0] - 5), std::abs(q[1] - 5)) - 1) < 1e-12;
    const bool on_mid = std::abs(q[1] - 2) < 1e-12 && !on_box;
    if (on_hole) CHECK(m.point_markers[v] == 2);
    else if (on_mid) CHECK(m.point_markers[v] == 3);
    else if (on_box && q[1] != 2) CHECK(m.point_markers[v] == 1);
    else if (!on_box) CHECK(m.point_markers[v] == 0);
  }
}

TEST_CASE("triangulate: bad PSLGs are errors") {
  PlanarMesh p;
  p.points = {{0, 0}, {2, 2}, {2, 0}, {0, 2}};
  p.segments = {{0, 1}, {2, 3}};  // crossing
  CHECK_THROWS_AS(triangulate_pslg(p), Error);
  p.segments = {{0, 1}, {1, 0}};  // the same segment twice (overlap)
  CHECK_THROWS_AS(triangulate_pslg(p), Error);
  PlanarMesh q;
  q.points = {{0, 0}, {1, 0}, {1, 0}, {0, 1}};
  q.segments = {{1, 2}};  // zero length
  CHECK_THROWS_AS(triangulate_pslg(q), Error);
  PlanarMesh open;
  open.points = {{0, 0}, {1, 0}, {0, 1}};
  open.segments = {{0, 1}};  // encloses nothing
  CHECK_THROWS_AS(triangulate_pslg(open), Error);
  PlanarMesh tri;
  tri.points = {{0, 0}, {1, 0}, {0, 1}};
  tri.segments = {{0, 1}, {1, 2}, {2, 0}};
  TriangulateOptions bad;
  bad.min_angle = 40;
  CHECK_THROWS_AS(triangulate_pslg(tri, bad), Error);
  CHECK(triangulate_pslg(tri).mesh.elements.size() >= 1);
}

TEST_CASE("results report their bounds and say which guarantee failed", "[stats]") {
  // A square with a hole and a region: the report counts the input's.
  PlanarMesh p;
  p.points = {{0, 0}, {10, 0}, {10, 10}, {0, 10}, {4, 4}, {6, 4}, {6, 6}, {4, 6}};
  p.segments = {{0, 1}, {1, 2}, {2, 3}, {3, 0}, {4, 5}, {5, 6}, {6, 7}, {7, 4}};
  p.holes = {{5, 5}};
  p.regions = {{{1, 1}, 3, -1}};
  TriangulateOptions opt;
  opt.min_angle = 25;
  TriangulateResult t = triangulate_pslg(p, opt);
  INFO(t.failed_guarantee());
  CHECK(t.failed_guarantee().empty());
  Json j = t.to_json();
  CHECK(j.at("holes").integer() == 1);
  CHECK(j.at("regions").integer() == 1);
  CHECK(j.at("min_angle_bound").number() == 25);
  CHECK(j.at("triangles").integer() == long(t.mesh.elements.size()));
  // What the checks read: the vertex limit, an angle below the bound away
  // from small input angles (none below it near them counts).
  TriangulateResult u = t;
  u.limit_reached = true;
  CHECK(u.failed_guarantee().find("vertex limit") != std::string::npos);
  u = t;
  u.min_angle_away_from_small_input_angles = 24.9;
  CHECK(u.failed_guarantee().find("below the bound") != std::string::npos);
  u.min_angle_bound = 0;  // no quality asked: nothing to fail
  CHECK(u.failed_guarantee().empty());

  const LabelImage img = make_image(12, 10, [](int x, int y) { return (x - 5) * (x - 5) + (y - 5) * (y - 5) < 12; });
  ImagePslgOptions po;
  po.tolerance = 0.5;
  ImagePslgResult r = image_to_pslg(img, po);
  CHECK(r.hausdorff <= 0.5 + 1e-9);
  CHECK(r.failed_guarantee().empty());
  CHECK(r.to_json().at("tolerance").number() == 0.5);
  CHECK(r.to_json().at("width").integer() == 12);
  r.hausdorff = 0.75;  // what the check reads
  CHECK_FALSE(r.failed_guarantee().empty());
}
