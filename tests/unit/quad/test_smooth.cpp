// quadsmooth's library: property tests on random quad meshes, and each
// clean-up operation called alone on a small hand-made mesh. The random
// meshes are made here: a jittered grid cut into triangles, each triangle
// split into three quads through its centroid and edge midpoints (strictly
// convex for any non-degenerate triangle), with two regions and constraint
// segments.
#include "quadsmooth/smooth.hpp"

#include "quad/quality.hpp"
#include "quadsmooth/smooth_mesh.hpp"
#include "tri2quad/tri2quad.hpp"
#include "util/error.hpp"

#include <catch2/catch.hpp>

#include <cmath>
#include <map>
#include <random>
#include <set>

using namespace imgmesh;

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

// An n x n grid of [0,1]^2 with every interior node thrown up to 0.3 cells
// away (all quads stay convex).
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

// tri2quad's output for a random triangle mesh: an n x n jittered grid of
// [0,1]^2 cut along random diagonals, region 1 left of x = 1/2 and region 2
// right of it (that column straight, and a constraint), boundary marker 1,
// constraint marker 2. Points carry 1 + their index as attribute.
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

TEST_CASE("the mean pass raises the mean mu and lowers no quad below the worst around it", "[smooth]") {
  // The same smoothing with and without the mean pass, which runs last: it
  // moves a vertex only to raise the sum of sin(mu) of its star, no quad of
  // the star below the star's worst, none non-convex; so the whole mesh's
  // sum of sin(mu) rises and its worst mu stays.
  double gain = 0;
  std::size_t climbs = 0;
  for (unsigned seed = 1; seed <= 40; ++seed) {
    const int n = 4 + 2 * int(seed % 5);
    PlanarMesh with = tri2quad_mesh(n, seed), without = with;
    SmoothOptions opt;
    opt.iterations = 6;
    opt.mean_rounds = 0;
    opt.grading = 0;  // its collapses and splits would follow the mean pass's moves
    const SmoothStats s0 = smooth_quad_mesh(without, opt);
    opt.mean_rounds = 3;
    const SmoothStats s1 = smooth_quad_mesh(with, opt);
    CAPTURE(seed, n, s0.after.min_mu, s1.after.min_mu, s0.after.mean_mu, s1.after.mean_mu);
    REQUIRE(with.elements == without.elements);  // the pass moves vertices only
    REQUIRE_NOTHROW(check_quad_mesh(with));
    double sin0 = 0, sin1 = 0;
    for (std::size_t e = 0; e < with.elements.size(); ++e) {
      const auto& q = with.elements[e];
      REQUIRE(is_strictly_convex(with.points[q[0]], with.points[q[1]], with.points[q[2]], with.points[q[3]]));
      const auto mu = [&](const PlanarMesh& m) {
        return joe_mu(m.points[q[0]], m.points[q[1]], m.points[q[2]], m.points[q[3]]);
      };
      sin0 += std::sin(mu(without) * M_PI / 180);
      sin1 += std::sin(mu(with) * M_PI / 180);
    }
    CHECK(s1.after.min_mu >= s0.after.min_mu - 1e-9);
    CHECK(sin1 >= sin0 - 1e-9);
    CHECK((s1.mean_climbs > 0) == (sin1 > sin0 + 1e-9));
    // Segment vertices stay.
    for (const auto& sg : with.segments)
      for (int v : sg) CHECK(with.points[v] == without.points[v]);
    gain += s1.after.mean_mu - s0.after.mean_mu;
    climbs += s1.mean_climbs;
  }
  CHECK(climbs > 0);
  CHECK(gain / 40 >= 0.5);  // degrees of mean mu, on average
}

TEST_CASE("a strip with every corner fixed and two flat corners is split into four", "[smooth]") {
  // Two quads (u, w, a, b) and (w, u, c, d) whose six corners all lie on the
  // boundary, so nothing can move: b, u, w, d nearly on one line, a flat
  // corner at u in the first quad and at w in the second (mu about 2
  // degrees). No swap and no split around one point keeps them convex (the
  // hexagon's angle at u or w would pass 180 degrees); the four-quad split
  // joins u and w to two new points.
  PlanarMesh m;
  m.points = {{0, 0}, {3, 1}, {0.5, 2.5}, {-3, -0.9}, {2.5, -1.5}, {6, 1.9}};  // u, w, a, b, c, d
  m.elements = {{0, 1, 2, 3}, {1, 0, 4, 5}};
  m.element_attributes = {{7}, {7}};
  const PlanarMesh orig = m;
  SmoothOptions opt;
  const SmoothStats st = smooth_quad_mesh(m, opt);
  CAPTURE(st.before.min_mu, st.after.min_mu, st.after.quads);
  CHECK(st.before.min_mu < 5);
  CHECK(st.splits_four >= 1);
  CHECK(st.after.min_mu >= 5);
  REQUIRE_NOTHROW(check_quad_mesh(m));
  for (const auto& e : m.elements)
    REQUIRE(is_strictly_convex(m.points[e[0]], m.points[e[1]], m.points[e[2]], m.points[e[3]]));
  CHECK(region_area(m, 7) == Approx(region_area(orig, 7)).epsilon(1e-12));
  // The corners stay where they were, the new points come after them, and
  // the boundary is the same six edges.
  for (std::size_t v = 0; v < orig.points.size(); ++v) CHECK(m.points[v] == orig.points[v]);
  std::map<std::pair<int, int>, int> uses;
  for (const auto& e : m.elements)
    for (int i = 0; i < 4; ++i) ++uses[std::minmax(e[i], e[(i + 1) % 4])];
  std::set<std::pair<int, int>> boundary, boundary0;
  for (const auto& [k, c] : uses)
    if (c == 1) boundary.insert(k);
  for (const auto& e : orig.elements)
    for (int i = 0; i < 4; ++i)
      if (std::minmax(e[i], e[(i + 1) % 4]) != std::minmax(0, 1)) boundary0.insert(std::minmax(e[i], e[(i + 1) % 4]));
  CHECK(boundary == boundary0);
}

TEST_CASE("a sliver along a segment is opened by moving its two free corners together", "[smooth]") {
  // The square's bottom side A-B carries a sliver (A, B, v, u) with its free
  // corners u, v just above it (corners of about 174 degrees at u and v, mu
  // under 3): moving u or v alone away from A-B makes the other reflex, so
  // only the edge move opens it (as on the lung through poly2tri --lattice 2).
  PlanarMesh m;
  m.points = {{0, 0}, {4, 0}, {4, 3}, {0, 3}, {1, 0.1}, {3, 0.1}, {1, 2}, {3, 2}};  // A B C D u v p q
  m.elements = {{0, 1, 5, 4}, {0, 4, 6, 3}, {4, 5, 7, 6}, {5, 1, 2, 7}, {6, 7, 2, 3}};
  const PlanarMesh orig = m;
  SmoothOptions opt;
  const SmoothStats st = smooth_quad_mesh(m, opt);
  CAPTURE(st.before.min_mu, st.after.min_mu, st.edge_moves);
  CHECK(st.before.min_mu < 3);
  CHECK(st.edge_moves >= 1);
  CHECK(st.after.min_mu >= 15);
  REQUIRE_NOTHROW(check_quad_mesh(m));
  for (const auto& e : m.elements)
    REQUIRE(is_strictly_convex(m.points[e[0]], m.points[e[1]], m.points[e[2]], m.points[e[3]]));
  for (int v = 0; v < 4; ++v) CHECK(m.points[v] == orig.points[v]);  // the boundary stays
}

