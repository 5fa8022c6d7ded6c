// The tip pass (lib/quadsmooth/smooth_tip.cpp): a wedge tip re-quadded, and
// a corner left as it was where no layout is better.
#include "smooth_test_support.hpp"

#include "quadsmooth/smooth.hpp"
#include "quadsmooth/smooth_mesh.hpp"

#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>

using namespace imgmesh;
using namespace quadsmooth_test;

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
