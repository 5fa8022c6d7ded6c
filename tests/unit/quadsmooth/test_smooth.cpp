// quadsmooth's loop, through smooth_quad_mesh (lib/quadsmooth/smooth.cpp):
// property tests on random quad meshes. The random meshes are made here: a
// jittered grid cut into triangles, each triangle split into three quads
// through its centroid and edge midpoints (strictly convex for any
// non-degenerate triangle), with two regions and constraint segments. Each
// room's own operations are tested in test_smooth_<room>.cpp.
#include "smooth_test_support.hpp"

#include "quad/predicates.hpp"
#include "quadsmooth/smooth.hpp"

#include <catch2/catch.hpp>

#include <algorithm>
#include <map>
#include <random>
#include <set>

using namespace imgmesh;
using namespace quadsmooth_test;

namespace {

// n x n cells on [0,1]^2; region 1 left of x = 0.5, region 2 right; the outer
// boundary (marker 1) and the region boundary (marker 2) are segments.
// Each point carries 1 + its original index as attribute, to follow it through.
PlanarMesh split_mesh(int n, unsigned seed, double jitter = 0.3) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> U(-jitter, jitter);
  PlanarMesh m;
  const double h = 1.0 / n;
  auto id = [&](int i, int j) { return j * (n + 1) + i; };
  for (int j = 0; j <= n; ++j)
    for (int i = 0; i <= n; ++i) {
      double x = i * h, y = j * h;
      // Jitter interior grid points, but keep the column x = 0.5 straight
      // (the region boundary) by jittering only y there.
      if (i > 0 && i < n && j > 0 && j < n) {
        if (2 * i != n) x += U(rng) * h;
        y += U(rng) * h;
      }
      m.points.push_back({x, y});
    }
  std::vector<std::array<int, 3>> tris;
  std::vector<int> tri_region;
  std::bernoulli_distribution coin(0.5);
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      const int a = id(i, j), b = id(i + 1, j), c = id(i + 1, j + 1), d = id(i, j + 1);
      if (coin(rng)) { tris.push_back({a, b, c}); tris.push_back({a, c, d}); }
      else { tris.push_back({a, b, d}); tris.push_back({b, c, d}); }
      tri_region.push_back(2 * i < n ? 1 : 2);
      tri_region.push_back(2 * i < n ? 1 : 2);
    }
  std::map<std::pair<int, int>, int> mid;
  auto midpoint = [&](int a, int b) {
    auto key = std::minmax(a, b);
    auto it = mid.find(key);
    if (it != mid.end()) return it->second;
    const int k = int(m.points.size());
    m.points.push_back({0.5 * (m.points[a][0] + m.points[b][0]), 0.5 * (m.points[a][1] + m.points[b][1])});
    mid[key] = k;
    return k;
  };
  for (std::size_t t = 0; t < tris.size(); ++t) {
    const auto [a, b, c] = tris[t];
    const int g = int(m.points.size());
    m.points.push_back({(m.points[a][0] + m.points[b][0] + m.points[c][0]) / 3,
                        (m.points[a][1] + m.points[b][1] + m.points[c][1]) / 3});
    const int ab = midpoint(a, b), bc = midpoint(b, c), ca = midpoint(c, a);
    for (auto q : {std::vector<int>{a, ab, g, ca}, {b, bc, g, ab}, {c, ca, g, bc}}) {
      m.elements.push_back(q);
      m.element_attributes.push_back({double(tri_region[t])});
    }
  }
  // Segments: outer boundary and the region boundary, as quad edges.
  std::map<std::pair<int, int>, int> count;
  for (const auto& e : m.elements)
    for (int i = 0; i < 4; ++i) ++count[std::minmax(e[i], e[(i + 1) % 4])];
  for (const auto& [k, c] : count) {
    const auto& p = m.points[k.first];
    const auto& q = m.points[k.second];
    if (c == 1) { m.segments.push_back({k.first, k.second}); m.segment_markers.push_back(1); }
    else if (p[0] == 0.5 && q[0] == 0.5) { m.segments.push_back({k.first, k.second}); m.segment_markers.push_back(2); }
  }
  // Attribute 1 + the original index (points the clean-up adds get 0).
  for (std::size_t v = 0; v < m.points.size(); ++v) m.point_attributes.push_back({double(v + 1)});
  return m;
}

