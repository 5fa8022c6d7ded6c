// tri2quad on random constrained meshes (every guarantee), its input from a planar mesh and its stats.
#include "tri2quad_test_support.hpp"

#include "quad/quality.hpp"
#include "tri2quad/polygons.hpp"
#include "tri2quad/tri2quad.hpp"
#include "util/error.hpp"

#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>
#include <random>
#include <set>

using namespace imgmesh;
using namespace tri2quad_test;
using tri2quad_detail::LocalPatch;

TEST_CASE("Random constrained Delaunay triangulations: all guarantees", "[tri2quad][property]") {
  std::mt19937 g(2006);
  std::size_t total_t = 0, total_q = 0, total_s = 0, fallbacks = 0, meshes = 0;
  std::map<std::string, std::size_t> cases;
  for (int it = 0; it < 2500; ++it) {
    const int npts = 5 + int(g() % 300);
    const int holes = int(g() % 3), loops = int(g() % 3);
    const Tri2QuadInput in = random_cdt(g, npts, holes, loops);
    if (in.triangles.empty()) continue;
    const bool outside = (it % 4) == 3;
    Tri2QuadOptions o;
    o.allow_outside = outside;
    INFO("mesh " << it << ": " << in.triangles.size() << " triangles, " << holes << " holes, " << loops << " loops");
    const auto r = tri2quad(in, o);
    std::string used;
    for (const auto& [n, c] : r.cases) if (c) used += n + "=" + std::to_string(c) + " ";
    INFO("h " << r.components << " cases: " << used);
    check_result(in, r, outside);
    // Region attributes are carried: one per quad, values from the input.
    REQUIRE(r.region.size() == r.quads.size());
    total_t += r.triangles;
    total_q += r.quads.size();
    total_s += r.steiner;
    for (const auto& [n, c] : r.cases) cases[n] += c;
    ++meshes;
  }
  fallbacks = cases["fallback_split"];
  INFO("meshes " << meshes << " t " << total_t << " q " << total_q << " s " << total_s << " fallbacks " << fallbacks);
  CHECK(meshes > 2000);
  CHECK(double(total_q) / double(total_t) < 1.0);
  WARN("random CDTs: quads/t = " << double(total_q) / double(total_t) << ", Steiner/t = "
                                 << double(total_s) / double(total_t) << ", fallback splits " << fallbacks);
  std::string s;
  for (const auto& [n, c] : cases) s += n + "=" + std::to_string(c) + " ";
  WARN(s);
  // Every step and case ran somewhere in the sample.
  for (const char* name : {"4c_convex_quad", "4c_quad_to_grandparent", "B21_pentagon_ear", "4b_B21_type1",
                           "4cii_B21_type2", "4cii_B21_type3_edge_point", "4ci_4ciii_B11_hexagon", "4cvf_B31_heptagon",
                           "3_nonempty_triangle", "3b_B12_quad_point", "3c_B22_pentagon_point", "5bd_joe_split",
                           "5bd_outside_point", "5c_B12_nested", "3_3_repair_split", "5_B11_root_pentagon_edge_point",
                           "B22_middle_type1_B12", "4civ_hexagon_point", "4civ_B21_B12_pair_nonempty",
                           "3d_edge_point_B12_twice", "3c_4cvde_leftover_B12", "B31_heptagon_edge_point"}) {
    INFO(name);
    CHECK(cases[name] > 0);
  }
  WARN("largest excess over the bounds: quads " << small_excess_q << ", Steiner " << small_excess_s
                                                << "; size-bound retries " << cases["size_bound_retry"]);
  CHECK(small_excess_q <= 0);
  CHECK(small_excess_s <= 0);
  // The bounds hold by construction: the rerun from other root edges (a
  // safety net) is never needed.
  CHECK(cases["size_bound_retry"] == 0);
}

// Small meshes are where the additive 4h has the least room: the exact
// bounds (and every other guarantee) on thousands of them, both modes.
TEST_CASE("Small random constrained Delaunay triangulations: exact size bounds", "[tri2quad][property][small]") {
  std::mt19937 g(31415);
  std::size_t meshes = 0, retries = 0;
  for (int it = 0; it < 3000; ++it) {
    const int npts = int(g() % 40);
    const int holes = int(g() % 3), loops = int(g() % 3);
    const Tri2QuadInput in = random_cdt(g, npts, holes, loops);
    if (in.triangles.empty()) continue;
    for (int o = 0; o < 2; ++o) {
      Tri2QuadOptions opt;
      opt.allow_outside = o == 1;
      INFO("mesh " << it << ": " << in.triangles.size() << " triangles, allow_outside " << o);
      const auto r = tri2quad(in, opt);
      check_result(in, r, opt.allow_outside);
      REQUIRE(r.region.size() == r.quads.size());
      for (const auto& [n, c] : r.cases) if (n == "size_bound_retry") retries += c;
      ++meshes;
    }
  }
  CHECK(meshes > 5000);
  CHECK(retries == 0);
  WARN("small random CDTs: " << meshes << " runs, size-bound retries " << retries);
}

