// Doublet removal, the sharp-corner pass and the collapses that merge the
// doublet they leave (lib/quadsmooth/smooth_doublet.cpp).
#include "smooth_test_support.hpp"

#include "quad/predicates.hpp"
#include "quadsmooth/smooth.hpp"
#include "quadsmooth/smooth_mesh.hpp"

#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>

using namespace imgmesh;
using namespace quadsmooth_test;

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