std::set<std::pair<int, int>> edge_set(const PlanarMesh& m) {
  std::set<std::pair<int, int>> s;
  for (const auto& e : m.elements)
    for (int i = 0; i < 4; ++i) s.insert(std::minmax(e[i], e[(i + 1) % 4]));
  return s;
}

} // namespace

TEST_CASE("smoothing keeps quads strictly convex, conforming, on their curves", "[smooth]") {
  for (unsigned seed : {1u, 2u, 3u, 4u}) {
    for (bool cleanup : {false, true}) {
      for (bool slide : {false, true}) {
        CAPTURE(seed, cleanup, slide);
        PlanarMesh m = split_mesh(8 + int(seed) * 2, seed);
        const PlanarMesh orig = m;
        SmoothOptions opt;
        opt.iterations = 8;
        opt.cleanup = cleanup;
        opt.slide_boundary = slide;
        const SmoothStats st = smooth_quad_mesh(m, opt);

        // Conforming, counter-clockwise, strictly convex.
        REQUIRE_NOTHROW(check_quad_mesh(m));
        for (const auto& e : m.elements) {
          REQUIRE(e.size() == 4);
          REQUIRE(is_strictly_convex(m.points[e[0]], m.points[e[1]], m.points[e[2]], m.points[e[3]]));
        }
        CHECK(st.after.non_convex == 0);
        // The domain and each region keep their area: with all quads
        // counter-clockwise and convex this also rules out overlaps.
        CHECK(region_area(m, 1) == Approx(region_area(orig, 1)).epsilon(1e-12));
        CHECK(region_area(m, 2) == Approx(region_area(orig, 2)).epsilon(1e-12));
        // The guard never lets the worst quad get worse.
        CHECK(st.after.min_mu >= st.before.min_mu - 1e-9);
        if (!cleanup) CHECK(m.elements.size() == orig.elements.size());
        CHECK(m.element_attributes.size() == m.elements.size());
        REQUIRE(m.point_attributes.size() == m.points.size());

        // Constrained vertices: fixed, or (slide) on their own straight line.
        // Points added by pair splits lie strictly inside a region.
        for (std::size_t v = 0; v < m.points.size(); ++v) {
          const int o = int(m.point_attributes[v][0]) - 1;
          const Point2 p = m.points[v];
          if (o < 0) {
            CHECK(p[0] > 0); CHECK(p[0] < 1); CHECK(p[1] > 0); CHECK(p[1] < 1); CHECK(p[0] != 0.5);
            continue;
          }
          const Point2 q = orig.points[o];
          const bool outer = q[0] == 0 || q[0] == 1 || q[1] == 0 || q[1] == 1;
          const bool inner = q[0] == 0.5;
          if (!outer && !inner) continue;
          if (!slide) {
            CHECK(p == q);
          } else {
            // Same side of the square (exactly), or still on x = 0.5 (exactly).
            if (q[0] == 0 || q[0] == 1 || q[0] == 0.5) CHECK(p[0] == q[0]);
            if (q[1] == 0 || q[1] == 1) CHECK(p[1] == q[1]);
            CHECK(p[0] >= 0); CHECK(p[0] <= 1); CHECK(p[1] >= 0); CHECK(p[1] <= 1);
          }
        }
        // Corners never move.
        std::size_t corners = 0;
        for (std::size_t v = 0; v < m.points.size(); ++v) {
          const int o = int(m.point_attributes[v][0]) - 1;
          if (o < 0) continue;
          const Point2 q = orig.points[o];
          if ((q[0] == 0 || q[0] == 1) && (q[1] == 0 || q[1] == 1)) { CHECK(m.points[v] == q); ++corners; }
        }
        CHECK(corners == 4);
        // Every segment is still an edge of the mesh, markers kept.
        const auto edges = edge_set(m);
        REQUIRE(m.segments.size() == orig.segments.size());
        CHECK(m.segment_markers == orig.segment_markers);
        for (const auto& s : m.segments) CHECK(edges.count(std::minmax(s[0], s[1])) == 1);
      }
    }
  }
}