// Diagnostic (hidden): excess over the size bounds on many small meshes,
// with the cases used by the worst ones.
TEST_CASE("size bound slack on small meshes", "[.slack]") {
  std::mt19937 g(4242);
  long wq = -1000, ws = -1000;
  std::size_t over_q = 0, over_s = 0, n = 0, raw_over = 0;
  long raw_q = -1000, raw_s = -1000;
  std::map<std::string, std::size_t> over_cases;
  int printed = 0;
  for (int it = 0; it < 20000; ++it) {
    const int npts = int(g() % 40);
    const int holes = int(g() % 3), loops = int(g() % 3);
    const Tri2QuadInput in = random_cdt(g, npts, holes, loops);
    if (in.triangles.empty()) continue;
    for (int o = 0; o < 4; ++o) {
      Tri2QuadOptions opt;
      opt.allow_outside = o % 2 == 1;
      opt.size_retry = o >= 2;
      const auto r = tri2quad(in, opt);
      ++n;
      if (!opt.size_retry) {
        raw_q = std::max(raw_q, long(r.quads.size()) - long(r.quad_bound()));
        raw_s = std::max(raw_s, long(r.steiner) - long(r.steiner_bound(opt.allow_outside)));
        const bool over = r.quads.size() > r.quad_bound() || r.steiner > r.steiner_bound(opt.allow_outside);
        raw_over += over;
        if (over) {
          std::string used;
          for (const auto& [nm, c] : r.cases) if (c) { used += nm + "=" + std::to_string(c) + " "; over_cases[nm] += 1; }
          if (printed++ < 30)
            std::printf("it %d o %d t %zu h %zu q %zu/%zu s %zu/%zu: %s\n", it, o, r.triangles, r.components,
                        r.quads.size(), r.quad_bound(), r.steiner, r.steiner_bound(opt.allow_outside), used.c_str());
        }
        continue;
      }
      const long eq = long(r.quads.size()) - long(r.quad_bound());
      const long es = long(r.steiner) - long(r.steiner_bound(opt.allow_outside));
      wq = std::max(wq, eq);
      ws = std::max(ws, es);
      if (eq > 0 || es > 0) {
        over_q += eq > 0;
        over_s += es > 0;
        std::string used;
        for (const auto& [nm, c] : r.cases) if (c) { used += nm + "=" + std::to_string(c) + " "; over_cases[nm] += 1; }
        if (printed++ < 30)
          std::printf("it %d o %d t %zu h %zu q %zu/%zu s %zu/%zu: %s\n", it, o, r.triangles, r.components,
                      r.quads.size(), r.quad_bound(), r.steiner, r.steiner_bound(opt.allow_outside), used.c_str());
      }
    }
  }
  std::printf("runs %zu worst excess q %ld s %ld; over q %zu over s %zu\n", n / 2, wq, ws, over_q, over_s);
  std::printf("without retries: worst excess q %ld s %ld, runs over a bound %zu\n", raw_q, raw_s, raw_over);
  for (const auto& [nm, c] : over_cases) std::printf("  %s %zu\n", nm.c_str(), c);
}