TEST_CASE("more pair splits: more quads, more of them with good angles", "[smooth]") {
  double share[2] = {0, 0};
  std::size_t quads[2] = {0, 0};
  for (unsigned seed = 1; seed <= 10; ++seed) {
    for (int k = 0; k < 2; ++k) {
      PlanarMesh m = tri2quad_mesh(12, seed);
      SmoothOptions opt;
      opt.split_below = k == 0 ? 15 : 30;
      const SmoothStats st = smooth_quad_mesh(m, opt);
      share[k] += st.after.angles_45_135;
      quads[k] += st.after.quads;
    }
  }
  CAPTURE(share[0], share[1], quads[0], quads[1]);
  CHECK(quads[1] > quads[0]);
  CHECK(share[1] > share[0]);
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

TEST_CASE("a doublet is removed when the merged quad is convex", "[smooth]") {
  // v = (1,1) sits on the diagonal of the square; two quads share v-a and v-c.
  PlanarMesh m;
  m.points = {{0, 0}, {2, 0}, {2, 2}, {0, 2}, {1, 1}};
  m.elements = {{4, 0, 1, 2}, {4, 2, 3, 0}};
  SmoothOptions opt;
  const SmoothStats st = smooth_quad_mesh(m, opt);
  CHECK(st.doublets == 1);
  REQUIRE(m.elements.size() == 1);
  REQUIRE(m.points.size() == 4);
  CHECK(st.after.non_convex == 0);
  CHECK(st.after.min_mu == Approx(45));
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

TEST_CASE("bad input is refused with a clear error", "[smooth]") {
  PlanarMesh m;
  m.points = {{0, 0}, {1, 0}, {1, 1}, {0, 1}, {2, 0}, {2, 1}};
  m.elements = {{0, 3, 2, 1}};  // clockwise
  CHECK_THROWS_AS(check_quad_mesh(m), Error);
  m.elements = {{0, 1, 2, 7}};  // id out of range
  CHECK_THROWS_AS(check_quad_mesh(m), Error);
  m.elements = {{0, 1, 2, 3}, {1, 4, 5, 2}, {0, 1, 2, 3}};  // edge in three elements... and same direction
  CHECK_THROWS_AS(check_quad_mesh(m), Error);
  m.elements = {{0, 1, 2, 3}, {0, 1, 5, 2}};  // 0-1 used twice in the same direction
  CHECK_THROWS_AS(check_quad_mesh(m), Error);
  m.elements = {};
  CHECK_THROWS_AS(check_quad_mesh(m), Error);
  m.elements = {{0, 1, 2, 3}};
  m.points[2][0] = std::nan("");
  CHECK_THROWS_AS(check_quad_mesh(m), Error);
  m.points[2][0] = 1;
  CHECK_NOTHROW(check_quad_mesh(m));
}

// ---- The clean-up operations one at a time, on small hand-made meshes ----

namespace {

// Everything an operation may change, to check that a refused one changed
// nothing.
struct State {
  std::vector<quadsmooth_detail::Quad> quads;
  std::vector<std::vector<int>> stars;
  std::vector<Point2> points;
  std::vector<double> sines;
  std::vector<char> quad_dead, vertex_dead;
  std::size_t elements;
};

State snapshot(const quadsmooth_detail::QuadMesh& qm) {
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

bool live_quads_strictly_convex(const quadsmooth_detail::QuadMesh& qm) {
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

// Undirected edges used by exactly one element.
std::set<std::pair<int, int>> boundary_edges(const PlanarMesh& m) {
  std::map<std::pair<int, int>, int> uses;
  for (const auto& e : m.elements)
    for (std::size_t i = 0; i < e.size(); ++i) ++uses[std::minmax(e[i], e[(i + 1) % e.size()])];
  std::set<std::pair<int, int>> s;
  for (const auto& [k, c] : uses)
    if (c == 1) s.insert(k);
  return s;
}

bool shares_edge(const quadsmooth_detail::QuadMesh& qm, int a, int b) {
  return qm.quad_with_edge(a, b) >= 0 && qm.quad_with_edge(b, a) >= 0;
}

} // namespace

TEST_CASE("doublet removal merges the two quads of a valence-2 vertex into a strictly convex one", "[smooth]") {
  // v = (1,1) on the diagonal of the square: its two quads have straight
  // angles at v; the merged quad is the square.
  PlanarMesh m;
  m.points = {{0, 0}, {2, 0}, {2, 2}, {0, 2}, {1, 1}};
  m.elements = {{4, 0, 1, 2}, {4, 2, 3, 0}};
  const SmoothOptions opt;
  quadsmooth_detail::QuadMesh qm(m, opt, quadsmooth_detail::conforming_stars(m, {}));
  REQUIRE_FALSE(qm.fixed[4]);
  CHECK_FALSE(quadsmooth_detail::remove_doublet(qm, 0));  // a corner of the square is fixed
  REQUIRE(quadsmooth_detail::remove_doublet(qm, 4));
  CHECK(qm.vertex_dead[4]);
  CHECK(qm.vertex_quads[4].empty());
  CHECK(live_quads_strictly_convex(qm));
  for (int x : {0, 1, 2, 3}) CHECK(qm.vertex_quads[x].size() == 1);
  qm.compact();
  REQUIRE(m.elements.size() == 1);
  REQUIRE(m.points.size() == 4);
  REQUIRE_NOTHROW(check_quad_mesh(m));
  CHECK(quad_mu(m, m.elements[0]) == Approx(45));
  CHECK(total_area(m) == Approx(4));
}

TEST_CASE("a sharp corner split by a valence-3 vertex is left one quad", "[smooth]") {
  // A convex hexagon c, h1..h5 with a 30-degree corner at c (every vertex
  // fixed, on the boundary) around the free m, whose three quads split c's
  // corner 17.7 / 12.3 degrees: the two quads (h5, c, h1, h2) and
  // (h2, h3, h4, h5) keep c's whole angle in one.
  PlanarMesh m;
  m.points = {{0, 0}, {3, 0}, {4.5, 0.6}, {5.6, 1.8}, {5.5, 2.9}, {3.9, 2.25}, {2.5, 0.8}};
  m.elements = {{6, 0, 1, 2}, {6, 2, 3, 4}, {6, 4, 5, 0}};
  const double area = total_area(m);
  const SmoothOptions opt;
  quadsmooth_detail::QuadMesh qm(m, opt, quadsmooth_detail::conforming_stars(m, {}));
  REQUIRE_FALSE(qm.fixed[6]);
  double worst_before = 2;
  for (double s : qm.quad_sin_mu) worst_before = std::min(worst_before, s);
  CHECK_FALSE(quadsmooth_detail::open_sharp_corner(qm, 0, false));  // c itself is fixed
  REQUIRE(quadsmooth_detail::open_sharp_corner(qm, 6, false));
  CHECK(qm.vertex_dead[6]);
  CHECK(qm.vertex_quads[0].size() == 1);
  CHECK(live_quads_strictly_convex(qm));
  qm.compact();
  REQUIRE(m.elements.size() == 2);
  REQUIRE(m.points.size() == 6);
  REQUIRE_NOTHROW(check_quad_mesh(m));
  CHECK(total_area(m) == Approx(area));
  for (const auto& e : m.elements) CHECK(std::sin(quad_mu(m, e) * (3.14159265358979323846 / 180)) > worst_before);
}

TEST_CASE("a sharp corner whose hexagon cannot be split in two gets m joined to the other corners", "[smooth]") {
  // From the brain slice's default chain (BrainT1Slice.png, threshold 100):
  // the quads within two edges of a free valence-3 vertex m (27) in a small
  // triangular region whose 30-degree corner c (0) it splits into two quads
  // of mu 7.4. Neither pair of quads keeping c whole is strictly convex
  // where the corners stand (one even corner of m's hexagon is reflex, one
  // has valence 3); joined to the odd corners, the doublet left merged and
  // the free corners placed, c is in one quad.
  PlanarMesh m;
  m.points = {{39.5, 86.5}, {40.863727286595285, 86.69040542337531}, {39.5, 88.5}, {41.5, 89.5}, {39.75, 89.75}, {38.5, 82.5}, {42.422234125883769, 82.473222085610871}, {39.207106781186546, 83.207106781186553}, {43.469397439496959, 83.019020405806799}, {38.5, 89.5}, {38.5, 88.75}, {42.5, 89.5}, {37, 84.5}, {44.5, 86}, {42.5, 84.5}, {41.360521018838128, 85.25965265410791}, {40.5, 84.5}, {38.5, 84.5}, {38.5, 83.5}, {38.009480519437616, 87.465555688699666}, {42.490276384099658, 87.536182301687148}, {43.5, 85.25}, {39.825925382886261, 82.994951273174976}, {39.597162515464618, 82.015540295897296}, {40.779453087501423, 82.011730862522668}, {40.749423976768092, 84.044192325832782}, {41.317964984007745, 84.914258515836593}, {40.557322207645946, 85.304739051210078}, {40.650196132588391, 84.797128909009245}, {41.062650482128596, 84.485627069503394}, {44.343113567214417, 84.298504846214044}, {45.328259264202806, 85.071064008859423}, {40.55421366050431, 89.138347142077393}, {42.002433154297869, 85.928189053427602}, {39.166945097641317, 83.779584413789593}, {39.56901827207011, 84.38068673870454}, {37.300488481250611, 85.626979968167817}, {41.84787946443786, 83.29604018607499}, {40.834898751563578, 83.008574305675253}, {41.336648959728144, 87.79405522440689}, {40.358086259142439, 88.146690268363329}, {38.255507234186609, 85.531921867380845}, {39.131512046103204, 85.428029468775946}, {38.744497856912666, 86.957934688543475}, {41.865988338236782, 84.393521404629027}, {41.563487020375867, 83.820810182762386}, {41.019398075804311, 83.575262684902896}};
  m.elements = {{7, 5, 23, 22}, {6, 8, 14, 37}, {16, 7, 22, 25}, {0, 16, 28, 27}, {45, 44, 26, 29}, {15, 0, 27, 26}, {27, 28, 29, 26}, {13, 21, 30, 31}, {4, 9, 10, 2}, {33, 21, 13, 20}, {20, 39, 1, 33}, {21, 33, 15, 14}, {0, 1, 39, 40}, {1, 0, 15, 33}, {7, 34, 18, 5}, {16, 35, 34, 7}, {17, 18, 34, 35}, {36, 12, 17, 41}, {17, 35, 42, 41}, {40, 2, 43, 0}, {29, 28, 16, 25}, {30, 21, 14, 8}, {37, 14, 44, 45}, {22, 23, 24, 38}, {20, 11, 3, 39}, {32, 4, 2, 40}, {35, 16, 0, 42}, {42, 0, 43, 41}, {2, 10, 19, 43}, {29, 25, 46, 45}, {14, 15, 26, 44}, {3, 32, 40, 39}, {43, 19, 36, 41}, {25, 22, 38, 46}, {38, 37, 45, 46}};
  const int regions[] = {1, 1, 1, 1, 1, 1, 1, 1, 1, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 1, 1, 1, 1, 0, 0, 0, 0, 0, 1, 1, 0, 0, 1, 1};
  for (int r : regions) m.element_attributes.push_back({double(r)});
  const double area = total_area(m);
  const SmoothOptions opt;
  quadsmooth_detail::QuadMesh qm(m, opt, quadsmooth_detail::conforming_stars(m, {}));
  REQUIRE(qm.fixed[0]);
  REQUIRE_FALSE(qm.fixed[27]);
  double worst_before = 2;
  for (double s : qm.quad_sin_mu) worst_before = std::min(worst_before, s);
  // c's fan in the region: the quads of c and m there.
  auto fan_of_c = [&] {
    for (std::size_t q = 0; q < qm.quads.size(); ++q) {
      const quadsmooth_detail::Quad& Q = qm.quads[q];
      if (!qm.quad_dead[q] && std::count(Q.begin(), Q.end(), 0) && std::count(Q.begin(), Q.end(), 27))
        return qm.fan(0, int(q)).count;
    }
    return -1;
  };
  REQUIRE(fan_of_c() == 2);
  CHECK_FALSE(quadsmooth_detail::open_sharp_corner(qm, 27, false));
  REQUIRE(quadsmooth_detail::open_sharp_corner(qm, 27, true));
  CHECK(fan_of_c() == 1);
  CHECK(live_quads_strictly_convex(qm));
  double worst_after = 2;
  for (std::size_t q = 0; q < qm.quads.size(); ++q)
    if (!qm.quad_dead[q]) worst_after = std::min(worst_after, qm.quad_sin_mu[q]);
  CHECK(worst_after > worst_before);
  qm.compact();
  REQUIRE_NOTHROW(check_quad_mesh(m));
  CHECK(total_area(m) == Approx(area));
}

TEST_CASE("a sharp corner whose hexagon splits only once its doublets merge gets one quad", "[smooth]") {
  // From the brain slice's default chain (BrainT1Slice.png, threshold 100):
  // the quads within three edges of a free valence-3 vertex m (3) that
  // splits the 33.7-degree wedge tip c (0) of the curve into two quads of
  // mu 8.4. Neither split of m's hexagon keeping c whole is strictly
  // convex where the corners stand (the free corners sit on the wedge's
  // sides), nor is m joined to the other corners; with the corners it
  // leaves in two quads merged away (two doublets in turn) and the rest
  // placed, c is in one quad and the patch's worst mu rises.
  PlanarMesh m;
  m.points = {{134.5, 68.5}, {133, 69.5}, {133.11321856517085, 69.157669638416536}, {133.60011083221232, 68.774311985288975}, {132.697224362268, 68.5}, {133.09012872795734, 68.710101275373773}, {132.95936462106596, 68.951106799039636}, {133.5, 67.5}, {134.5, 67.5}, {134.85638858257479, 70.205779489841206}, {134.01390577604755, 70.566962290951892}, {135.5, 69.5}, {135.5, 68.5}, {135.5, 67.5}, {133.4108875661681, 71.163436016106161}, {132.33205029433785, 69.945299803774773}, {132.30446143259911, 69.398299818132898}, {132.67077458937047, 68.926947634449718}, {130.89444872453601, 68.5}, {131.5, 66.5}, {132.5, 66.5}, {133.1270474395665, 66.577281029717426}, {130.7143982866836, 69.079770557005347}, {134, 66.5}, {134.50669090936333, 66.740660481083964}, {133.41364362656535, 65.6242127279328}, {135.04107734492885, 66.428018312398137}, {135.7439592106833, 71.824024640692343}, {134.93594737560326, 72.24960217890299}, {136.7470196573083, 71.355959778754226}, {136.38240126097443, 70.220913643214658}, {136.5, 69.5}, {133.95595042531932, 72.423854681894269}, {136.23549468501645, 67.922039727545723}, {136.4816793431593, 68.654581894710347}, {136.94321206901466, 68.962577221913875}, {136.18933161332217, 67.102253702816242}, {135.63437353793032, 66.263677340315382}, {132.5, 71.5}, {131.5, 70.5}, {132.5, 72.5}, {131.5, 69.5}, {129.89526349109425, 67.167333423731691}, {130.42765454971396, 65.914528586624556}, {127.5, 68.5}, {128.2323176743179, 67.148540497490359}, {129.35555875936876, 69.346339464519147}, {130.78754554746155, 64.794730680031719}, {131.5, 65.5}, {132.5, 65.5}, {129.43610109757353, 70.325559560970589}};
  m.elements = {{0, 1, 2, 3}, {4, 0, 3, 5}, {3, 2, 6, 5}, {4, 7, 8, 0}, {0, 9, 10, 1}, {11, 9, 0, 12}, {0, 8, 13, 12}, {1, 10, 14, 15}, {2, 1, 15, 16}, {16, 17, 6, 2}, {18, 19, 20, 4}, {4, 5, 6, 17}, {7, 4, 20, 21}, {22, 18, 4, 17}, {8, 7, 23, 24}, {23, 7, 21, 25}, {13, 8, 24, 26}, {10, 9, 27, 28}, {29, 27, 9, 30}, {9, 11, 31, 30}, {28, 32, 14, 10}, {11, 12, 33, 34}, {35, 31, 11, 34}, {33, 12, 13, 36}, {13, 26, 37, 36}, {15, 14, 38, 39}, {14, 32, 40, 38}, {15, 39, 41, 16}, {17, 16, 41, 22}, {18, 42, 43, 19}, {44, 45, 42, 18}, {44, 18, 22, 46}, {19, 43, 47, 48}, {19, 48, 49, 20}, {20, 49, 25, 21}, {41, 50, 46, 22}};
  const int regions[] = {0, 0, 0, 1, 1, 1, 1, 1, 0, 0, 1, 0, 1, 0, 0, 1, 0, 1, 1, 1, 1, 0, 0, 0, 0, 1, 1, 0, 0, 1, 1, 0, 1, 0, 1, 0};
  for (int r : regions) m.element_attributes.push_back({double(r)});
  const double area = total_area(m);
  const SmoothOptions opt;
  quadsmooth_detail::QuadMesh qm(m, opt, quadsmooth_detail::conforming_stars(m, {}));
  REQUIRE(qm.fixed[0]);
  REQUIRE_FALSE(qm.fixed[3]);
  double worst_before = 2;
  for (double s : qm.quad_sin_mu) worst_before = std::min(worst_before, s);
  REQUIRE(worst_before < std::sin(8.5 * M_PI / 180));
  // c's fan in the wedge (region 0): its quads there.
  auto fan_of_c = [&] {
    int n = 0;
    for (std::size_t q = 0; q < qm.quads.size(); ++q) {
      const quadsmooth_detail::Quad& Q = qm.quads[q];
      if (!qm.quad_dead[q] && std::count(Q.begin(), Q.end(), 0) && m.element_attributes[qm.quad_element[q]][0] == 0) ++n;
    }
    return n;
  };
  REQUIRE(fan_of_c() == 2);
  CHECK_FALSE(quadsmooth_detail::open_sharp_corner(qm, 3, false));  // the in-pass way: both splits not convex
  const std::size_t quads_before = m.elements.size();
  REQUIRE(quadsmooth_detail::open_sharp_corner(qm, 3, true));
  CHECK(qm.vertex_dead[3]);
  CHECK(fan_of_c() == 1);
  CHECK(live_quads_strictly_convex(qm));
  double worst_after = 2;
  for (std::size_t q = 0; q < qm.quads.size(); ++q)
    if (!qm.quad_dead[q]) worst_after = std::min(worst_after, qm.quad_sin_mu[q]);
  CHECK(worst_after > std::sin(12 * M_PI / 180));
  for (int v = 0; v < int(qm.points.size()); ++v)
    if (qm.fixed[v]) CHECK_FALSE(qm.vertex_dead[v]);  // every fixed vertex kept
  qm.compact();
  CHECK(m.elements.size() == quads_before - 3);  // m's quad and the two doublets' quads
  REQUIRE_NOTHROW(check_quad_mesh(m));
  CHECK(total_area(m) == Approx(area));
}

TEST_CASE("a wedge tip held by two quads is re-quadded around it into one quad", "[smooth]") {
  // From BrainMidSagittalSlice.png (ITK's example data, threshold 100),
  // the README's chain as quadsmooth left it before the tip pass: the quads
  // within three rings of the 33.7-degree wedge tip c (0) of a thin
  // triangular region, which two quads of mu 8.42 hold (at most a quarter
  // of the tip's angle). No hexagon split can keep c whole there (the
  // corner left beside c's quad would be reflex): the wedge is re-quadded
  // from new inner points, c in one quad, every quad strictly convex.
  PlanarMesh m;
  m.points = {{111.5, 145.5}, {112.5, 147.5}, {112.5, 146.5}, {113.0, 146.5}, {112.98184630677157, 147.0037019875712}, {113.5, 146.5}, {113.33744045569131, 147.08757891345996}, {111.5, 143.697224362268}, {111.5, 142.5}, {113.5, 142.5}, {112.5, 144.0}, {112.0, 144.75}, {111.9209391247781, 144.60733769918207}, {111.93445100839702, 144.27002500474163}, {111.71220759053922, 144.79850510764297}, {111.6979603339515, 144.1619180744348}, {110.2608765754579, 144.14220552941643}, {110.31000821940917, 142.6969205682013}, {111.70491237502478, 145.80932275396012}, {111.35519633389336, 145.9855703777254}, {110.77587471012431, 145.56810055852785}, {111.5, 141.5}, {113.49761647132884, 141.4985122885908}, {115.01204682809062, 141.73448015138058}, {114.35896492523612, 143.0256745943553}, {112.07529143573558, 145.9384065883816}, {111.5, 146.5}, {111.54815603450737, 146.20855303919694}, {110.5, 146.5}, {113.05083456797908, 144.98678214175095}, {114.022796345197, 145.91177210009943}, {115.90967689156257, 144.60241327680896}, {109.61564930708457, 147.9678507262786}, {109.46637285880479, 146.3221403333244}, {110.5, 147.5}, {107.69475777401881, 147.99054885642732}, {108.28898074039476, 149.38600500096433}, {111.5, 147.5}, {110.5, 141.5}, {108.74041681079144, 144.4264715350496}, {108.46366279018274, 142.7211596182835}, {106.63909149406928, 145.57211416607487}, {106.82511977505763, 142.79729031171485}, {108.56756391861848, 141.0545876609398}, {106.96993719379546, 140.56785694051501}};
  m.elements = {{1, 2, 3, 4}, {3, 5, 6, 4}, {7, 8, 9, 10}, {10, 11, 12, 13}, {11, 0, 14, 12}, {0, 7, 15, 14}, {15, 13, 12, 14}, {7, 16, 17, 8}, {0, 18, 19, 20}, {21, 22, 9, 8}, {23, 24, 9, 22}, {25, 2, 26, 27}, {11, 25, 18, 0}, {26, 28, 19, 27}, {29, 30, 5, 3}, {31, 30, 29, 24}, {10, 9, 24, 29}, {29, 25, 11, 10}, {3, 2, 25, 29}, {32, 33, 28, 34}, {35, 33, 32, 36}, {10, 13, 15, 7}, {34, 28, 26, 37}, {17, 38, 21, 8}, {20, 19, 28, 33}, {17, 16, 39, 40}, {39, 33, 35, 41}, {2, 1, 37, 26}, {41, 42, 40, 39}, {43, 40, 42, 44}, {38, 17, 40, 43}, {33, 39, 16, 20}, {18, 25, 27, 19}, {16, 7, 0, 20}};
  const int regions[] = {0, 0, 0, 0, 0, 0, 0, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 0, 0, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1};
  for (int r : regions) m.element_attributes.push_back({double(r)});
  const double area = total_area(m);
  const SmoothOptions opt;
  quadsmooth_detail::QuadMesh qm(m, opt, quadsmooth_detail::conforming_stars(m, {}));
  REQUIRE(qm.fixed[0]);
  auto worst = [&] {
    double w = 2;
    for (std::size_t q = 0; q < qm.quads.size(); ++q)
      if (!qm.quad_dead[q]) w = std::min(w, qm.quad_sin_mu[q]);
    return w;
  };
  REQUIRE(worst() < std::sin(8.5 * M_PI / 180));
  // c's quads in the wedge (region 0).
  auto fan_of_c = [&] {
    std::vector<int> f;
    for (int q : qm.vertex_quads[0])
      if (m.element_attributes[qm.quad_element[q]][0] == 0) f.push_back(q);
    return f;
  };
  const std::vector<int> fan = fan_of_c();
  REQUIRE(fan.size() == 2);
  std::vector<char> fixed_before(qm.fixed.begin(), qm.fixed.end());
  REQUIRE(quadsmooth_detail::open_wedge_tip(qm, 0, fan[0], 3));
  CHECK(fan_of_c().size() == 1);
  CHECK(live_quads_strictly_convex(qm));
  CHECK(worst() > std::sin(10 * M_PI / 180));
  for (std::size_t v = 0; v < fixed_before.size(); ++v)
    if (fixed_before[v]) {
      CHECK_FALSE(qm.vertex_dead[v]);  // every fixed vertex kept, in place
      CHECK(qm.points[v] == m.points[v]);
    }
  qm.compact();
  REQUIRE_NOTHROW(check_quad_mesh(m));
  CHECK(total_area(m) == Approx(area));
  // The pass finds it too, and a tip already in one quad is left alone.
  PlanarMesh m2 = m;
  quadsmooth_detail::QuadMesh qm2(m2, opt, quadsmooth_detail::conforming_stars(m2, {}));
  SmoothStats st;
  quadsmooth_detail::tip_pass(qm2, st);
  CHECK(st.wedge_tips == 0);
}

TEST_CASE("the tip pass leaves a corner exactly as it was where no layout settles convex and better", "[smooth]") {
  // From BrainT1Slice.png's thesis chain (threshold 100, poly2tri
  // --square-lattice 0, tri2quad --pair-above 0) as quadsmooth leaves it
  // before the tip pass: the quads within four rings of (67.5, 187.5). The
  // fixed corner at (67.5, 189.5) is held by two quads where its angle
  // wants one, one of them of mu 11.6. The pass tries the layouts of its
  // patches; none is both strictly convex once settled and better, so
  // each is undone and the mesh comes back exactly (taken anyway, settle's
  // verdict ignored, one leaves a quad not strictly convex).
  PlanarMesh m;
  m.points = {{67.5, 187.5}, {71.92434197476152, 188.98119508960366}, {71.55526686637106, 188.8428505111552}, {71.5, 188.5}, {72.5, 188.5}, {71.22196301324922, 189.0244867685014}, {71.0, 189.5}, {70.5, 189.5}, {70.5, 188.5}, {72.5, 184.5}, {71.5, 186.5}, {71.25640381238179, 184.98406299207278}, {71.94638411277484, 183.6104999146164}, {69.21498585142508, 182.47100848914494}, {69.64831483301262, 182.90469360686268}, {69.5, 183.5}, {67.5, 183.5}, {69.25, 185.75}, {68.5, 185.5}, {69.0, 184.5}, {70.11597327329609, 185.1498818578001}, {70.34229757977208, 184.16397214440082}, {70.36672690075837, 185.69313920617515}, {70.0, 186.0}, {70.78559161186291, 185.51429352722067}, {70.63203888052759, 185.70408995621256}, {70.75, 186.25}, {70.61244507123939, 185.97928494211354}, {70.375, 186.125}, {70.4767765522418, 185.9958929033052}, {69.5, 186.5}, {69.5, 187.5}, {68.5, 187.5}, {68.5, 186.5}, {70.625, 189.8125}, {71.25, 189.875}, {68.16351395715074, 187.93504781199215}, {70.0, 189.75}, {69.78632458218897, 189.19724445793028}, {70.02821106446179, 187.81680163393173}, {68.7129335805424, 188.97320123395684}, {69.81059116590187, 186.23752414159603}, {71.64524585868455, 187.36309891855439}, {69.42250485095033, 186.05232676835334}, {69.722162645732, 186.09564398240187}, {67.88804677207284, 186.09552089992954}, {64.9603032779347, 185.91871880593035}, {66.5, 187.5}, {66.5, 189.5}, {63.5, 188.5}, {66.81930569701656, 185.17658594676774}, {72.35368593976118, 187.7401610852947}, {67.74037380477694, 184.97821850334003}, {68.02382231404262, 184.32483369339155}, {74.5, 184.5}, {73.66555132682507, 186.27371353464437}, {63.55947823328849, 184.6652435309326}, {62.5, 186.5}, {66.63100987259037, 182.19152855891394}, {64.6499774824675, 182.75390325446824}, {68.7681261025205, 181.11125473241702}, {62.63954959472813, 182.82001101938533}, {63.84323748213699, 180.7470642516706}, {58.5, 201.5}, {57.5, 199.5}, {58.5, 197.5}, {59.9808662121279, 199.56570339689142}, {66.5, 199.5}, {71.5, 202.5}, {67.96883470710365, 202.69927422256865}, {65.99777643830521, 201.0694094896599}, {57.5, 195.5}, {54.5, 199.5}, {70.6025885664492, 191.69121548593552}, {71.875, 189.9375}, {71.37439699910189, 191.34243081387723}, {64.40522157474271, 194.7304563857836}, {66.65218415665139, 192.5901427160862}, {68.44163416903021, 195.560397651818}, {70.58649985441957, 192.46625257595161}, {71.88181141378098, 191.85986184348687}, {70.56825404515786, 194.24132333264419}, {73.15650204525903, 196.88228901701666}, {72.31079083922191, 199.09056652259105}, {70.10356366602917, 191.24103408333627}, {67.5, 189.5}, {67.85715711019482, 191.34249285109618}, {73.03797841723062, 192.51489792822926}, {69.43905232913765, 191.29744402784738}, {61.145565185023955, 194.50822702430472}, {60.868331856557546, 190.05635616860977}, {60.5, 186.5}, {57.9014985121662, 191.22197303229}, {58.87540741546147, 193.80381074854182}, {57.12246680923886, 187.63661737125554}, {59.5, 184.5}, {56.31277315142337, 185.77382273017315}, {75.18894443560545, 187.210203510755}, {73.09461082254977, 187.4380978607177}, {66.47949025623596, 179.76883294352282}, {68.14073103391092, 179.17651101786686}, {75.15040868394227, 193.80018118094017}, {61.68124374672177, 184.26385282924315}};
  m.elements = {{1, 2, 3, 4}, {5, 6, 7, 8}, {9, 10, 11, 12}, {13, 14, 15, 16}, {17, 18, 19, 20}, {20, 19, 15, 21}, {22, 23, 17, 20}, {24, 25, 22, 20}, {25, 24, 26, 27}, {20, 21, 11, 24}, {11, 10, 26, 24}, {26, 28, 29, 27}, {30, 31, 32, 33}, {34, 7, 6, 35}, {0, 33, 32, 36}, {7, 34, 37, 38}, {31, 39, 38, 40}, {41, 28, 26, 39}, {26, 10, 42, 39}, {43, 17, 23, 44}, {44, 23, 28, 41}, {39, 31, 30, 41}, {30, 43, 44, 41}, {32, 31, 40, 36}, {43, 30, 33, 45}, {46, 47, 48, 49}, {47, 46, 50, 45}, {45, 18, 17, 43}, {4, 3, 42, 51}, {45, 33, 0, 47}, {18, 45, 50, 52}, {50, 16, 53, 52}, {10, 9, 54, 55}, {56, 46, 49, 57}, {58, 46, 56, 59}, {58, 16, 50, 46}, {60, 13, 16, 58}, {56, 61, 62, 59}, {63, 64, 65, 66}, {67, 68, 69, 70}, {65, 67, 70, 66}, {71, 65, 64, 72}, {73, 35, 74, 75}, {67, 76, 77, 78}, {79, 73, 75, 80}, {78, 81, 82, 83}, {73, 84, 34, 35}, {77, 48, 85, 86}, {79, 80, 87, 81}, {85, 48, 47, 0}, {81, 78, 77, 86}, {85, 37, 88, 86}, {76, 89, 90, 49}, {65, 89, 76, 67}, {49, 48, 77, 76}, {91, 57, 49, 90}, {92, 90, 89, 93}, {90, 92, 94, 91}, {95, 91, 94, 96}, {8, 3, 2, 5}, {28, 23, 22, 29}, {22, 25, 27, 29}, {42, 3, 8, 39}, {16, 15, 19, 53}, {19, 18, 52, 53}, {97, 98, 10, 55}, {99, 100, 60, 58}, {87, 101, 82, 81}, {37, 34, 84, 88}, {86, 88, 79, 81}, {88, 84, 73, 79}, {8, 7, 38, 39}, {42, 10, 98, 51}, {83, 68, 67, 78}, {89, 65, 71, 93}, {38, 37, 85, 40}, {61, 56, 57, 102}, {40, 85, 0, 36}, {57, 91, 95, 102}, {62, 99, 58, 59}};
  const int regions[] = {0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 1, 1, 1, 1, 1, 0, 0, 0, 0, 1, 1, 0, 0, 1, 1, 1, 1, 1};
  for (int r : regions) m.element_attributes.push_back({double(r)});
  const double area = total_area(m);
  const SmoothOptions opt;
  quadsmooth_detail::QuadMesh qm(m, opt, quadsmooth_detail::conforming_stars(m, {}));
  REQUIRE(live_quads_strictly_convex(qm));
  std::vector<char> fixed_before(qm.fixed.begin(), qm.fixed.end());
  std::vector<Point2> points_before = m.points;
  SmoothStats st;
  // The corner c at (67.5, 189.5): its fan holding a quad under 12 degrees
  // is two quads where its angle wants one, so the pass tries it.
  int c = -1;
  for (int v = 0; v < int(m.points.size()); ++v)
    if (m.points[v] == Point2{67.5, 189.5}) c = v;
  REQUIRE(c >= 0);
  REQUIRE(qm.fixed[c]);
  int fan_count = 0;
  for (int q : qm.vertex_quads[c])
    if (qm.quad_sin_mu[q] < std::sin(12 * M_PI / 180)) {
      const quadsmooth_detail::Fan f = qm.fan(c, q);
      if (!f.closed && f.ideal == 1) fan_count = f.count;
    }
  REQUIRE(fan_count == 2);
  const std::vector<std::vector<int>> elements_before = m.elements;
  quadsmooth_detail::tip_pass(qm, st);
  CHECK(live_quads_strictly_convex(qm));
  for (std::size_t v = 0; v < fixed_before.size(); ++v)
    if (fixed_before[v]) {
      CHECK_FALSE(qm.vertex_dead[v]);
      CHECK(qm.points[v] == points_before[v]);
    }
  qm.compact();
  REQUIRE_NOTHROW(check_quad_mesh(m));
  CHECK(total_area(m) == Approx(area));
  CHECK(st.wedge_tips == 0);
  CHECK(m.elements == elements_before);
  CHECK(m.points == points_before);
}

TEST_CASE("a collapse refused as the corners stand is taken once its patch is placed and climbed", "[smooth]") {
  // From the brain slice's default chain (BrainT1Slice.png, threshold 100),
  // after the smoothing passes: the quads within three edges of quad 0, in
  // the thin gap between a pixel square and the curve under it, where two
  // free vertices (2, 3) leave three quads of mu 8.4-9.0 (corners of 18
  // degrees at fixed vertices). collapse_quad refuses quad 0 both ways (one
  // leaves a doublet, the other is no better before relaxing); merged along
  // its diagonal, the patch placed, relaxed and climbed, the gap is two
  // quads of mu over 20.
  PlanarMesh m;
  m.points = {{38.5, 89.5}, {37.5, 89.5}, {37.158026649604679, 89.301354264159158}, {37.488288093810638, 89.171285120829012}, {38.5, 88.75}, {37.5, 89}, {39.75, 89.75}, {39.5, 88.5}, {40, 91}, {38.5, 90.5}, {37.5, 90.5}, {36.441269729051356, 90.439507767113341}, {36.5, 89.25}, {36.160347609401924, 90.146625559309896}, {37.960935252358901, 87.384918155529178}, {37.137461615988578, 87.680704410403308}, {38.734095612371782, 86.986909246255962}, {36.348917493882816, 88.238075278111324}, {40.578975492220692, 89.13909128977555}, {41.5, 89.5}, {40.87128426413517, 90.317691540673906}, {40.351924233226654, 88.138562414979361}, {40.638222063491455, 90.917526733229096}, {39.5, 86.5}, {40.25, 92.25}, {41.013458021497613, 91.40461253861352}, {38.55389386779455, 91.401566792165085}, {39.468159281483643, 91.684607162339688}, {39.897404715276473, 92.285746449702103}, {37.5, 91.5}, {36.5, 91.5}, {35.395210930161284, 91.062755380068211}, {35.274533602674836, 92.430591369946271}, {35.458507117887123, 90.496511045025841}, {35.5, 89.5}, {35.703952295048282, 88.39589206194772}, {35.596651427777445, 89.862096655056064}, {34.931417029595977, 90.214234951336238}, {37.29408845704787, 85.620579943965069}, {36.508547652965717, 86.260376257544607}, {38.250403935678108, 85.427631861382991}, {35.66139498111729, 86.896233366589087}, {39.131512046103204, 85.428029468775946}, {35.030135385645785, 87.593415355689871}, {41.349688730301217, 87.753624069282694}, {42.5, 90.5}, {41.780735495173246, 90.903677475866203}, {42.5, 89.5}, {41.233455720043651, 90.843421938798286}, {42.46660187485778, 87.471582563043413}, {40.861185974115614, 86.692127576357947}, {41.360521018838128, 85.25965265410791}, {42.008877864440535, 85.928189053427602}, {39.56901827207011, 84.38068673870454}, {40.5, 84.5}, {41.042493594270844, 84.750668473790313}, {40.5, 93.5}, {42.061470990346486, 92.307354951732421}, {42.5, 94.5}, {39.956851122325951, 93.563538582527457}, {41.92110324275987, 91.605516213799319}, {38.243015616286378, 92.145870747189505}, {37.5, 92.5}, {39.5, 92.5}, {38.5, 92.5}, {39.5, 94.085786437626908}, {36.5, 92.5}, {36.069220630939704, 92.751817315983956}, {34.5, 90.5}, {33.656284967899829, 91.614066359127676}, {35.5, 93.5}, {34.007770488239863, 93.601712079869358}, {36.5, 93.5}, {34.958432961685766, 89.534326661218472}, {35, 89.375}, {35.138844125640105, 89.714287685277057}, {35.208846503838274, 88.521320443942955}, {34.689371134330905, 88.037005837406525}, {34.5, 89.5}, {34.78524541359026, 89.602442662433262}};
  m.elements = {{0, 1, 2, 3}, {4, 0, 3, 5}, {6, 0, 4, 7}, {8, 9, 0, 6}, {10, 1, 0, 9}, {2, 1, 10, 11}, {5, 3, 2, 12}, {12, 2, 11, 13}, {14, 4, 5, 15}, {7, 4, 14, 16}, {15, 5, 12, 17}, {6, 18, 19, 20}, {18, 6, 7, 21}, {22, 8, 6, 20}, {21, 7, 16, 23}, {24, 8, 22, 25}, {26, 9, 8, 27}, {8, 24, 28, 27}, {29, 10, 9, 26}, {10, 29, 30, 11}, {31, 11, 30, 32}, {11, 31, 33, 13}, {12, 34, 35, 17}, {36, 34, 12, 13}, {13, 33, 37, 36}, {38, 14, 15, 39}, {16, 14, 38, 40}, {39, 15, 17, 41}, {42, 23, 16, 40}, {17, 35, 43, 41}, {19, 18, 21, 44}, {45, 46, 19, 47}, {19, 46, 48, 20}, {49, 47, 19, 44}, {20, 48, 25, 22}, {23, 50, 44, 21}, {50, 23, 51, 52}, {53, 54, 23, 42}, {51, 23, 54, 55}, {56, 24, 57, 58}, {24, 56, 59, 28}, {60, 57, 24, 25}, {46, 60, 25, 48}, {61, 62, 29, 26}, {63, 64, 61, 26}, {63, 26, 27, 28}, {65, 63, 28, 59}, {66, 30, 29, 62}, {30, 66, 67, 32}, {33, 31, 68, 37}, {32, 69, 68, 31}, {69, 32, 70, 71}, {72, 70, 32, 67}, {73, 74, 34, 75}, {34, 36, 37, 75}, {35, 34, 74, 76}, {77, 43, 35, 76}, {37, 68, 78, 79}, {37, 79, 73, 75}};
  const int regions[] = {1, 1, 1, 1, 0, 1, 1, 1, 0, 0, 0, 0, 0, 0, 0, 0, 1, 1, 1, 1, 1, 1, 0, 1, 1, 0, 0, 0, 0, 0, 0, 1, 0, 0, 0, 0, 0, 0, 1, 0, 1, 0, 0, 1, 1, 1, 1, 0, 1, 1, 1, 1, 1, 1, 1, 0, 0, 1, 1};
  for (int r : regions) m.element_attributes.push_back({double(r)});
  const double area = total_area(m);
  const SmoothOptions opt;
  quadsmooth_detail::QuadMesh qm(m, opt, quadsmooth_detail::conforming_stars(m, {}));
  REQUIRE_FALSE(qm.fixed[2]);
  REQUIRE_FALSE(qm.fixed[3]);
  const double worst_before = *std::min_element(qm.quad_sin_mu.begin(), qm.quad_sin_mu.end());
  REQUIRE(worst_before < std::sin(9 * M_PI / 180));
  SmoothStats st;
  CHECK_FALSE(quadsmooth_detail::collapse_quad(qm, 0, 0, st));
  CHECK_FALSE(quadsmooth_detail::collapse_quad(qm, 0, 1, st));
  const std::size_t quads_before = m.elements.size();
  REQUIRE((quadsmooth_detail::collapse_and_merge(qm, 0, 0) || quadsmooth_detail::collapse_and_merge(qm, 0, 1)));
  CHECK(live_quads_strictly_convex(qm));
  double worst_after = 2;
  for (std::size_t q = 0; q < qm.quads.size(); ++q)
    if (!qm.quad_dead[q]) worst_after = std::min(worst_after, qm.quad_sin_mu[q]);
  CHECK(worst_after > worst_before);
  double worst_gap = 2;  // the quads at the square's corner (1) above the gap
  for (int q : qm.vertex_quads[1]) worst_gap = std::min(worst_gap, qm.quad_sin_mu[q]);
  CHECK(worst_gap > std::sin(20 * M_PI / 180));
  for (int v = 0; v < int(qm.points.size()); ++v)
    if (qm.fixed[v]) CHECK_FALSE(qm.vertex_dead[v]);  // every fixed vertex kept
  qm.compact();
  CHECK(m.elements.size() == quads_before - 1);
  REQUIRE_NOTHROW(check_quad_mesh(m));
  CHECK(total_area(m) == Approx(area));
}

TEST_CASE("the final collapse merges the doublet it leaves where that lifts the worst mu", "[smooth]") {
  // From the brain slice's default chain (BrainT1Slice.png, threshold 100),
  // after the smoothing passes and the sharp-corner pass: the quads within
  // three edges of quad 0, at (118.3, 47.4), where free vertices leave
  // quads of mu 8.9 with 18-degree corners at fixed vertices. The final
  // collapse of one of them leaves a free vertex in two quads, merged too;
  // the worst mu rises and every quad stays strictly convex.
  PlanarMesh m;
  m.points = {{117.5, 47.5}, {118.5095658799068, 47.177604474362056}, {118.62536736240646, 47.324673564477528}, {118.5, 47.5}, {117.5, 46.75}, {118.5, 47}, {116.5, 47.5}, {116.5, 46.5}, {117.04080010132655, 47.925599993641846}, {116.5, 48}, {118.5, 49.5}, {119.5, 47.25}, {119.13224753735123, 47.796223711509882}, {119.39543768656608, 48.459632621999503}, {118.5, 45.5}, {116.5, 45.5}, {118.99180569100332, 45.990451132181683}, {119.62143269122659, 46.195463729217423}, {115.93215228099986, 46.616538864109629}, {115.79604782459526, 47.248357744915779}, {115.52699489114751, 47.861608783455061}, {115.80430260907434, 46.032489765477081}, {116.5, 48.5}, {115.53922606036643, 48.651908407804001}, {118.5, 50.5}, {116.5, 50.5}, {119.98126147254749, 49.341425107503078}, {119.29759707213188, 49.779938614655805}, {119.47949646155752, 51.133842522870793}, {120.5, 45.5}, {120.5, 47.5}, {120.94066159840575, 48.956404015055497}, {116.41954601287372, 43.552604509869745}, {115.07792359064466, 44.149486516512709}, {117.39420591095291, 42.850221909195511}, {118.5, 43.5}, {120.5, 44.5}, {114.98313651414497, 45.860711051258534}, {115.22796368155835, 46.482395743484432}, {114.88191652624907, 46.999888749207138}, {114.4411829520525, 47.676922390942281}, {113.9805724205183, 48.671586855891157}, {115.32089479163137, 50.197091056676094}, {113.6047323133475, 50.021818083680202}, {119.480219837687, 52.518933874664697}, {118.5, 53.5}, {117.5, 54}, {117.5, 52.252203759368179}, {116.5, 52.5}, {114.65282137773066, 52.538196400444562}, {120.18894266819511, 50.850457935005544}, {121.04219848233578, 50.542282617375939}, {120.33589911975477, 52.004088430381223}, {122.5, 46.5}, {122.05695508955466, 47.547351860779997}, {122.06147099034648, 44.307354951732428}, {122.24613984742329, 49.010232531275918}, {122.33995131350098, 50.618468834513521}};
  m.elements = {{0, 1, 2, 3}, {0, 4, 5, 1}, {6, 7, 4, 0}, {8, 9, 6, 0}, {0, 3, 10, 8}, {5, 11, 2, 1}, {3, 2, 11, 12}, {10, 3, 12, 13}, {14, 4, 7, 15}, {5, 4, 14, 16}, {17, 11, 5, 16}, {18, 7, 6, 19}, {19, 6, 9, 20}, {21, 15, 7, 18}, {10, 22, 9, 8}, {20, 9, 22, 23}, {10, 24, 25, 22}, {10, 13, 26, 27}, {24, 10, 27, 28}, {29, 30, 11, 17}, {13, 12, 11, 30}, {30, 31, 26, 13}, {32, 14, 15, 33}, {34, 35, 14, 32}, {29, 17, 16, 14}, {14, 35, 36, 29}, {33, 15, 21, 37}, {37, 21, 18, 38}, {18, 19, 39, 38}, {39, 19, 20, 40}, {20, 23, 41, 40}, {22, 25, 42, 23}, {23, 42, 43, 41}, {44, 45, 24, 28}, {24, 45, 46, 47}, {48, 25, 24, 47}, {25, 48, 49, 42}, {28, 27, 26, 50}, {26, 31, 51, 50}, {28, 50, 52, 44}, {53, 54, 30, 29}, {29, 36, 55, 53}, {31, 30, 54, 56}, {51, 31, 56, 57}};
  const int regions[] = {1, 1, 1, 0, 0, 1, 1, 1, 0, 0, 0, 1, 1, 1, 0, 1, 1, 1, 1, 0, 1, 1, 1, 1, 0, 0, 1, 1, 1, 1, 1, 1, 1, 1, 0, 0, 1, 1, 1, 1, 1, 0, 1, 1};
  for (int r : regions) m.element_attributes.push_back({double(r)});
  const double area = total_area(m);
  const SmoothOptions opt;
  quadsmooth_detail::QuadMesh qm(m, opt, quadsmooth_detail::conforming_stars(m, {}));
  auto worst_near = [&] {  // the worst mu of the quads within an edge of quad 0's corners
    double w = 2;
    for (std::size_t q = 0; q < qm.quads.size(); ++q)
      if (!qm.quad_dead[q] && std::hypot(qm.points[qm.quads[q][0]][0] - 118.3, qm.points[qm.quads[q][0]][1] - 47.4) < 1.5)
        w = std::min(w, qm.quad_sin_mu[q]);
    return w;
  };
  const double worst_before = worst_near();
  REQUIRE(worst_before < std::sin(9 * M_PI / 180));
  const std::size_t quads_before = m.elements.size(), points_before = m.points.size();
  SmoothStats st;
  quadsmooth_detail::final_collapse_pass(qm, st);
  CHECK(st.collapses >= 1);
  CHECK(live_quads_strictly_convex(qm));
  CHECK(worst_near() > std::sin(10 * M_PI / 180));
  for (int v = 0; v < int(qm.points.size()); ++v)
    if (qm.fixed[v]) CHECK_FALSE(qm.vertex_dead[v]);  // every fixed vertex kept
  qm.compact();
  CAPTURE(st.collapses, quads_before, m.elements.size(), points_before, m.points.size());
  CHECK(quads_before - m.elements.size() == 2 * st.collapses);  // each collapsed quad and its doublet's
  REQUIRE_NOTHROW(check_quad_mesh(m));
  CHECK(total_area(m) == Approx(area));
}

TEST_CASE("the final pair split lifts a quad under 10 degrees that the passes left", "[smooth]") {
  // From ITK's BrainProtonDensitySlice.png (threshold 100), the default
  // chain after the passes, the sharp-corner pass and the final collapse:
  // the quads within three edges of quad 2 (mu 9.6, every corner fixed) in
  // a channel between two curves, which the passes left (their last pair
  // splits ran before those). Split once more at the end, one of its pairs
  // becomes three or four quads and the worst mu rises over 10.
  PlanarMesh m;
  m.points = {{22.5, 90}, {22.5, 90.5}, {21.726959514814851, 90.275721155861902}, {21.899840596383623, 89.996690544025725}, {22.5, 89.5}, {21.869219696265745, 89.695867921651327}, {23.25, 90.75}, {23.375, 91.625}, {23.125, 89.875}, {22.826025714263022, 89.827626387334064}, {22.710910225661213, 89.534055157836605}, {24.706653082625614, 91.416966580419668}, {24.422570992690495, 90.57028557073761}, {24.172014575891101, 89.859726354943774}, {22.370768771795806, 92.134785754027988}, {23.5, 92.5}, {24.649389429980374, 92.650797587436742}, {21.499999999999996, 91}, {21.313205714935485, 90.604242362287593}, {21.614805782274626, 91.810869343401237}, {21.176776695296638, 89.469669914110085}, {20.853553390593273, 90.439339828220184}, {22.5, 89}, {23, 89}, {24.829026251635693, 89.153162869803324}, {23.919218230679036, 89.079507681202585}, {23.498549971365652, 88.815333229504077}, {26.035743028959253, 93.015039004231767}, {26.065297958474325, 90.768247892802492}, {25.74510803159626, 89.721049390515418}, {23.125, 94.375}, {22.007526268886384, 93.336212069767441}, {21.053006423598251, 92.379637261667526}, {24.555126988317223, 93.815305261748705}, {25.900954229466915, 94.577862896529837}, {20.5, 91.5}, {20.298092780217917, 88.292027139607612}, {21.5, 88.5}, {20.03416728397611, 89.844980960535679}, {20.376392972205871, 90.418570477508382}, {22.5, 88.5}, {20.181671499670617, 91.135634192195752}, {22.9375, 88.5625}, {23.483541657801474, 88.427400811894373}, {24.974206552171573, 87.822081680280704}, {26.967615074379825, 88.651886800182396}, {23.986546512471222, 88.227107213297955}, {27.237551786884808, 92.898887284618439}, {27.523374212272866, 94.899956199201398}, {27.219853222605256, 90.689440954858043}, {24.827128711585612, 97.161566394814258}, {22.75, 96.25}, {25.548471095691689, 95.785725196588174}, {20.672304948911922, 93.821153123609093}, {20.518962737549469, 92.794408638212403}, {19.842859058970468, 92.393484894807273}, {27.436840685888448, 96.814412855588813}, {19.76153186281255, 91.5321736961086}};
  m.elements = {{0, 1, 2, 3}, {4, 0, 3, 5}, {0, 6, 7, 1}, {8, 6, 0, 9}, {0, 4, 10, 9}, {11, 7, 6, 12}, {6, 8, 13, 12}, {14, 1, 7, 15}, {15, 7, 11, 16}, {1, 17, 18, 2}, {17, 1, 14, 19}, {20, 2, 18, 21}, {3, 2, 20, 5}, {4, 22, 23, 10}, {22, 4, 5, 20}, {24, 13, 8, 25}, {8, 23, 26, 25}, {23, 8, 9, 10}, {27, 16, 11, 28}, {29, 28, 11, 12}, {12, 13, 24, 29}, {30, 31, 14, 15}, {32, 19, 14, 31}, {30, 15, 16, 33}, {34, 33, 16, 27}, {21, 18, 17, 35}, {35, 17, 19, 32}, {36, 37, 20, 38}, {38, 20, 21, 39}, {20, 37, 40, 22}, {21, 35, 41, 39}, {40, 42, 23, 22}, {26, 23, 42, 43}, {24, 44, 45, 29}, {44, 24, 25, 46}, {46, 25, 26, 43}, {47, 48, 34, 27}, {28, 49, 47, 27}, {45, 49, 28, 29}, {50, 51, 30, 52}, {53, 31, 30, 51}, {34, 52, 30, 33}, {31, 53, 54, 32}, {54, 55, 35, 32}, {52, 34, 48, 56}, {35, 55, 57, 41}};
  const int regions[] = {1, 1, 0, 0, 0, 1, 1, 0, 1, 1, 0, 1, 1, 0, 1, 1, 1, 0, 1, 1, 1, 0, 0, 1, 1, 1, 0, 0, 0, 1, 0, 0, 1, 1, 1, 1, 1, 1, 1, 1, 0, 1, 0, 0, 1, 0};
  for (int r : regions) m.element_attributes.push_back({double(r)});
  const double area = total_area(m);
  const SmoothOptions opt;
  quadsmooth_detail::QuadMesh qm(m, opt, quadsmooth_detail::conforming_stars(m, {}));
  for (int x : qm.quads[2]) REQUIRE(qm.fixed[x]);
  REQUIRE(qm.quad_sin_mu[2] < std::sin(10 * M_PI / 180));
  const double worst_before = *std::min_element(qm.quad_sin_mu.begin(), qm.quad_sin_mu.end());
  const std::size_t points_before = m.points.size();
  SmoothStats st;
  quadsmooth_detail::final_split_pass(qm, st);
  CHECK(st.splits >= 1);
  CHECK(live_quads_strictly_convex(qm));
  double worst_after = 2;
  for (std::size_t q = 0; q < qm.quads.size(); ++q)
    if (!qm.quad_dead[q]) worst_after = std::min(worst_after, qm.quad_sin_mu[q]);
  CHECK(worst_after > std::max(worst_before, std::sin(10 * M_PI / 180)));
  qm.compact();
  CHECK(m.points.size() > points_before);  // every input vertex kept, new ones added
  REQUIRE_NOTHROW(check_quad_mesh(m));
  CHECK(total_area(m) == Approx(area));
}

TEST_CASE("the max-min climb raises the worst mu around a free vertex, every quad strictly convex", "[smooth]") {
  // Four unit squares around v = (1, 1), v pulled to (1.5, 1.3): its worst
  // quad has mu under 20 degrees; the square's centre is the max-min.
  PlanarMesh m;
  m.points = {{0, 0}, {1, 0}, {2, 0}, {0, 1}, {1.5, 1.3}, {2, 1}, {0, 2}, {1, 2}, {2, 2}};
  m.elements = {{0, 1, 4, 3}, {1, 2, 5, 4}, {3, 4, 7, 6}, {4, 5, 8, 7}};
  const SmoothOptions opt;
  quadsmooth_detail::QuadMesh qm(m, opt, quadsmooth_detail::conforming_stars(m, {}));
  REQUIRE_FALSE(qm.fixed[4]);
  const double worst_before = *std::min_element(qm.quad_sin_mu.begin(), qm.quad_sin_mu.end());
  REQUIRE(worst_before < std::sin(20 * 3.14159265358979323846 / 180));
  REQUIRE(quadsmooth_detail::raise_worst(qm, 4, 1.0));
  CHECK(live_quads_strictly_convex(qm));
  for (int q = 0; q < 4; ++q) CHECK(qm.quad_sin_mu[q] == Approx(qm.sin_mu_of(qm.quads[q])));
  CHECK(*std::min_element(qm.quad_sin_mu.begin(), qm.quad_sin_mu.end()) > worst_before + 0.2);
}

TEST_CASE("the max-min climb of two vertices never lowers the worst mu of their stars", "[smooth]") {
  // tri2quad's quads of random point sets: every edge with two free ends
  // of a quad under 12 degrees climbs; the worst mu of the two stars does
  // not drop, and every quad stays strictly convex.
  std::size_t moved = 0;
  for (unsigned seed = 1; seed <= 20; ++seed) {
    PlanarMesh m = tri2quad_mesh(4 + 2 * int(seed % 5), seed);
    const SmoothOptions opt;
    quadsmooth_detail::QuadMesh qm(m, opt, quadsmooth_detail::conforming_stars(m, {}));
    for (int q = 0; q < int(qm.quads.size()); ++q)
      for (int k = 0; k < 4; ++k) {
        const int u = qm.quads[q][k], v = qm.quads[q][(k + 1) & 3];
        if (qm.fixed[u] || qm.fixed[v] || qm.quad_sin_mu[q] >= std::sin(12 * M_PI / 180)) continue;
        auto worst = [&] {
          double w = 2;
          for (int x : {u, v})
            for (int r : qm.vertex_quads[x]) w = std::min(w, qm.sin_mu_of(qm.quads[r]));
          return w;
        };
        const double before = worst();
        CAPTURE(seed, q, k);
        if (quadsmooth_detail::raise_worst_pair(qm, u, v, 0.1)) ++moved;
        CHECK(worst() >= before);
      }
    CHECK(live_quads_strictly_convex(qm));
  }
  CHECK(moved > 0);
}

TEST_CASE("doublet removal is refused when the merged quad would not be strictly convex", "[smooth]") {
  // v on the segment a-c; the merged quad (a, b, c, d) would be reflex at c.
  PlanarMesh m;
  m.points = {{0, 0}, {2, 0}, {0.8, 0.8}, {0, 2}, {0.4, 0.4}};  // a b c d v
  m.elements = {{4, 0, 1, 2}, {4, 2, 3, 0}};
  REQUIRE_FALSE(is_strictly_convex(m.points[0], m.points[1], m.points[2], m.points[3]));
  const SmoothOptions opt;
  quadsmooth_detail::QuadMesh qm(m, opt, quadsmooth_detail::conforming_stars(m, {}));
  const State before = snapshot(qm);
  CHECK_FALSE(quadsmooth_detail::remove_doublet(qm, 4));
  check_same(snapshot(qm), before);
}

TEST_CASE("a diagonal swap for the worst mu takes the better diagonal of the hexagon", "[smooth]") {
  // Two quads of a flat hexagon sharing its long diagonal p0-p3 (mu about
  // 22 degrees); across p1-p4 they are nearly rectangles.
  PlanarMesh m;
  m.points = {{0, 0}, {2, -0.3}, {4, 0}, {4, 1}, {2, 1.3}, {0, 1}};
  m.elements = {{0, 1, 2, 3}, {3, 4, 5, 0}};
  const double mu0 = std::min(quad_mu(m, m.elements[0]), quad_mu(m, m.elements[1]));
  REQUIRE(mu0 < 30);
  const std::vector<Point2> points0 = m.points;
  SmoothOptions opt;
  opt.split_below = 0;  // swaps only
  quadsmooth_detail::QuadMesh qm(m, opt, quadsmooth_detail::conforming_stars(m, {}));
  SmoothStats st;
  REQUIRE(quadsmooth_detail::swap_diagonal(qm, 0, 3, st));  // edge 3 of quad 0 is p3 -> p0
  CHECK(st.swaps == 1);
  CHECK(shares_edge(qm, 1, 4));
  CHECK_FALSE(shares_edge(qm, 0, 3));
  CHECK(live_quads_strictly_convex(qm));
  CHECK(qm.points == points0);  // a swap moves no vertex
  qm.compact();
  REQUIRE_NOTHROW(check_quad_mesh(m));
  CHECK(std::min(quad_mu(m, m.elements[0]), quad_mu(m, m.elements[1])) > mu0 + 5);
  CHECK(total_area(m) == Approx(4 + 2 * 0.3 * 2));
}

TEST_CASE("a diagonal swap that would make a quad non-convex is refused and nothing changes", "[smooth]") {
  // The strip below (every corner on the boundary): either other diagonal
  // of the hexagon (u, c, d, w, a, b) leaves a quad with a corner over 180
  // degrees at u or w.
  PlanarMesh m;
  m.points = {{0, 0}, {3, 1}, {0.5, 2.5}, {-3, -0.9}, {2.5, -1.5}, {6, 1.9}};  // u, w, a, b, c, d
  m.elements = {{0, 1, 2, 3}, {1, 0, 4, 5}};
  const int H[6] = {0, 4, 5, 1, 2, 3};
  for (int k = 1; k <= 2; ++k) {
    const auto& P = m.points;
    const bool n1 = is_strictly_convex(P[H[k]], P[H[k + 1]], P[H[k + 2]], P[H[(k + 3) % 6]]);
    const bool n2 = is_strictly_convex(P[H[(k + 3) % 6]], P[H[(k + 4) % 6]], P[H[(k + 5) % 6]], P[H[k]]);
    REQUIRE_FALSE((n1 && n2));
  }
  SmoothOptions opt;
  opt.split_below = 0;  // no pair split in its place
  quadsmooth_detail::QuadMesh qm(m, opt, quadsmooth_detail::conforming_stars(m, {}));
  REQUIRE(qm.quad_sin_mu[0] < 0.5);  // poor: a swap is looked for
  const State before = snapshot(qm);
  SmoothStats st;
  for (int i = 0; i < 4; ++i) CHECK_FALSE(quadsmooth_detail::swap_diagonal(qm, 0, i, st));
  CHECK(st.swaps + st.valence_swaps + st.splits == 0);
  check_same(snapshot(qm), before);
}

TEST_CASE("a pair split turns the fixed strip into four strictly convex quads around two new points", "[smooth]") {
  PlanarMesh m;
  m.points = {{0, 0}, {3, 1}, {0.5, 2.5}, {-3, -0.9}, {2.5, -1.5}, {6, 1.9}};  // u, w, a, b, c, d
  m.elements = {{0, 1, 2, 3}, {1, 0, 4, 5}};
  m.element_attributes = {{7}, {7}};
  const PlanarMesh orig = m;
  const SmoothOptions opt;
  quadsmooth_detail::QuadMesh qm(m, opt, quadsmooth_detail::conforming_stars(m, {}));
  const int H[6] = {0, 4, 5, 1, 2, 3};  // the pair's hexagon, counter-clockwise
  REQUIRE(quadsmooth_detail::split_pair(qm, 0, 1, H) == 4);
  CHECK(live_quads_strictly_convex(qm));
  qm.compact();
  REQUIRE_NOTHROW(check_quad_mesh(m));
  CHECK(m.elements.size() == 4);
  REQUIRE(m.points.size() == 8);
  for (std::size_t v = 0; v < orig.points.size(); ++v) CHECK(m.points[v] == orig.points[v]);
  for (const auto& a : m.element_attributes) CHECK(a == std::vector<double>{7});
  CHECK(total_area(m) == Approx(total_area(orig)).epsilon(1e-12));
  CHECK(boundary_edges(m) == boundary_edges(orig));
  double mu = 90;
  for (const auto& e : m.elements) mu = std::min(mu, quad_mu(m, e));
  CHECK(mu > std::min(quad_mu(orig, orig.elements[0]), quad_mu(orig, orig.elements[1])));
}

TEST_CASE("a pair split that would not improve is undone exactly", "[smooth]") {
  // Two unit squares: any split is worse than mu = 45.
  PlanarMesh m;
  m.points = {{0, 0}, {1, 0}, {2, 0}, {2, 1}, {1, 1}, {0, 1}};
  m.elements = {{0, 1, 4, 5}, {1, 2, 3, 4}};
  const SmoothOptions opt;
  quadsmooth_detail::QuadMesh qm(m, opt, quadsmooth_detail::conforming_stars(m, {}));
  const State before = snapshot(qm);
  const int H[6] = {1, 2, 3, 4, 5, 0};  // around the shared edge 1-4
  CHECK(quadsmooth_detail::split_pair(qm, 0, 1, H) == 0);
  check_same(snapshot(qm), before);
  CHECK(m.points.size() == 6);
}

TEST_CASE("a patch rolls back the stars, points and quads it saved and drops what was added", "[smooth]") {
  PlanarMesh m = jittered_grid(4, 3);
  const SmoothOptions opt;
  quadsmooth_detail::QuadMesh qm(m, opt, quadsmooth_detail::conforming_stars(m, {}));
  const State before = snapshot(qm);
  const int v = 6;  // an interior grid node
  REQUIRE_FALSE(qm.fixed[v]);
  quadsmooth_detail::Patch pt;
  qm.save_patch({v}, pt);
  qm.points[v][0] += 0.01;
  const int q0 = qm.vertex_quads[v][0];
  const quadsmooth_detail::Quad old = qm.quads[q0];
  const int e = qm.add_vertex({0.5, 0.5});
  pt.verts.push_back(e);
  const int q = qm.add_quad(q0);
  pt.quads.push_back(q);
  qm.set_quad(q0, {old[0], old[1], old[2], e});
  qm.set_quad(q, {old[2], old[3], old[0], e});
  quadsmooth_detail::relax(qm, pt);
  qm.rollback(pt);
  check_same(snapshot(qm), before);
  CHECK(m.points.size() == before.points.size());
}

TEST_CASE("a quad collapse at a boundary vertex keeps it where it was, on the boundary", "[smooth]") {
  // a on the bottom side y = 0 with three quads; the middle one (a, b, c, d)
  // is squashed (mu under 6 degrees): c, free, merges into a, which stays.
  // b and d are boundary vertices (the domain has notches beside them).
  PlanarMesh m;
  m.points = {{-2, 0}, {0, 0}, {2, 0}, {1, 1}, {0, 1.1}, {-1, 1},  // i a e b c d
              {-2, 1}, {2, 1}, {0, 2}, {1, 2}, {-1, 2}};          // h f y x g
  enum { i, a, e, b, c, d, h, f, y, x, g };
  m.elements = {{i, a, d, h}, {a, e, f, b}, {a, b, c, d}, {d, c, y, g}, {c, b, x, y}};
  REQUIRE_NOTHROW(check_quad_mesh(m));
  const PlanarMesh orig = m;
  REQUIRE(quad_mu(m, m.elements[2]) < 15);
  const SmoothOptions opt;
  quadsmooth_detail::QuadMesh qm(m, opt, quadsmooth_detail::conforming_stars(m, {}));
  REQUIRE(qm.fixed[a]);
  REQUIRE_FALSE(qm.fixed[c]);
  SmoothStats st;
  CHECK_FALSE(quadsmooth_detail::collapse_quad(qm, 2, 1, st));  // b and d: both fixed
  REQUIRE(quadsmooth_detail::collapse_quad(qm, 2, 0, st));
  CHECK(st.collapses == 1);
  CHECK(qm.quad_dead[2]);
  CHECK(qm.vertex_dead[c]);
  CHECK(qm.points[a] == orig.points[a]);  // on the side y = 0, where it was
  CHECK(live_quads_strictly_convex(qm));
  qm.compact();
  REQUIRE_NOTHROW(check_quad_mesh(m));
  CHECK(m.elements.size() == 4);
  REQUIRE(m.points.size() == orig.points.size() - 1);
  // Vertices after c move down by one; every boundary edge stays.
  auto renum = [&](int v) { return v > c ? v - 1 : v; };
  std::set<std::pair<int, int>> expected;
  for (const auto& [p, q] : boundary_edges(orig)) expected.insert(std::minmax(renum(p), renum(q)));
  CHECK(boundary_edges(m) == expected);
  for (int v = 0; v < int(orig.points.size()); ++v)
    if (v != c) CHECK(m.points[renum(v)] == orig.points[v]);
  CHECK(total_area(m) == Approx(total_area(orig)).epsilon(1e-12));
  double mu = 90;
  for (const auto& el : m.elements) mu = std::min(mu, quad_mu(m, el));
  CHECK(mu > quad_mu(orig, orig.elements[2]));
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

namespace {

// The largest size ratio (square roots of the areas) of two quads sharing an edge.
double max_neighbour_ratio(const PlanarMesh& m) {
  std::map<std::pair<int, int>, double> seen;
  double worst = 1;
  for (const auto& e : m.elements) {
    const double s = std::sqrt(quad_area(m.points[e[0]], m.points[e[1]], m.points[e[2]], m.points[e[3]]));
    for (int i = 0; i < 4; ++i) {
      const auto k = std::minmax(e[i], e[(i + 1) % 4]);
      const auto it = seen.find(k);
      if (it == seen.end()) seen[k] = s;
      else worst = std::max(worst, std::max(s / it->second, it->second / s));
    }
  }
  return worst;
}

} // namespace

TEST_CASE("the grading pass grows a small quad ringed by four large ones to sqrt 6", "[smooth]") {
  // A 3 x 3 square (its corners on the boundary) with a concentric square
  // of side 0.3 inside, joined corner to corner: four trapezoids 5 times
  // the inner square's size (mu 5.7 degrees). The pass alone (quadsmooth's
  // clean-up merges the five into one).
  PlanarMesh m;
  m.points = {{0, 0}, {3, 0}, {3, 3}, {0, 3}, {1.35, 1.35}, {1.65, 1.35}, {1.65, 1.65}, {1.35, 1.65}};
  m.elements = {{4, 5, 6, 7}, {0, 1, 5, 4}, {1, 2, 6, 5}, {2, 3, 7, 6}, {3, 0, 4, 7}};
  m.element_attributes.assign(5, {1.0});
  REQUIRE(max_neighbour_ratio(m) > 4.9);
  SmoothOptions opt;
  quadsmooth_detail::QuadMesh qm(m, opt, quadsmooth_detail::conforming_stars(m, {}));
  SmoothStats st;
  st.before = quality_report(m);
  quadsmooth_detail::grading_pass(qm, st, opt.grading);
  qm.compact();
  const QualityReport after = quality_report(m);
  CAPTURE(max_neighbour_ratio(m), st.grading_moves, after.min_mu);
  CHECK(max_neighbour_ratio(m) <= std::sqrt(6.0) * (1 + 1e-9));
  CHECK(st.grading_moves > 0);
  CHECK(m.elements.size() == 5);
  REQUIRE_NOTHROW(check_quad_mesh(m));
  for (const auto& e : m.elements)
    REQUIRE(is_strictly_convex(m.points[e[0]], m.points[e[1]], m.points[e[2]], m.points[e[3]]));
  CHECK(after.min_mu >= st.before.min_mu - 1e-9);
  CHECK(region_area(m, 1) == Approx(9).epsilon(1e-12));
  for (int v = 0; v < 4; ++v) CHECK(m.points[v] == (std::array<double, 2>{v == 1 || v == 2 ? 3.0 : 0.0, v >= 2 ? 3.0 : 0.0}));
}

TEST_CASE("the grading pass takes no quad under 10 degrees nor under its own mu", "[smooth]") {
  // tri2quad's outputs of jittered grids through quadsmooth with and
  // without the pass (which runs last, but for guarded mean rounds): the
  // worst mu is the one without it, or 10 degrees if that is lower.
  for (unsigned seed = 1; seed <= 20; ++seed) {
    const int n = 4 + 2 * int(seed % 5);
    PlanarMesh with = tri2quad_mesh(n, seed), without = with;
    SmoothOptions opt;
    opt.grading = 0;
    const SmoothStats s0 = smooth_quad_mesh(without, opt);
    const SmoothStats s1 = smooth_quad_mesh(with, SmoothOptions{});
    CAPTURE(seed, n, s0.after.min_mu, s1.after.min_mu, max_neighbour_ratio(without), max_neighbour_ratio(with));
    REQUIRE_NOTHROW(check_quad_mesh(with));
    for (const auto& e : with.elements)
      REQUIRE(is_strictly_convex(with.points[e[0]], with.points[e[1]], with.points[e[2]], with.points[e[3]]));
    CHECK(s1.after.min_mu >= std::min(10.0, s0.after.min_mu) - 1e-9);
    // The largest ratio only falls, or the mean rounds after raise it to sqrt 6.
    CHECK(max_neighbour_ratio(with) <= std::max(std::sqrt(6.0), max_neighbour_ratio(without)) * (1 + 1e-9));
  }
}