TEST_CASE("clean-up and smoothing of tri2quad outputs keep every guarantee", "[smooth]") {
  // Random meshes through tri2quad: the clean-up's swaps, splits and
  // collapses all run here; every result must stay strictly convex and
  // conforming, keep each region's area, every constraint vertex and every
  // segment, and never lower the worst mu.
  SmoothStats total;
  for (unsigned seed = 1; seed <= 200; ++seed) {
    const int n = 4 + 2 * int(seed % 5);
    PlanarMesh m = tri2quad_mesh(n, seed);
    const PlanarMesh orig = m;
    SmoothOptions opt;
    opt.iterations = 6;
    opt.split_below = seed % 2 ? 15 : 30;  // the default, and many more splits
    const SmoothStats st = smooth_quad_mesh(m, opt);
    CAPTURE(seed, n, opt.split_below);
    REQUIRE_NOTHROW(check_quad_mesh(m));
    for (const auto& e : m.elements)
      REQUIRE(is_strictly_convex(m.points[e[0]], m.points[e[1]], m.points[e[2]], m.points[e[3]]));
    CHECK(region_area(m, 1) == Approx(region_area(orig, 1)).epsilon(1e-12));
    CHECK(region_area(m, 2) == Approx(region_area(orig, 2)).epsilon(1e-12));
    CHECK(st.after.min_mu >= st.before.min_mu - 1e-9);
    REQUIRE(m.element_attributes.size() == m.elements.size());
    REQUIRE(m.point_attributes.size() == m.points.size());
    // Each quad keeps the attribute of its side of x = 1/2.
    for (std::size_t e = 0; e < m.elements.size(); ++e) {
      double cx = 0;
      for (int v : m.elements[e]) cx += m.points[v][0] / 4;
      CHECK(m.element_attributes[e][0] == (cx < 0.5 ? 1.0 : 2.0));
    }
    // Vertices on a segment keep their place; added points are off them.
    std::set<int> on_segment;
    for (const auto& sg : orig.segments) on_segment.insert({sg[0], sg[1]});
    std::size_t kept = 0;
    for (std::size_t v = 0; v < m.points.size(); ++v) {
      const int o = int(m.point_attributes[v][0]) - 1;
      if (o >= 0 && on_segment.count(o)) { CHECK(m.points[v] == orig.points[o]); ++kept; }
      if (o < 0) CHECK(m.points[v][0] != 0.5);
    }
    CHECK(kept == on_segment.size());
    const auto edges = edge_set(m);
    REQUIRE(m.segments.size() == orig.segments.size());
    CHECK(m.segment_markers == orig.segment_markers);
    for (const auto& sg : m.segments) CHECK(edges.count(std::minmax(sg[0], sg[1])) == 1);
    total.swaps += st.swaps;
    total.valence_swaps += st.valence_swaps;
    total.splits += st.splits;
    total.splits_four += st.splits_four;
    total.collapses += st.collapses;
  }
  // The operations the guarantees are about did run.
  CHECK(total.valence_swaps > 0);
  CHECK(total.splits > 0);
  CHECK(total.splits_four > 0);
  CHECK(total.collapses > 0);
}

TEST_CASE("smoothing improves split meshes", "[smooth]") {
  // Each triangle's three quads: valence-3 centroids and valence-6 corners
  // cap the reachable quality, so only improvement and the floor are asked.
  for (unsigned seed : {11u, 12u}) {
    double mean_without = 0, share_without = 0;
    for (bool cleanup : {false, true}) {
      PlanarMesh m = split_mesh(20, seed);
      SmoothOptions opt;
      opt.iterations = 10;
      opt.cleanup = cleanup;
      const SmoothStats st = smooth_quad_mesh(m, opt);
      CAPTURE(seed, cleanup, st.before.min_mu, st.before.mean_mu, st.after.min_mu, st.after.mean_mu);
      CHECK(st.after.mean_mu >= st.before.mean_mu + 2);
      CHECK(st.after.min_mu >= 5);
      CHECK(st.after.angles_45_135 > st.before.angles_45_135);
      // Smoothing evens the sizes out; the clean-up changes the quad count.
      if (!cleanup) {
        CHECK(st.after.area_stddev <= st.before.area_stddev);
        mean_without = st.after.mean_mu;
        share_without = st.after.angles_45_135;
      } else {
        // Valence-driven swaps (valence-6 corners, valence-3 centroids) and
        // pair splits take place and pay off.
        CHECK(st.valence_swaps > 0);
        CHECK(st.splits > 0);
        CHECK(st.after.mean_mu > mean_without);
        CHECK(st.after.angles_45_135 > share_without);
      }
    }
  }
}