TEST_CASE("tri2quad_input: a planar mesh's triangles, segments and regions; planar_mesh back", "[tri2quad][input]") {
  // The unit square cut along (0, 2) into two regions, the cut a segment
  // with marker 5; ids printed from 1.
  PlanarMesh m;
  m.first_index = 1;
  m.points = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
  m.elements = {{0, 1, 2}, {0, 2, 3}};
  m.element_attributes = {{1}, {2}};
  m.segments = {{0, 2}};
  m.segment_markers = {5};
  const Tri2QuadInput in = tri2quad_input(PlanarMesh(m), "square.ele");
  CHECK(in.points == m.points);
  CHECK(in.triangles == std::vector<std::array<int, 3>>{{0, 1, 2}, {0, 2, 3}});
  CHECK(in.region == std::vector<double>{1, 2});
  CHECK(in.constraints == m.segments);
  CHECK(in.constraint_markers == m.segment_markers);
  CHECK(in.index_base == 1);
  CHECK(in.path == "square.ele");

  const Tri2QuadResult r = tri2quad(in);
  check_result(in, r, false);
  // Each quad keeps the region of the triangle it lies in, and the cut
  // comes out as a chain of segments with its marker.
  REQUIRE(r.region.size() == r.quads.size());
  for (std::size_t k = 0; k < r.quads.size(); ++k) {
    P2 c{0, 0};
    for (int v : r.quads[k]) c = {c[0] + r.points[v][0] / 4, c[1] + r.points[v][1] / 4};
    CHECK(r.region[k] == (c[0] > c[1] ? 1 : 2));
  }
  std::size_t on_cut = 0;
  for (std::size_t k = 0; k < r.segments.size(); ++k) {
    const P2 &a = r.points[r.segments[k][0]], &b = r.points[r.segments[k][1]];
    if (a[0] == a[1] && b[0] == b[1]) {
      ++on_cut;
      CHECK(r.segment_markers[k] == 5);
    }
  }
  CHECK(on_cut >= 1);

  const PlanarMesh q = planar_mesh(r, in.index_base);
  CHECK(q.first_index == 1);
  CHECK(q.points == r.points);
  REQUIRE(q.elements.size() == r.quads.size());
  for (std::size_t k = 0; k < q.elements.size(); ++k) {
    CHECK(q.elements[k] == std::vector<int>(r.quads[k].begin(), r.quads[k].end()));
    CHECK(q.element_attributes[k] == std::vector<double>{r.region[k]});
  }
  CHECK(q.segments == r.segments);
  CHECK(q.segment_markers == r.segment_markers);

  // No element with an attribute: no regions.
  PlanarMesh plain = m;
  plain.element_attributes = {{}, {}};
  CHECK(tri2quad_input(std::move(plain), "p.ele").region.empty());

  // A quad element is refused, naming it with the mesh's first index.
  PlanarMesh with_quad = m;
  with_quad.elements = {{0, 1, 2, 3}};
  with_quad.element_attributes.clear();
  try {
    tri2quad_input(std::move(with_quad), "q.off");
    FAIL("no error");
  } catch (const Error& e) {
    CHECK(e.message() == "q.off: element 1 is not a triangle");
  }

  // A constraint that is not an edge of the mesh is refused by tri2quad,
  // naming the segment and the file.
  PlanarMesh off_edge = m;
  off_edge.segments = {{1, 3}};
  const Tri2QuadInput bad = tri2quad_input(std::move(off_edge), "bad.ele");
  try {
    tri2quad(bad);
    FAIL("no error");
  } catch (const Error& e) {
    CHECK(e.path() == "bad.ele");
    CHECK(std::string(e.what()).find("constraint segment (2, 4) is not an edge of the triangle mesh") !=
          std::string::npos);
  }
}

TEST_CASE("Tri2QuadResult: to_json and failed_guarantee say what holds", "[tri2quad][stats]") {
  Tri2QuadInput in;
  in.points = {{0, 0}, {1, 0}, {0, 1}};
  in.triangles = {{0, 1, 2}};
  Tri2QuadResult r = tri2quad(in);
  check_result(in, r, false);
  CHECK(r.failed_guarantee().empty());
  const Json j = r.to_json();
  CHECK(j.at("triangles").integer() == 1);
  CHECK(j.at("quads").integer() == long(r.quads.size()));
  CHECK(j.at("steiner_points").integer() == long(r.steiner));
  CHECK(j.at("quad_bound").integer() == long(r.quad_bound()));
  CHECK(j.at("steiner_bound").integer() == long(r.steiner_bound(false)));
  CHECK(j.at("within_bounds").boolean());
  CHECK(j.at("non_convex").integer() == 0);
  CHECK(j.at("cases").at("5bd_joe_split").integer() == 1);
  CHECK(j.at("quality").at("quads").integer() == long(r.quads.size()));

  // Over a size bound: the counts in the message, as the tool said them.
  Tri2QuadResult big = r;
  while (big.quads.size() <= big.quad_bound()) big.quads.push_back(big.quads[0]);
  CHECK(!big.to_json().at("within_bounds").boolean());
  CHECK(big.failed_guarantee() == "size bound exceeded (quads " + std::to_string(big.quads.size()) + " / " +
                                      std::to_string(big.quad_bound()) + ", Steiner points " +
                                      std::to_string(big.steiner) + " / " + std::to_string(big.steiner_bound(false)) +
                                      ")");
  // A quad turned clockwise comes first.
  Tri2QuadResult flipped = big;
  std::reverse(flipped.quads[0].begin(), flipped.quads[0].end());
  CHECK(flipped.failed_guarantee() == "1 quads not strictly convex");
  CHECK(flipped.to_json().at("non_convex").integer() == 1);
}
