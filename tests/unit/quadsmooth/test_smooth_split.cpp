// Pair splits (lib/quadsmooth/smooth_split.cpp): through the loop, alone on
// small hand-made meshes, and the final pair split.
#include "smooth_test_support.hpp"

#include "quad/predicates.hpp"
#include "quadsmooth/smooth.hpp"
#include "quadsmooth/smooth_mesh.hpp"

#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <map>
#include <set>

using namespace imgmesh;
using namespace quadsmooth_test;

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