TEST_CASE("smoothing reaches the quality targets on distorted grids", "[smooth]") {
  for (unsigned seed : {21u, 23u, 25u}) {
    PlanarMesh m = jittered_grid(30, seed);
    const auto before = quality_report(m);
    SmoothOptions opt;
    opt.iterations = 10;
    const SmoothStats st = smooth_quad_mesh(m, opt);
    CAPTURE(seed, before.min_mu, before.mean_mu, st.after.min_mu, st.after.mean_mu, before.non_convex);
    REQUIRE(before.non_convex == 0);
    CHECK(before.mean_mu < 30);  // the test starts below the bar
    CHECK(st.after.non_convex == 0);
    CHECK(st.after.min_mu >= 5);
    CHECK(st.after.mean_mu >= 30);
  }
}

TEST_CASE("same input, same output", "[smooth]") {
  PlanarMesh a = split_mesh(10, 7), b = split_mesh(10, 7);
  SmoothOptions opt;
  smooth_quad_mesh(a, opt);
  smooth_quad_mesh(b, opt);
  CHECK(a.points == b.points);
  CHECK(a.elements == b.elements);
}

TEST_CASE("the output does not depend on the number of threads", "[smooth]") {
  // Large enough for colour classes to be split over threads.
  PlanarMesh a = jittered_grid(150, 3), b = a;
  SmoothOptions opt;
  opt.iterations = 4;
  opt.threads = 1;
  const SmoothStats sa = smooth_quad_mesh(a, opt);
  opt.threads = 3;
  const SmoothStats sb = smooth_quad_mesh(b, opt);
  CHECK(a.points == b.points);
  CHECK(a.elements == b.elements);
  CHECK(sa.moves == sb.moves);
  CHECK(sa.moves > 0);
}

TEST_CASE("a quad that comes in non-convex is never made worse", "[smooth]") {
  PlanarMesh m = split_mesh(6, 5, 0.0);
  // Push one interior centroid point until a quad around it is non-convex.
  int v = -1;
  for (std::size_t e = 0; e < m.elements.size() && v < 0; ++e) {
    const auto& p = m.points[m.elements[e][2]];
    if (p[0] > 0.3 && p[0] < 0.45 && p[1] > 0.3 && p[1] < 0.7) v = m.elements[e][2];
  }
  REQUIRE(v >= 0);
  m.points[v][0] += 0.06;
  const auto before = quality_report(m);
  REQUIRE(before.non_convex >= 1);
  SmoothOptions opt;
  const SmoothStats st = smooth_quad_mesh(m, opt);
  CHECK(st.after.non_convex <= before.non_convex);
  REQUIRE_NOTHROW(check_quad_mesh(m));
}

TEST_CASE("the failed guarantee is a quad not strictly convex after", "[smooth]") {
  PlanarMesh m = split_mesh(6, 1);
  const SmoothStats ok = smooth_quad_mesh(m, SmoothOptions{});
  CHECK(ok.failed_guarantee().empty());
  PlanarMesh dart;
  dart.points = {{0, 0}, {2, 0}, {0.5, 0.5}, {0, 2}};  // reflex at (0.5, 0.5), all fixed
  dart.elements = {{0, 1, 2, 3}};
  const SmoothStats st = smooth_quad_mesh(dart, SmoothOptions{});
  CHECK(st.after.non_convex == 1);
  CHECK(st.failed_guarantee() == "1 quad(s) are not strictly convex (they came in that way)");
  SmoothStats made = st;
  made.before.non_convex = 0;
  CHECK(made.failed_guarantee() == "1 quad(s) made non-convex");
}
