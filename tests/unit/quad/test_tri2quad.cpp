// tri2quad: the small-polygon constructions (appendix B) one by one, the
// steps on hand-made meshes, and properties on thousands of random
// constrained Delaunay triangulations (CGAL) with holes and interior
// constraint loops.
#include "quad/quality.hpp"
#include "quad/tri2quad.hpp"
#include "quad/tri2quad_polygons.hpp"
#include "util/error.hpp"

#include <CGAL/Constrained_Delaunay_triangulation_2.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Triangulation_face_base_with_info_2.h>

#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <list>
#include <map>
#include <random>
#include <set>

using namespace imgmesh;
using t2q::LocalPatch;
using t2q::P2;

namespace {

constexpr double kPi = 3.14159265358979323846;

double poly_area(const std::vector<P2>& v) {
  double a = 0;
  for (std::size_t i = 0; i < v.size(); ++i)
    a += v[i][0] * v[(i + 1) % v.size()][1] - v[(i + 1) % v.size()][0] * v[i][1];
  return a / 2;
}

// Quads of a patch: all strictly convex (exact) and their areas add up to
// `area`; every new point used.
void check_patch(const LocalPatch& lp, double area, std::size_t quads_max, std::size_t points_max) {
  double sum = 0;
  for (const auto& q : lp.quads) {
    CHECK(is_strictly_convex(lp.p[q[0]], lp.p[q[1]], lp.p[q[2]], lp.p[q[3]]));
    sum += quad_area(lp.p[q[0]], lp.p[q[1]], lp.p[q[2]], lp.p[q[3]]);
  }
  CHECK(sum == Approx(area).epsilon(1e-9));
  CHECK(lp.quads.size() <= quads_max);
  std::size_t fresh = 0;
  for (int g : lp.gid) fresh += g < 0;
  CHECK(fresh <= points_max);
  // Edge-to-edge inside the patch: no directed edge twice.
  std::set<std::pair<int, int>> seen;
  for (const auto& q : lp.quads)
    for (int k = 0; k < 4; ++k) CHECK(seen.insert({q[k], q[(k + 1) % 4]}).second);
}

LocalPatch patch_of(const std::vector<P2>& v) {
  LocalPatch lp;
  for (std::size_t i = 0; i < v.size(); ++i) lp.add_known(v[i], int(i));
  return lp;
}

t2q::Ring ring(int n) {
  t2q::Ring r;
  for (int i = 0; i < n; ++i) r.push_back(i);
  return r;
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

} // namespace

TEST_CASE("B.1.1: random hexagons get at most 5 strictly convex quads and 3 points", "[tri2quad][B11]") {
  std::mt19937 g(11);
  int done = 0, tried = 0, reflex3 = 0;
  for (int it = 0; it < 3000; ++it) {
    auto v = random_star(g, 6, 0.2, 1.0);
    if (!simple_ccw(v)) continue;
    int reflex = 0;
    for (int i = 0; i < 6; ++i) reflex += orientation(v[(i + 5) % 6], v[i], v[(i + 1) % 6]) <= 0;
    reflex3 += reflex == 3;
    ++tried;
    LocalPatch lp = patch_of(v);
    if (t2q::hexagon(lp, ring(6))) {
      ++done;
      check_patch(lp, poly_area(v), 5, 3);
      // Euler: a hexagon with k interior points has 2 + k quads.
      CHECK(lp.quads.size() == 2 + (lp.p.size() - 6));
    }
  }
  CHECK(reflex3 > 0);
  // The thesis's lemma says always; our construction may miss rare ones
  // (the caller then falls back), but not many.
  WARN("B.1.1: " << done << " of " << tried << " random hexagons");
  CHECK(done == tried);
}

TEST_CASE("B.1.2: quadrilateral with an interior point, convex, kernel and arm cases", "[tri2quad][B12]") {
  std::mt19937 g(12);
  std::uniform_real_distribution<double> U(0, 1);
  int convex = 0, reflex = 0, ok_convex = 0, ok_reflex = 0;
  for (int it = 0; it < 3000; ++it) {
    auto v = random_star(g, 4, 0.1, 1.0);
    if (!simple_ccw(v)) continue;
    // A random interior point (rejection sampling in the bounding box).
    P2 q{};
    bool found = false;
    for (int k = 0; k < 100 && !found; ++k) {
      q = {2 * U(g) - 1, 2 * U(g) - 1};
      // Inside: fan triangles from v0 (the quad is star-shaped from its kernel,
      // use the ray test instead).
      int crossings = 0;
      for (int i = 0; i < 4; ++i) {
        const P2 &a = v[i], &b = v[(i + 1) % 4];
        if ((a[1] > q[1]) != (b[1] > q[1]) && q[0] < a[0] + (q[1] - a[1]) * (b[0] - a[0]) / (b[1] - a[1])) ++crossings;
      }
      found = crossings % 2 == 1;
      for (int i = 0; i < 4 && found; ++i) found = orientation(v[i], v[(i + 1) % 4], q) != 0;
    }
    if (!found) continue;
    bool is_convex = true;
    for (int i = 0; i < 4; ++i) is_convex = is_convex && orientation(v[(i + 3) % 4], v[i], v[(i + 1) % 4]) > 0;
    (is_convex ? convex : reflex)++;
    LocalPatch lp = patch_of(v);
    const int qi = lp.add_known(q, 4);
    if (t2q::quad_with_point(lp, ring(4), qi)) {
      (is_convex ? ok_convex : ok_reflex)++;
      check_patch(lp, poly_area(v), 5, 3);
      CHECK(lp.quads.size() == 5);  // forced by Euler
    }
  }
  CHECK(convex > 100);
  CHECK(reflex > 100);
  CHECK(ok_convex == convex);
  CHECK(ok_reflex == reflex);
}

// Quadrilaterals with a point (c0, c1, c2, c3, q) that random CDTs produced
// and an earlier B.1.2 search could not close: darts with a needle of
// 0-2 degrees and the point in an arm, outside the kernel.
TEST_CASE("B.1.2 on extreme darts from random meshes", "[tri2quad][B12]") {
  const std::vector<std::array<double, 10>> darts = {
    {-0.01911706019874691, 0.14823220926310118, -0.10010657662579542, 0.66986715959180121, -0.19701914144591251, -0.017297975856837615, -0.72539382558003274, -0.55418064604317596, -0.10614721570543051, 0.4863494346885795},
    {-0.7055819274081524, -0.35994242440004559, -0.3539710756241306, -0.27904558496713544, 0.22301686899089718, -0.38461499212032307, 0.18809083829785669, -0.15039213282932648, 0.18096142372717217, -0.27610743990861519},
    {0.18774965713760333, 0.74627244648884228, 0.20511919930532985, 0.64123008926909297, 0.19874246001815443, 0.68111991296965924, 0.21981733550753418, 0.70026291767849236, 0.21723671074843998, 0.70060498221550749},
    {0.20262886265753866, 0.8300313329840201, 0.74011460918888106, 0.71948266794148386, 0.78074527511751146, 0.66790821898879138, 0.82611554296860479, 0.70252240657688536, 0.78851097352882271, 0.6880373575263965},
    {0.24503078597161365, 0.19210049807665214, 0.19032851320510796, 0.33583642760682159, 0.20502317308559453, 0.44285937842215334, 0.099388849690697778, 0.57411228293561867, 0.15002503259034239, 0.45714463136704753},
    {0.24659388623573003, 0.40471073468574326, 0.084457662566712929, 0.19890908848994152, 0.361351075139142, -0.80258736570125044, 0.19678223232247299, -0.1823189405985797, 0.2396064390740078, 0.38797230124933768},
    {0.27897545224823794, 0.44686314935250288, 0.28110803120616867, 0.35462384397942009, 0.33348118454794695, 0.4296675995313527, 0.29018004791900265, 0.36949490847161615, 0.28100991868172637, 0.42070032500693649},
    {0.2996575638232496, 0.31435722132847432, 0.33813857347833315, 0.24153919674057547, 0.33174498004099173, 0.33456482096223705, 0.33272189228182975, 0.31748368494326629, 0.32202588722775005, 0.29625412252327421},
    {0.30636612147898984, 0.67842758606398768, 0.24290185515546484, 0.635919922822897, 0.39386372588410073, 0.62353836512002914, 0.35280140162215101, 0.62748935540855477, 0.30850861454089662, 0.65685533064700441},
    {0.32293617253494311, 0.60514445105626835, -0.16697595322092115, -0.75522908420603718, 0.23632164520168714, -0.10005946264728477, 0.093344969507187722, -0.037622531265497493, 0.099342880401571021, -0.21997699094378831},
    {0.33067529914641774, 0.28600163351462443, 0.017178137461593062, 0.12442806300121004, 0.19539266628597921, -0.301157145296021, 0.13230407885155354, -0.14389718361967352, 0.15198965733824288, 0.014551519157464776},
    {0.35715136819944188, 0.56789610267442336, 0.39668944076979562, 0.74916986683057152, 0.35635865246297244, 0.73247051720901557, 0.37009182040691274, 0.62747077836774334, 0.37150542375522377, 0.65574279130281365},
    {0.37682064682399047, 0.34304482426799487, 0.3602326710808077, 0.414672012904239, 0.33698732804362302, 0.30461011763909041, 0.34480965572557765, 0.34089184939361378, 0.3532467865139019, 0.35550375953063501},
    {0.38998169593714532, 0.37262217956900084, 0.31120517899856154, 0.42375859898286672, 0.32766578373424099, 0.28837128868945439, 0.32146618812737615, 0.34012771931842212, 0.38046430190372499, 0.37855825019622025},
    {0.43152460772991397, 0.32532605967113432, 0.32612493977880996, 0.27962284982536212, 0.29276691165377844, 0.30540045362036083, 0.29732773686321001, 0.26592109200749564, 0.29468487149390288, 0.29187799033912809},
    {0.51677552735779131, 0.098414274052993425, 0.12869276716488018, 0.069499511116438775, 0.58775625323976344, 0.54840190343104289, -0.076126090227482693, -0.14217545351088942, 0.3836314910128642, 0.058014114767033664},
    {0.82130725544153071, 0.16829077206365273, 0.1203049588411028, 0.080739190688620718, 0.13921572873336865, 0.10830226731449054, -0.10221533192132666, -0.2136069947536238, 0.3380010596755374, 0.10287308896517566},
    {0.82611554296860479, 0.70252240657688536, 0.6960421440655622, 0.72885685661790989, 0.74011460918888106, 0.71948266794148386, 0.78074527511751146, 0.66790821898879138, 0.78851097352882271, 0.6880373575263965},
    {0.1373546591328213, 0.7837423001436512, 0.33549484204210855, 0.56663560946621638, 0.4004721473955215, 0.79057525441676435, 0.79590387675236784, 0.80181039521883024, 0.31940703112177582, 0.76282515069291801},
    {0.22853212092479247, 0.63268256552233026, 0.11528929269632973, 0.4683618792952049, 0.14053510483092235, 0.50443632749235578, 0.21679519172826445, 0.50976406378906591, 0.17279319995888981, 0.51989141548389328},
    {0.31527212556161388, 0.62560120234819305, 0.33107676382265644, 0.61262742153517891, 0.25619357442733115, 0.67487265406846808, 0.28924902969170152, 0.61972888041478458, 0.29629408415379338, 0.62657336315400036},
    {0.36057396823265103, 0.35598124375877677, 0.41559173652917969, 0.35040969925380566, 0.42913794226699847, 0.41029109688727977, 0.30193726813700339, 0.31032748864218068, 0.41921250799394177, 0.38057647007494855},
    {0.36849732376267946, 0.26061691372353579, 0.40622144583004921, 0.33100300269304278, 0.27393609286629228, 0.32449886796512434, 0.31671378769720621, 0.32563265836587885, 0.33243333587180823, 0.30648506223872601},
    {0.5433177126720764, 0.83040788906797691, 0.62207895583525041, 0.88070445007895826, 0.40450951474397068, 0.815117568766482, 0.44613533239859954, 0.82765384795934271, 0.53452929826685924, 0.84708810029580739},
    {0.72248319303974984, 0.38228603255509058, 0.47435446891657451, 0.56426046142148067, 0.61855206835447296, 0.45842812727914822, 0.57617135611175685, 0.35321577148451888, 0.66082596772207836, 0.40093384021907363},
    {0.89307212945371228, 0.45900415633835667, 0.83818938656460706, 0.59787687496873976, 0.80359581558194615, 0.42428812866004528, 0.68983822355660251, 0.37970034900347155, 0.85297132038445644, 0.46220024647337449},
    {0.92761652924375837, 0.36519979450454709, 0.65435169961075268, 0.18134552967186712, 0.57505696017488461, 0.19087109319381501, 0.46607011742749843, 0.054271686938891284, 0.55805383818259502, 0.16351224492866417},
  };
  for (const auto& d : darts) {
    std::vector<P2> v;
    for (int i = 0; i < 4; ++i) v.push_back({d[2 * i], d[2 * i + 1]});
    LocalPatch lp = patch_of(v);
    const int qi = lp.add_known({d[8], d[9]}, 4);
    REQUIRE(t2q::quad_with_point(lp, ring(4), qi));
    check_patch(lp, poly_area(v), 5, 3);
  }
}

TEST_CASE("B.2.1: pentagon edge types leave a triangle on the outgoing edge", "[tri2quad][B21]") {
  // Type 1: the outgoing edge in the centre triangle of a convex pentagon
  // whose ears make the ear shortcut impossible.
  SECTION("regular pentagon: an ear (no point) suffices") {
    std::vector<P2> v;
    for (int i = 0; i < 5; ++i) v.push_back({std::cos(2 * kPi * i / 5 - kPi / 2), std::sin(2 * kPi * i / 5 - kPi / 2)});
    LocalPatch lp = patch_of(v);
    int kind = -1;
    const int apex = t2q::pentagon(lp, ring(5), &kind);
    REQUIRE(apex >= 0);
    CHECK(kind == 0);
    const double tri = poly_area({lp.p[0], lp.p[1], lp.p[apex]});
    CHECK(tri > 0);
    check_patch(lp, poly_area(v) - tri, 1, 0);
  }
  SECTION("reflex corners next to the outgoing edge force type 1 or 2") {
    std::mt19937 g(21);
    int seen[4] = {0, 0, 0, 0}, fails = 0, total = 0;
    for (int it = 0; it < 4000; ++it) {
      auto v = random_star(g, 5, 0.15, 1.0);
      if (!simple_ccw(v)) continue;
      ++total;
      LocalPatch lp = patch_of(v);
      int kind = -1;
      const int apex = t2q::pentagon(lp, ring(5), &kind);
      if (apex < 0) { ++fails; continue; }
      ++seen[kind];
      const double tri = poly_area({lp.p[0], lp.p[1], lp.p[apex]});
      CHECK(orientation(lp.p[0], lp.p[1], lp.p[apex]) > 0);
      // Types 1 and 2 as in the lemma; the type-3 stand-in may need the
      // hexagon's 3 points.
      if (kind < 3) check_patch(lp, poly_area(v) - tri, 3, 2);
      else check_patch(lp, poly_area(v) - tri, 5, 4);
    }
    CHECK(seen[0] > 0);
    CHECK(seen[1] > 0);
    CHECK(seen[2] > 0);
    CHECK(seen[3] > 0);
    CHECK(fails == 0);
  }
}

// Lemma B.2.1 within its budget, as tri2quad uses it below the root: a
// leftover triangle on the outgoing edge with at most 3 quads and 2 points
// (ear, type 1, type 2), or else type 3: a point m on the outgoing edge and
// the hexagon (v0, m, v1, ..., v4) with at most 2 more points (4 quads, 3
// points).
TEST_CASE("B.2.1 within budget: leftover forms or type 3 with an edge point", "[tri2quad][B21]") {
  std::mt19937 g(2121);
  int leftover = 0, type3 = 0, fails = 0;
  for (int it = 0; it < 6000; ++it) {
    auto v = random_star(g, 5, 0.1, 1.0);
    if (!simple_ccw(v)) continue;
    LocalPatch lp = patch_of(v);
    const int apex = t2q::pentagon(lp, ring(5), nullptr, 1);
    if (apex >= 0) {
      ++leftover;
      check_patch(lp, poly_area(v) - poly_area({lp.p[0], lp.p[1], lp.p[apex]}), 3, 2);
      continue;
    }
    LocalPatch le = patch_of(v);
    const int m = le.add_new({0.5 * (v[0][0] + v[1][0]), 0.5 * (v[0][1] + v[1][1])});
    if (t2q::hexagon(le, {0, m, 1, 2, 3, 4}, 2)) {
      ++type3;
      check_patch(le, poly_area(v), 4, 3);
    } else {
      ++fails;
    }
  }
  CHECK(leftover > 0);
  CHECK(type3 > 0);
  WARN("B.2.1 within budget: leftover " << leftover << ", type 3 " << type3 << ", neither " << fails);
  CHECK(fails == 0);
}

TEST_CASE("B.3.1: heptagons, both forms (ear and the p1-p3 path)", "[tri2quad][B31]") {
  std::mt19937 g(31);
  int seen[2] = {0, 0}, fails = 0, total = 0;
  for (int it = 0; it < 3000; ++it) {
    auto v = random_star(g, 7, 0.3, 1.0);
    if (!simple_ccw(v)) continue;
    ++total;
    LocalPatch lp = patch_of(v);
    int kind = -1;
    const int apex = t2q::heptagon(lp, ring(7), &kind);
    if (apex < 0) { ++fails; continue; }
    ++seen[kind];
    CHECK(orientation(lp.p[0], lp.p[1], lp.p[apex]) > 0);
    const double tri = poly_area({lp.p[0], lp.p[1], lp.p[apex]});
    // Lemma B.3.1: six quads and four points at most (ear form: 5 and 3).
    check_patch(lp, poly_area(v) - tri, 6, 4);
  }
  CHECK(seen[0] > 0);
  CHECK(seen[1] > 0);
  // Not every heptagon is covered (the caller then closes with a degenerate
  // quad or the safe split), but most are.
  CHECK(fails < total / 5);
  WARN("heptagons: ear " << seen[0] << ", path " << seen[1] << ", not covered " << fails << " of " << total);
}

namespace {
// A point beyond the edge (p, q) (right of p -> q), at a random place.
P2 beyond(std::mt19937& g, const P2& p, const P2& q) {
  std::uniform_real_distribution<double> U(0, 1);
  const double t = 0.02 + 0.96 * U(g), h = 0.02 + std::pow(U(g), 2);
  const P2 m = {p[0] + t * (q[0] - p[0]), p[1] + t * (q[1] - p[1])};
  return {m[0] + h * (q[1] - p[1]), m[1] - h * (q[0] - p[0])};
}

bool convex_ring(const std::vector<P2>& v) {
  for (std::size_t i = 0; i < v.size(); ++i)
    if (orientation(v[(i + v.size() - 1) % v.size()], v[i], v[(i + 1) % v.size()]) <= 0) return false;
  return true;
}
} // namespace

// The heptagons of 4(c)(v)(f) as the algorithm forms them: the centre
// triangle (a, b, c) with the outgoing edge ab and, on bc and ca, a pair of
// triangles that is not a convex quadrilateral (else it would have been a
// quad already), with either diagonal: the four triangulations (a)-(d) of
// Fig. B.6, reflex vertices anywhere. Each is closed by B.3.1 with a
// leftover triangle on ab (at most 6 quads, 4 points) or, failing that,
// with a point on ab (at most 7 quads, 5 points).
TEST_CASE("B.3.1 on heptagons from the algorithm: the four triangulations", "[tri2quad][B31]") {
  std::mt19937 g(3131);
  int seen[4] = {0, 0, 0, 0}, leftover = 0, closed = 0, fails = 0;
  std::map<int, int> reflex_count;
  for (int it = 0; it < 400000 && leftover + closed + fails < 4000; ++it) {
    const P2 a{0, 0}, b{1, 0};
    std::uniform_real_distribution<double> U(0, 1);
    const P2 c{-0.3 + 1.6 * U(g), 0.05 + 1.2 * U(g)};
    // Pair on (b, c): t1 = (c, b, w), t2 across (b, w) or (w, c).
    const int pattern = int(g() % 4);
    const P2 w1 = beyond(g, b, c);
    const bool d1 = pattern & 1;
    const P2 x1 = d1 ? beyond(g, w1, c) : beyond(g, b, w1);
    const P2 w2 = beyond(g, c, a);
    const bool d2 = pattern & 2;
    const P2 x2 = d2 ? beyond(g, w2, a) : beyond(g, c, w2);
    // Heptagon a, b, then the pair on bc, c, the pair on ca.
    const std::vector<P2> q1 = d1 ? std::vector<P2>{b, w1, x1, c} : std::vector<P2>{b, x1, w1, c};
    const std::vector<P2> q2 = d2 ? std::vector<P2>{c, w2, x2, a} : std::vector<P2>{c, x2, w2, a};
    if (convex_ring(q1) || convex_ring(q2) || !simple_ccw(q1) || !simple_ccw(q2)) continue;
    const std::vector<P2> v = {a, b, q1[1], q1[2], c, q2[1], q2[2]};
    if (!simple_ccw(v)) continue;
    ++seen[pattern];
    int reflex = 0;
    for (int i = 0; i < 7; ++i) reflex += orientation(v[(i + 6) % 7], v[i], v[(i + 1) % 7]) <= 0;
    ++reflex_count[reflex];
    LocalPatch lp = patch_of(v);
    const int apex = t2q::heptagon(lp, ring(7));
    if (apex >= 0) {
      ++leftover;
      CHECK(orientation(lp.p[0], lp.p[1], lp.p[apex]) > 0);
      check_patch(lp, poly_area(v) - poly_area({lp.p[0], lp.p[1], lp.p[apex]}), 6, 4);
      continue;
    }
    LocalPatch lc = patch_of(v);
    const int m = lc.add_new({0.5, 0});
    if (t2q::heptagon_closed(lc, ring(7), m)) {
      ++closed;
      check_patch(lc, poly_area(v), 7, 5);
    } else {
      ++fails;
    }
  }
  for (int k = 0; k < 4; ++k) CHECK(seen[k] > 200);
  CHECK(reflex_count[3] > 0);
  CHECK(fails == 0);
  WARN("algorithm heptagons: leftover " << leftover << ", closed with an edge point " << closed << ", not covered "
                                        << fails << "; by reflex count 1/2/3/4: " << reflex_count[1] << "/"
                                        << reflex_count[2] << "/" << reflex_count[3] << "/" << reflex_count[4]);
}

// Heptagons (a, b, x1, y1, c, x2, y2) that random CDTs of a few dozen
// points produced and the earlier B.3.1 construction could not close:
// slivers with corners of 0-3 degrees and c up to 335 degrees.
TEST_CASE("B.3.1 on extreme heptagons from random meshes", "[tri2quad][B31]") {
  const std::vector<std::array<double, 14>> hepts = {
    {0.12746938549864445, 0.78826505769489974, 0.70873781582594186, 0.071550157098194844, 0.62411440446921496, 0.22138732180643528, 0.63049371884582961, 0.39112398612616656, 0.28728326719781838, 0.59249153557517009, 0.36422569812020567, 0.82427355921051926, 0.40028354048723047, 0.83182648738774501},
    {0.29411321688426828, 0.42510793455550749, 0.3792863031492546, 0.67264246357127189, 0.50974852517345615, 0.78538792612795305, 0.68695466487554446, 0.86731932245004639, 0.15000782001258472, 0.79868968357791825, 0.41987937582120299, 0.067516060726099891, 0.34488827325062532, 0.30024179755601788},
    {0.30237532489140528, 0.78073153784566141, 0.04871679791555078, 0.53077615811915169, 0.00553805279022479, 0.50934151379779125, 0.27842554651803531, 0.47898548756988069, 0.26617428939645882, 0.64853409904419446, 0.4065298968188823, 0.62734574183281167, 0.31772395563603784, 0.66969584582948416},
    {0.30346811940958796, 0.30201985499552092, 0.31041862002964449, 0.4284140205628903, 0.38011022958015717, 0.58333758729978458, 0.2629689581638523, 0.42905609456370541, 0.29961508941961412, 0.39238262311416916, 0.24134530279378325, 0.36786947768184197, 0.091205224785012862, 0.39604526890812003},
    {0.31446486010910391, 0.59510628871106086, 0.43750127334413386, 0.63444883985741329, 0.43097689220910573, 0.68238216935967932, 0.42860121101466481, 0.65364691257163421, 0.3853437204496698, 0.667148199328502, 0.41594197840979164, 0.67800090815582381, 0.35515101588327158, 0.73522606067476282},
    {0.32273939738799529, 0.29738422192111413, 0.3945468981311166, 0.1279020321615118, 0.77501730826591819, 0.20601013109454747, 0.55608498648640314, 0.19162345367621653, 0.4414074996119654, 0.20287643928876781, 0.47064337137151574, 0.32422424539831951, 0.48311226316153599, 0.33529094714518093},
    {0.32609826223263177, 0.70767742787535359, 0.30151321332371939, 0.58806853827179373, 0.45128243106816673, 0.66648631244471002, 0.401207010650312, 0.67865935113592168, 0.3911695415865753, 0.64048748523146359, 0.38172103601772917, 0.6929524174006817, 0.38895160386225947, 0.69750436539496052},
    {0.36390356713181815, 0.065030879002044795, 0.55266918921879116, 0.24408015957374068, 0.45077755612574205, 0.27884853950394123, 0.44031670132403461, 0.30927513687297004, 0.4469498382032388, 0.26844826120971221, 0.31678128021953433, 0.28614989604160412, 0.15765255434882602, 0.85839358992625114},
    {0.38783942818990014, 0.90012408704122837, 0.30084466374187668, 0.76496030950128557, 0.36319707181761496, 0.70102589500034063, 0.37188860239330035, 0.68933362871298276, 0.3362072361910165, 0.79888274329909481, 0.48103290720071123, 0.69253350510261247, 0.53310830064201675, 0.62113110918653913},
    {0.44515606028282212, 0.32861784890575035, 0.32846452073595861, 0.086120753186817056, 0.68196912349524874, 0.10057466245833413, 0.6068984957562541, 0.2953313667840422, 0.4966079488370142, 0.16394160700054367, 0.49895637002930465, 0.33036728359175871, 0.40376887637383369, 0.4220550374396671},
    {0.46435071767509017, 0.9018837454721953, 0.3522099095284314, 0.13803861259247469, 0.50355072087158781, 0.47787673465533509, 0.58026509621071043, 0.61963182576982667, 0.46691977429926462, 0.54138701693990554, 0.50383856334525579, 0.82140186726308517, 0.55153784183214172, 0.75542725767662899},
    {0.47825045964707724, 0.053136970741524292, 0.90442346942858376, 0.3599307499537765, 0.6844740364520292, 0.27981050674929087, 0.61798775637780035, 0.30320121475461836, 0.63616068482758636, 0.19600909709585379, 0.39270505940454098, 0.18910673849417564, 0.36520812004009162, 0.21955245525589651},
    {0.49126358085325139, 0.70064144479479329, 0.15139656950169278, 0.77362148351336968, 0.25050760804440425, 0.68563576861034004, 0.27107342286188002, 0.71031749477641415, 0.29163923767935579, 0.73499922094248826, 0.34081563977958701, 0.7069614225691071, 0.40574381251481095, 0.60286196022871752},
    {0.49452403164767417, 0.59163394232336741, 0.35513121987378332, 0.8600100581995811, 0.075915613781688429, 0.74048666091792281, 0.12263286372862686, 0.44840083574334333, 0.25448921444461076, 0.7502936827731167, 0.38551020252517826, 0.52602323339212465, 0.23460372540024721, 0.19309347371271551},
    {0.50557600957673565, 0.53501766188102362, 0.28525106747206108, 0.38800974198071436, 0.42490981111389969, 0.33860882377551788, 0.43961230585053634, 0.38002677085114944, 0.35310026174520226, 0.36456316739813177, 0.51258252960698769, 0.50750884010669073, 0.60766475974071743, 0.50978440016953475},
    {0.51301126108371897, 0.94585267700916109, 0.37113275312215099, 0.13982258301926992, 0.41459449832452011, 0.34208981705181085, 0.45909752255811098, 0.53704933666170462, 0.48212680151375686, 0.76514122071295831, 0.58985450129507755, 0.77866486880347419, 0.72392566628811084, 0.71839294528416608},
    {0.55055460337304873, 0.61567537024576902, 0.52551059639454523, 0.51229907271318009, 0.60592746170211764, 0.50990232106247002, 0.58736423362309831, 0.52441790720942294, 0.59205366965454653, 0.57777013591447113, 0.6259652542131191, 0.53338455241393945, 0.64188123394240959, 0.58652073980313557},
    {0.56092078964879255, 0.23212656478086863, 0.88148689857782747, 0.30082133388256549, 0.7352277424085264, 0.36025361362895142, 0.74649878757158183, 0.30908084163050997, 0.68876902782863347, 0.26554607184202439, 0.60001891849521583, 0.35134970637777962, 0.65012800947698313, 0.27672896937527791},
    {0.56276257226995063, 0.61174771704843323, 0.45511871512602442, 0.73189928333407006, 0.40069400411330836, 0.67774290285638517, 0.28440957497090213, 0.65198524393433088, 0.43559296927060198, 0.6749781816080519, 0.4365587209172952, 0.61877353386727463, 0.40589813030799526, 0.6118454909378177},
    {0.56360590247783626, 0.28537936081796655, 0.93042720487326225, 0.29027393915004029, 0.76077462181595235, 0.30132763865899459, 0.74571463142594741, 0.3645746019555981, 0.71135174875842988, 0.28928836564971666, 0.62411371778680558, 0.31565417786766836, 0.59817142021291891, 0.33682276137177541},
    {0.56666171812378918, 0.6903455506110423, 0.35641795488719324, 0.55076235192159995, 0.3958493625297777, 0.51820721203816844, 0.46560568842803263, 0.40392984833534146, 0.4100132327762564, 0.56368011133001605, 0.58727181673862705, 0.64325723242396271, 0.75322897489730334, 0.66190136107787645},
    {0.59836780248941446, 0.56757822626738486, 0.5928615029897909, 0.43079556557218768, 0.6982565053869122, 0.31965863422881863, 0.59892752016389472, 0.42706930326521664, 0.6314128832202206, 0.53688598650815678, 0.68453157274984122, 0.42150336414808043, 0.67043518989525519, 0.56643666448635899},
    {0.60315035964002317, 0.30008086969331726, 0.54129840769708215, 0.21214237062397967, 0.70457145692906231, 0.26321022739118916, 0.64758074482193961, 0.27958470356022969, 0.6047854771800798, 0.24447977059981663, 0.61818493787637674, 0.28613749111633785, 0.62536555223098134, 0.28983278662677348},
    {0.60339474431255791, 0.49768081481901433, 0.032717495934157959, 0.50365344674429091, 0.97819689162155299, 0.48121265744709651, 0.77570567498395848, 0.5335561626851546, 0.68010233608049786, 0.4890882228465514, 0.64176892519409479, 0.62288308833021333, 0.61991361569658598, 0.52484787135046518},
    {0.6071679818179786, 0.32487751654711355, 0.59994460976023534, 0.081768665668501272, 0.89243880104416706, 0.30613411694065185, 0.7728707051311261, 0.42849350618524878, 0.70804134942430863, 0.27553549016568896, 0.63835831101253293, 0.33269612266406456, 0.69256558734905094, 0.40038395314197917},
    {0.6128164917284612, 0.19578738363257564, 0.98172887784912488, 0.39603764144825182, 0.56316134153241215, 0.89964327373787334, 0.74494633404299737, 0.5848454615195221, 0.80638432439130048, 0.33105891951649979, 0.68717491707518275, 0.43619807997255294, 0.67915372928229645, 0.4071772197245192},
    {0.61736698452272132, 0.51658558928191645, 0.77928205233051484, 0.63602668277603847, 0.76432546244640531, 0.21893249166388523, 0.80674868758680551, 0.76036476994141733, 0.68057916929951456, 0.63455067399801723, 0.66198324522789176, 0.78227403131170248, 0.67065756740751392, 0.63440706648121792},
    {0.67778048086295972, 0.94806253135411556, 0.37137807197279094, 0.091376743562574136, 0.54566004933930601, 0.22397049206518793, 0.50900123874572911, 0.39633288310496129, 0.551824755410117, 0.53566181385343103, 0.77048687783468539, 0.6361066465308951, 0.67589984255046709, 0.715873617240946},
    {0.69706587342921134, 0.77512171415371833, 0.2832942904916691, 0.88546082661232317, 0.20517640018265199, 0.19453047810108548, 0.25372159183220455, 0.53361093104789636, 0.41216071270284571, 0.83840026351010066, 0.43137184276046142, 0.67985071117117413, 0.47849302225633866, 0.69987111693470205},
    {0.70092546562381974, 0.17376663559082489, 0.84907317298386609, 0.33464752417877897, 0.69776201836053764, 0.40169894540597656, 0.71840135906466984, 0.3799746373846718, 0.65224765042589106, 0.28999885995637886, 0.6367091686356795, 0.32983595462272902, 0.68383727112826187, 0.036291356309060108},
    {0.70568351693319498, 0.87821699550742327, 0.54561403685257692, 0.6380014102800009, 0.57722954420125705, 0.62428483132458679, 0.6110874603250781, 0.59153287825742207, 0.5818979417421849, 0.65249043905338899, 0.69969823957059885, 0.79054643198372854, 0.77317732713507414, 0.68234442690161967},
    {0.71891918122497533, 0.30148759419580534, 0.67165805576278381, 0.44143327454351472, 0.73620822653988371, 0.52443264457986294, 0.51302167247203667, 0.45545376173545826, 0.60072814778780736, 0.29357474633184177, 0.21764308059473292, 0.12808879867896056, 0.73896996788522573, 0.30642281488634693},
    {0.72818856186892522, 0.13819140129578816, 0.78694439261239646, 0.78850880498824916, 0.69141211971036187, 0.86012704509672, 0.74254170327332003, 0.70297184044613759, 0.75540909004622914, 0.44573693382348156, 0.72727459695086061, 0.34904901969176105, 0.73342756898876793, 0.34189110795820027},
    {0.78696245076411231, 0.16575312587638585, 0.58371226835598256, 0.94563562419249658, 0.59671462007634557, 0.78250854280821303, 0.59430448697867, 0.40735894391968658, 0.74695462432255888, 0.31514059328085631, 0.73847716735316538, 0.24254920669809682, 0.64425457309241874, 0.2392396101300987},
    {0.78942682249009344, 0.55039690256199125, 0.1592624584295918, 0.86444110222009773, 0.36685402886399565, 0.62095744417575172, 0.36902497657792394, 0.59055916571250311, 0.41633309369733534, 0.64465214316627839, 0.7017256400849563, 0.54496142453919794, 0.68928926626608233, 0.38877828673417203},
    {0.81271088480446241, 0.25411820345795855, 0.34825384777833013, 0.89330458413829184, 0.34377893395575726, 0.77920825233558255, 0.45668356500169582, 0.7163063744491901, 0.52301897660144292, 0.65176547479269842, 0.48665890056214284, 0.35391372589526249, 0.56461776893142712, 0.36733266554430832},
    {0.93188988822840135, 0.58606093631588363, 0.66841253192410199, 0.60810130393386874, 0.72702428969377331, 0.45186186621386837, 0.7373535851677675, 0.3736985244603927, 0.78417309168763616, 0.5756910703642768, 0.82486383905844329, 0.40206089170152259, 0.64867088587390231, 0.086586056749100471},
    {0.97730490146661675, 0.62875303748405842, 0.44883852205150571, 0.88007151861619481, 0.43089791291024671, 0.71878854445068818, 0.50461254472152639, 0.73050129582452983, 0.78787858731650062, 0.65549265048824179, 0.68077885140781214, 0.49407528068839529, 0.81716994834337187, 0.61421000628663147},
  };
  int leftover = 0, closed = 0;
  for (const auto& h : hepts) {
    std::vector<P2> v;
    for (int i = 0; i < 7; ++i) v.push_back({h[2 * i], h[2 * i + 1]});
    LocalPatch lp = patch_of(v);
    const int apex = t2q::heptagon(lp, ring(7));
    if (apex >= 0) {
      ++leftover;
      check_patch(lp, poly_area(v) - poly_area({lp.p[0], lp.p[1], lp.p[apex]}), 6, 4);
      continue;
    }
    LocalPatch lc = patch_of(v);
    const int m = lc.add_new({0.5 * (v[0][0] + v[1][0]), 0.5 * (v[0][1] + v[1][1])});
    const bool ok = t2q::heptagon_closed(lc, ring(7), m);
    closed += ok;
    if (ok) check_patch(lc, poly_area(v), 7, 5);
  }
  WARN("extreme heptagons: leftover " << leftover << ", closed " << closed << " of " << hepts.size());
  CHECK(closed > 0);
  // One is not covered (its centre triangle has almost no area, b is 0.8
  // degrees, a, c and y2 reflex); the node then closes its children alone
  // (the counted fallback).
  CHECK(leftover + closed + 1 >= int(hepts.size()));
}

TEST_CASE("Joe's and de Berg's triangle splits", "[tri2quad][splits]") {
  std::mt19937 g(31);
  std::uniform_real_distribution<double> U(-1, 1);
  for (int it = 0; it < 2000; ++it) {
    P2 a{U(g), U(g)}, b{U(g), U(g)}, c{U(g), U(g)};
    if (orientation(a, b, c) < 0) std::swap(b, c);
    if (!good_triangle(a, b, c)) continue;
    {
      LocalPatch lp;
      const int ia = lp.add_known(a, 0), ib = lp.add_known(b, 1), ic = lp.add_known(c, 2);
      const int m = lp.add_new({(b[0] + c[0]) / 2, (b[1] + c[1]) / 2});
      REQUIRE(t2q::joe_split(lp, ia, ib, m, ic));
      check_patch(lp, poly_area({a, b, c}), 5, 5);
    }
    {
      LocalPatch lp;
      const int ia = lp.add_known(a, 0), ib = lp.add_known(b, 1), ic = lp.add_known(c, 2);
      const int mab = lp.add_new({(a[0] + b[0]) / 2, (a[1] + b[1]) / 2});
      const int mbc = lp.add_new({(b[0] + c[0]) / 2, (b[1] + c[1]) / 2});
      const int mca = lp.add_new({(c[0] + a[0]) / 2, (c[1] + a[1]) / 2});
      REQUIRE(t2q::deberg_split(lp, ia, ib, ic, mab, mbc, mca));
      check_patch(lp, poly_area({a, b, c}), 3, 4);
    }
  }
}

// ---------------------------------------------------------------- meshes

namespace {

struct Check {
  std::size_t quads = 0, steiner = 0, bound_q = 0, bound_s = 0;
};

// Properties of a result against its input: strictly convex quads,
// conforming (each directed edge once, each interior edge in two quads),
// area, input vertices and every constraint kept as a chain of quad edges,
// and the size bounds.
// Largest excess over the size bounds seen (must stay <= 0).
long small_excess_q = -1000000, small_excess_s = -1000000;

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

} // namespace

namespace {

// The case counters that ran (non-zero), by name: what --stats reports.
std::map<std::string, std::size_t> cases_run(const Tri2QuadResult& r) {
  std::map<std::string, std::size_t> cs;
  for (const auto& [n, c] : r.cases)
    if (c) cs[n] = c;
  return cs;
}

// p in the closed simple polygon v: inside, or on an edge up to rounding
// (points the algorithm put "on" an edge are computed in floating point).
bool in_closed_polygon(const std::vector<P2>& v, const P2& p) {
  bool in = false;
  for (std::size_t i = 0; i < v.size(); ++i) {
    const P2 &a = v[i], &b = v[(i + 1) % v.size()];
    const double dx = b[0] - a[0], dy = b[1] - a[1], len2 = dx * dx + dy * dy;
    const double cr = dx * (p[1] - a[1]) - dy * (p[0] - a[0]);
    const double t = (dx * (p[0] - a[0]) + dy * (p[1] - a[1])) / len2;
    if (std::fabs(cr) <= 1e-9 * len2 && t >= -1e-9 && t <= 1 + 1e-9) return true;
    if ((a[1] > p[1]) != (b[1] > p[1]) && p[0] < a[0] + (p[1] - a[1]) * dx / dy) in = !in;
  }
  return in;
}

bool strictly_inside(const P2& a, const P2& b, const P2& c, const P2& p) {
  return orientation(a, b, p) > 0 && orientation(b, c, p) > 0 && orientation(c, a, p) > 0;
}

// The local result of one case: the quads with every corner in the closed
// region (the domain of T_v as the case sees it, counter-clockwise), all
// whether they are strictly convex, their area, and the Steiner points among their
// corners that are not corners of the region (the ones the case placed).
struct Local {
  std::size_t quads = 0, steiner = 0;
  double area = 0;
  bool convex = true;
};
Local local_result(const Tri2QuadResult& r, const std::vector<P2>& region) {
  Local l;
  std::set<int> placed;
  const auto& P = r.points;
  for (const auto& q : r.quads) {
    bool inside = true;
    for (int v : q) inside = inside && in_closed_polygon(region, P[v]);
    if (!inside) continue;
    ++l.quads;
    l.area += quad_area(P[q[0]], P[q[1]], P[q[2]], P[q[3]]);
    l.convex = l.convex && is_strictly_convex(P[q[0]], P[q[1]], P[q[2]], P[q[3]]);
    for (int v : q)
      if (std::size_t(v) >= r.input_points && std::find(region.begin(), region.end(), P[v]) == region.end())
        placed.insert(v);
  }
  l.steiner = placed.size();
  return l;
}

// The fourth corner of the quad with corners a, b and c, or -1: with (a, b)
// a case's outgoing edge and c the far vertex of the parent's triangle, the
// apex of the leftover triangle the case passed up.
int fourth_corner(const Tri2QuadResult& r, int a, int b, int c) {
  for (const auto& q : r.quads) {
    const auto has = [&](int v) { return std::find(q.begin(), q.end(), v) != q.end(); };
    if (!has(a) || !has(b) || !has(c)) continue;
    for (int v : q)
      if (v != a && v != b && v != c) return v;
  }
  return -1;
}

// The point a case put on its outgoing edge (a, b), leaning into its own
// side (left of a -> b): the Steiner point there nearest to the midpoint.
int edge_point(const Tri2QuadResult& r, const P2& a, const P2& b) {
  int best = -1;
  double bd = 0;
  const P2 mid = {0.5 * (a[0] + b[0]), 0.5 * (a[1] + b[1])};
  for (std::size_t i = r.input_points; i < r.points.size(); ++i) {
    if (orientation(a, b, r.points[i]) <= 0) continue;
    const double d = std::hypot(r.points[i][0] - mid[0], r.points[i][1] - mid[1]);
    if (best < 0 || d < bd) { best = int(i); bd = d; }
  }
  return best;
}

// Steiner points on the segment (a, b) up to rounding.
std::size_t steiner_on(const Tri2QuadResult& r, const P2& a, const P2& b) {
  std::size_t n = 0;
  for (std::size_t i = r.input_points; i < r.points.size(); ++i) n += in_closed_polygon({a, b}, r.points[i]);
  return n;
}

Tri2QuadInput mesh(const std::vector<P2>& points, const std::vector<std::array<int, 3>>& triangles) {
  Tri2QuadInput in;
  in.points = points;
  in.triangles = triangles;
  return in;
}

using Cases = std::map<std::string, std::size_t>;

// A subtree that ends in 4(c)(ii) with B.2.1 type 3 (the mesh of the 4(c)(ii)
// test below): u = (a, b, c) = (0, 1, 2) and the non-convex pair (2, 1, 3),
// (3, 1, 4) below it put a point m on the edge (0, 1), 4 quads and 3
// points; the triangle below (0, 1) becomes a degenerate quadrilateral.
const std::vector<P2> kDentPoints = {{0, 0}, {4, 0}, {1.82, 0.6}, {1.95, 1.39}, {0.17, 4.43}, {2, -2}};
const std::vector<std::array<int, 3>> kDentTriangles = {{0, 1, 2}, {2, 1, 3}, {3, 1, 4}};
constexpr std::size_t kDentQuads = 4, kDentSteiner = 3;

// That subtree placed by a similarity on the edge (x, y) of a triangle
// (its b on x, its a on y), so that the triangle gets the point.
void add_dent(std::vector<P2>& pts, std::vector<std::array<int, 3>>& tris, int x, int y) {
  const P2 X = pts[x], Y = pts[y], v = {X[0] - Y[0], X[1] - Y[1]}, n = {-v[1], v[0]};
  int id[5] = {y, x, -1, -1, -1};
  for (int k = 2; k < 5; ++k) {
    const P2& p = kDentPoints[k];
    id[k] = int(pts.size());
    pts.push_back({Y[0] + (p[0] * v[0] + p[1] * n[0]) / 4, Y[1] + (p[0] * v[1] + p[1] * n[1]) / 4});
  }
  for (const auto& t : kDentTriangles) tris.push_back({id[t[0]], id[t[1]], id[t[2]]});
}

} // namespace

TEST_CASE("Steps on hand-made meshes", "[tri2quad][steps]") {
  SECTION("two triangles forming a convex quad: one quad, no point (4(c) shortcut)") {
    Tri2QuadInput in;
    in.points = {{0, 0}, {1, 0}, {1.2, 1}, {0, 1}};
    in.triangles = {{0, 1, 2}, {0, 2, 3}};
    const auto r = tri2quad(in);
    check_result(in, r, false);
    CHECK(r.quads.size() == 1);
    CHECK(r.steiner == 0);
  }
  SECTION("a non-convex pair at the root: step 5(c), nested template") {
    Tri2QuadInput in;
    in.points = {{0, 0}, {2, 0}, {1, 0.3}, {1, 2}};  // dart: 2 is reflex in (0,1,3,2)? use (0,1,2)+(0,2,3)
    in.points = {{0, 0}, {2, 1}, {0.5, 0.5}, {1, 2}};
    in.triangles = {{0, 1, 2}, {2, 1, 3}};
    const auto r = tri2quad(in);
    check_result(in, r, false);
  }
  SECTION("a single triangle: Joe's split by default, one outside point with --allow-outside") {
    Tri2QuadInput in;
    in.points = {{0, 0}, {1, 0}, {0.3, 0.8}};
    in.triangles = {{0, 1, 2}};
    const auto r = tri2quad(in);
    check_result(in, r, false);
    CHECK(r.quads.size() == 5);
    Tri2QuadOptions o;
    o.allow_outside = true;
    const auto r2 = tri2quad(in, o);
    CHECK(r2.quads.size() == 1);
    CHECK(r2.steiner_outside == 1);
    CHECK(is_strictly_convex(r2.points[r2.quads[0][0]], r2.points[r2.quads[0][1]], r2.points[r2.quads[0][2]],
                             r2.points[r2.quads[0][3]]));
  }
  SECTION("a fan around an interior vertex (non-empty triangles, B.1.2)") {
    for (int n = 3; n <= 9; ++n) {
      Tri2QuadInput in;
      in.points.push_back({0, 0});
      for (int i = 0; i < n; ++i) in.points.push_back({std::cos(2 * kPi * i / n), std::sin(2 * kPi * i / n)});
      for (int i = 0; i < n; ++i) in.triangles.push_back({0, 1 + i, 1 + (i + 1) % n});
      const auto r = tri2quad(in);
      check_result(in, r, false);
    }
  }
  SECTION("3(d): two non-empty triangles close with a point on the outgoing edge and B.1.2 twice") {
    // u = (a, b, c) with three triangles around y1 on bc and around y2 on
    // ca; at the root (ab on the boundary) and below a parent (b, a, z).
    for (int with_parent = 0; with_parent < 2; ++with_parent) {
      Tri2QuadInput in;
      in.points = {{0, 0}, {4, 0}, {2, 2}, {4, 3}, {10.0 / 3, 5.0 / 3}, {0, 3}, {2.0 / 3, 5.0 / 3}, {2, -2}};
      if (with_parent) in.triangles.push_back({1, 0, 7});
      in.triangles.push_back({0, 1, 2});
      for (const std::array<int, 3>& t : {std::array<int, 3>{1, 3, 4}, {3, 2, 4}, {2, 1, 4}, {2, 5, 6}, {5, 0, 6}, {0, 2, 6}})
        in.triangles.push_back(t);
      const auto r = tri2quad(in);
      check_result(in, r, false);
      std::map<std::string, std::size_t> cs(r.cases.begin(), r.cases.end());
      CHECK(cs["3_nonempty_triangle"] == 2);
      CHECK(cs["3d_edge_point_B12_twice"] == 1);
      // B.1.2 twice with the edge point (10 quads, 7 points); below a
      // parent, the parent's triangle with that point is one quad (step 1).
      CHECK(r.quads.size() == std::size_t(with_parent ? 11 : 10));
      CHECK(r.steiner == 7);
    }
  }
  SECTION("4(c)(v)(f) and 4(c)(iv): two non-convex pairs, or a pair and a non-empty triangle") {
    // u = (a, b, c); on bc the pair (c, b, w), (w, b, x), reflex at w; on
    // ca its mirror image (heptagon) or three triangles around y2.
    const std::vector<P2> p = {{0, 0}, {4, 0}, {2, 2}, {4.5, 2.5}, {6, 4}, {-0.5, 2.5}, {-2, 4},
                               {0, 3}, {2.0 / 3, 5.0 / 3}, {2, -2}};
    const std::vector<std::array<int, 3>> pair_bc = {{2, 1, 3}, {3, 1, 4}}, pair_ca = {{2, 0, 5}, {5, 0, 6}},
                                          ntri_ca = {{2, 7, 8}, {7, 0, 8}, {0, 2, 8}};
    for (int with_parent = 0; with_parent < 2; ++with_parent)
      for (int hept = 0; hept < 2; ++hept) {
        Tri2QuadInput in;
        in.points = p;
        if (with_parent) in.triangles.push_back({1, 0, 9});
        in.triangles.push_back({0, 1, 2});
        for (const auto& t : pair_bc) in.triangles.push_back(t);
        for (const auto& t : hept ? pair_ca : ntri_ca) in.triangles.push_back(t);
        INFO("parent " << with_parent << " heptagon " << hept);
        const auto r = tri2quad(in);
        check_result(in, r, false);
        std::map<std::string, std::size_t> cs(r.cases.begin(), r.cases.end());
        CHECK(cs["4c_quad_to_grandparent"] == std::size_t(hept ? 2 : 1));
        if (hept) {
          // The root closes with a point on its edge (7 quads, 5 points);
          // below a parent the leftover form (6 quads, 4 points at most).
          CHECK(cs["4cvf_B31_heptagon"] + cs["B31_heptagon_edge_point"] == 1);
          if (!with_parent) CHECK(cs["B31_heptagon_edge_point"] == 1);
        } else {
          CHECK(cs["3_nonempty_triangle"] == 1);
          CHECK(cs["4civ_hexagon_point"] + cs["4civ_B21_B12_pair_nonempty"] == 1);
        }
        CHECK(cs["fallback_pair_nested"] + cs["fallback_dent_triangle"] + cs["fallback_dent_nonempty"] == 0);
      }
  }
  SECTION("3(c) with its cross-edge / 4(c)(v)(d)-(e): a triangle with two vertices inside") {
    // The triangle (a, b, X) with c and y inside; u = (a, b, c) keeps its
    // triangle as the leftover and B.1.2 closes (b, X, a, c) around y.
    for (int with_parent = 0; with_parent < 2; ++with_parent) {
      Tri2QuadInput in;
      in.points = {{0, 0}, {4, 0}, {2, 4}, {2, 1}, {1.5, 1.2}, {2, -2}};  // a b X c y z
      if (with_parent) in.triangles.push_back({1, 0, 5});
      for (const std::array<int, 3>& t : {std::array<int, 3>{0, 1, 3}, {1, 2, 3}, {3, 2, 4}, {2, 0, 4}, {0, 3, 4}})
        in.triangles.push_back(t);
      INFO("parent " << with_parent);
      const auto r = tri2quad(in);
      check_result(in, r, false);
      std::map<std::string, std::size_t> cs(r.cases.begin(), r.cases.end());
      CHECK(cs["3c_4cvde_leftover_B12"] == 1);
      CHECK(cs["fallback_pair_nested"] + cs["fallback_dent_triangle"] + cs["fallback_dent_nonempty"] == 0);
    }
  }
  SECTION("4(c)(ii) with B.2.1 type 3: a point on the outgoing edge, the parent a degenerate quad (step 1)") {
    // u = (a, b, c) and the pair (c, b, w), (w, b, x) form a pentagon with
    // no leftover form within budget; the parent (b, a, z) takes the point.
    Tri2QuadInput in;
    in.points = kDentPoints;
    in.triangles = kDentTriangles;
    in.triangles.insert(in.triangles.begin(), std::array<int, 3>{1, 0, 5});
    const auto r = tri2quad(in);
    check_result(in, r, false);
    std::map<std::string, std::size_t> cs(r.cases.begin(), r.cases.end());
    CHECK(cs["4c_quad_to_grandparent"] == 1);
    CHECK(cs["4cii_B21_type3_edge_point"] == 1);
    CHECK(cs["4c_convex_quad"] == 1);  // the parent's triangle with the point
    // Type 3: 4 quads and 3 points (one on the edge); the parent 1 quad.
    CHECK(r.quads.size() == 5);
    CHECK(r.steiner == 3);
  }
  SECTION("a dangling constraint edge is refused, naming the edge") {
    Tri2QuadInput in;
    in.points = {{0, 0}, {2, 0}, {2, 2}, {0, 2}, {1, 1}};
    in.triangles = {{0, 1, 4}, {1, 2, 4}, {2, 3, 4}, {3, 0, 4}};
    in.constraints = {{0, 4}};
    in.index_base = 1;
    try {
      tri2quad(in);
      FAIL("no error");
    } catch (const Error& e) {
      const std::string w = e.what();
      CHECK((w.find("(1, 5)") != std::string::npos || w.find("(5, 1)") != std::string::npos));
      CHECK(w.find("dangles") != std::string::npos);
    }
  }
  SECTION("a constraint that is not a mesh edge is refused") {
    Tri2QuadInput in;
    in.points = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
    in.triangles = {{0, 1, 2}, {0, 2, 3}};
    in.constraints = {{1, 3}};
    CHECK_THROWS_AS(tri2quad(in), Error);
  }
}

// Each remaining case of steps 2-5 and each lemma's configuration on a
// hand-made mesh whose BFS tree forces it: the counters show that exactly
// that case ran (beside the cases of the rest of the mesh), and the quads
// inside the case's region are what the thesis's case produces. The root
// is triangle 0 (its first boundary edge is the root edge).
TEST_CASE("Steps on hand-made meshes: the remaining cases of steps 2-5 and of B.2.1 and B.2.2",
          "[tri2quad][steps]") {
  SECTION("4(b) and B.2.1 type 1: two leaves, the outgoing edge in the centre triangle") {
    // P = (A, B, C) below the root (B, A, z) with leaves (C, B, y) and (A, C,
    // x); C is reflex in the pentagon (A, B, y, C, x), so only the fan from C
    // triangulates it (type 1) and no ear leaves a convex quad.
    const P2 A{0, 0}, B{4, 0}, C{2, 2}, y{4, 2.5}, x{0, 2.5}, z{2, -2};
    const auto in = mesh({A, B, C, y, x, z}, {{1, 0, 5}, {0, 1, 2}, {2, 1, 3}, {0, 2, 4}});
    const auto r = tri2quad(in);
    check_result(in, r, false);
    CHECK(cases_run(r) == Cases{{"4b_B21_type1", 1}, {"4c_convex_quad", 1}});
    // Two quads and the leftover (A, B, p1), p1 in the centre triangle; the
    // root closes it with its own triangle as one quad.
    const int p1 = fourth_corner(r, 0, 1, 5);
    REQUIRE(p1 >= int(in.points.size()));
    CHECK(strictly_inside(A, B, C, r.points[p1]));
    const std::vector<P2> region = {A, B, y, C, x};
    const Local l = local_result(r, region);
    CHECK(l.convex);
    CHECK(l.quads == 2);
    CHECK(l.steiner == 1);
    CHECK(l.area == Approx(poly_area(region) - poly_area({A, B, r.points[p1]})));
    CHECK(r.quads.size() == 3);
    CHECK(r.steiner == 1);
  }
  SECTION("B.2.1 type 2: the pair's diagonal at C (4(c)(ii)), and its mirror image") {
    // P = (A, B, C) and the pair (C, B, w), (C, w, x) reflex at C: the
    // pentagon (A, B, w, x, C) has only the fan from C, so AB lies in an ear
    // away from the common vertex. 3 quads, 2 points and a leftover.
    for (int mirror = 0; mirror < 2; ++mirror) {
      std::vector<P2> p = {{0, 0}, {4, 0}, {2, 2}, {4, 2}, {0.5, 3.2}, {2, -2}};
      if (mirror)
        for (P2& v : p) v[0] = 4 - v[0];
      const auto in = mesh(p, {{1, 0, 5}, {0, 1, 2}, {2, 1, 3}, {2, 3, 4}});
      INFO("mirror " << mirror);
      const auto r = tri2quad(in);
      check_result(in, r, false);
      CHECK(cases_run(r) == Cases{{"4c_quad_to_grandparent", 1}, {"4cii_B21_type2", 1}, {"4c_convex_quad", 1}});
      const int p2 = fourth_corner(r, 0, 1, 5);
      REQUIRE(p2 >= int(in.points.size()));
      std::vector<P2> region = {p[0], p[1], p[3], p[4], p[2]};
      if (mirror) std::reverse(region.begin(), region.end());
      const Local l = local_result(r, region);
      CHECK(l.convex);
      CHECK(l.quads == 3);
      CHECK(l.steiner == 2);
      CHECK(l.area == Approx(poly_area(region) - std::fabs(poly_area({p[0], p[1], r.points[p2]}))));
      CHECK(r.quads.size() == 4);
      CHECK(r.steiner == 2);
    }
  }
  SECTION("B.2.1 type 3 mirrored: the pair on the other side, a point on the outgoing edge") {
    std::vector<P2> p = kDentPoints;
    for (P2& v : p) v[0] = 4 - v[0];
    auto tris = kDentTriangles;
    tris.insert(tris.begin(), std::array<int, 3>{1, 0, 5});
    const auto in = mesh(p, tris);
    const auto r = tri2quad(in);
    check_result(in, r, false);
    CHECK(cases_run(r) == Cases{{"4c_quad_to_grandparent", 1}, {"4cii_B21_type3_edge_point", 1}, {"4c_convex_quad", 1}});
    // The pentagon (a, b, x, w, c) (mirrored: clockwise) closed with one of
    // its 3 points on ab: 4 quads, no leftover; the parent one quad (step 1).
    std::vector<P2> region = {p[0], p[1], p[4], p[3], p[2]};
    std::reverse(region.begin(), region.end());
    const Local l = local_result(r, region);
    CHECK(l.convex);
    CHECK(l.quads == kDentQuads);
    CHECK(l.steiner == kDentSteiner);
    // The point m on ab leans into u (the perturbation of step 1), so the
    // parent's triangle with it is one quad.
    const int m = edge_point(r, p[1], p[0]);
    CHECK(fourth_corner(r, 0, 1, 5) == m);
    CHECK(l.area == Approx(poly_area(region) - std::fabs(poly_area({p[0], p[1], r.points[m]}))));
  }
  SECTION("Step 2: a degenerate pentagon (points on two edges) becomes a quad and a leftover") {
    // P = (A, B, C) below the root (B, A, z) gets points m1 on BC and m2 on
    // CA from two 4(c)(ii) subtrees: the pentagon (A, B, m1, C, m2) gives 1
    // quad, no point, and a leftover on AB (Table 3.1, step 2).
    std::vector<P2> p = {{0, 0}, {8, 0}, {4, 4}, {4, -3}};
    std::vector<std::array<int, 3>> tris = {{1, 0, 3}, {0, 1, 2}};
    add_dent(p, tris, 1, 2);
    add_dent(p, tris, 2, 0);
    const auto in = mesh(p, tris);
    const auto r = tri2quad(in);
    check_result(in, r, false);
    CHECK(cases_run(r) == Cases{{"4cii_B21_type3_edge_point", 2}, {"4c_quad_to_grandparent", 2},
                                {"B21_pentagon_ear", 1}, {"4c_convex_quad", 1}});
    const int m1 = edge_point(r, p[2], p[1]), m2 = edge_point(r, p[0], p[2]);
    const int apex = fourth_corner(r, 0, 1, 3);
    CHECK((apex == m1 || apex == m2));
    const std::vector<P2> region = {p[0], p[1], r.points[m1], p[2], r.points[m2]};
    const Local l = local_result(r, region);
    CHECK(l.convex);
    CHECK(l.quads == 1);
    CHECK(l.steiner == 0);
    CHECK(l.area == Approx(poly_area(region) - poly_area({p[0], p[1], r.points[apex]})));
    CHECK(r.quads.size() == 2 * kDentQuads + 1 + 1);
    CHECK(r.steiner == 2 * kDentSteiner);
  }
  SECTION("4(a): a degenerate quadrilateral parent and a leaf") {
    // P = (b, a, z) gets the point m on (b, a) from its child u and
    // the leaf (a, x, z); the root is (b, z, t). A point in P splits the
    // pentagon (z, b, m, a, x) into 2 quads and the leftover (z, b, s').
    std::vector<P2> p = kDentPoints;
    const P2 x{-1, 0.3}, t{4.5, -2};
    p.push_back(x);  // 6
    p.push_back(t);  // 7
    auto tris = kDentTriangles;
    tris.insert(tris.begin(), {std::array<int, 3>{1, 5, 7}, {1, 0, 5}});
    tris.push_back({0, 6, 5});
    const auto in = mesh(p, tris);
    const auto r = tri2quad(in);
    check_result(in, r, false);
    CHECK(cases_run(r) == Cases{{"4cii_B21_type3_edge_point", 1}, {"4c_quad_to_grandparent", 1},
                                {"4b_B21_type1", 1}, {"4c_convex_quad", 1}});
    const P2 &a = p[0], &b = p[1], &z = p[5];
    const int m = edge_point(r, p[0], p[1]);
    const int s = fourth_corner(r, 5, 1, 7);
    REQUIRE(s >= int(in.points.size()));
    CHECK(strictly_inside(b, a, z, r.points[s]));
    const std::vector<P2> region = {b, r.points[m], a, x, z};
    const Local l = local_result(r, region);
    CHECK(l.convex);
    CHECK(l.quads == 2);
    CHECK(l.steiner == 1);
    CHECK(l.area == Approx(poly_area(region) - poly_area({z, b, r.points[s]})));
    CHECK(r.quads.size() == kDentQuads + 2 + 1);
    CHECK(r.steiner == kDentSteiner + 1);
  }
  SECTION("3(a): a degenerate quadrilateral parent and a non-empty triangle") {
    // As 4(a), with three triangles around y across (a, z). Joining m to z
    // leaves the triangle (z, b, m) and the quadrilateral (z, m, a, x)
    // around y (B.1.2): 5 quads, 3 points. (z, b, y) is not a triangle,
    // so B.2.2's first form cannot run.
    std::vector<P2> p = kDentPoints;
    const P2 x{1.5, -4}, t{4.5, -2}, y{1.8, -2.5};
    for (const P2& v : {x, t, y}) p.push_back(v);  // 6, 7, 8
    auto tris = kDentTriangles;
    tris.insert(tris.begin(), {std::array<int, 3>{1, 5, 7}, {1, 0, 5}});
    for (const std::array<int, 3>& tr : {std::array<int, 3>{5, 0, 8}, {0, 6, 8}, {6, 5, 8}}) tris.push_back(tr);
    const auto in = mesh(p, tris);
    const auto r = tri2quad(in);
    check_result(in, r, false);
    CHECK(cases_run(r) == Cases{{"4cii_B21_type3_edge_point", 1}, {"4c_quad_to_grandparent", 1},
                                {"3_nonempty_triangle", 1}, {"3c_B22_pentagon_point", 1}, {"4c_convex_quad", 1}});
    const P2 &a = p[0], &b = p[1], &z = p[5];
    const int m = edge_point(r, p[0], p[1]);
    CHECK(fourth_corner(r, 5, 1, 7) == m);  // the leftover is (z, b, m)
    const std::vector<P2> region = {b, r.points[m], a, x, z};
    const Local l = local_result(r, region);
    CHECK(l.convex);
    CHECK(l.quads == 5);
    CHECK(l.steiner == 3);
    CHECK(l.area == Approx(poly_area(region) - poly_area({z, b, r.points[m]})));
    CHECK(r.quads.size() == kDentQuads + 5 + 1);
    CHECK(r.steiner == kDentSteiner + 3);
  }
  SECTION("3(b): a triangle parent of degree 2 and a non-empty triangle (B.1.2)") {
    // P = (A, B, C) below the root (B, A, z) and three triangles around y
    // across BC: the quadrilateral (A, B, X, C) around y, 5 quads and 3
    // points, no leftover; the root is then alone (Joe's split: 5 and 5).
    const std::vector<P2> p = {{0, 0}, {4, 0}, {2, 2}, {4, 3}, {2, -2}, {3.3, 1.7}};
    const auto in = mesh(p, {{1, 0, 4}, {0, 1, 2}, {2, 1, 5}, {1, 3, 5}, {3, 2, 5}});
    const auto r = tri2quad(in);
    check_result(in, r, false);
    CHECK(cases_run(r) == Cases{{"3_nonempty_triangle", 1}, {"3b_B12_quad_point", 1}, {"5bd_joe_split", 1}});
    const std::vector<P2> region = {p[0], p[1], p[3], p[2]};
    const Local l = local_result(r, region);
    CHECK(l.convex);
    CHECK(l.quads == 5);
    CHECK(l.steiner == 3);
    CHECK(l.area == Approx(poly_area(region)));
    CHECK(r.quads.size() == 5 + 5);
    CHECK(r.steiner == 3 + 5);
  }
  SECTION("4(c)(i): a degenerate quadrilateral and a non-convex pair below it (B.1.1)") {
    // P = (b, a, z) with m on (b, a) and the pair (z, a, x), (x, a, w),
    // reflex at a: the hexagon (b, m, a, w, x, z) closes with 2 + k quads
    // and k <= 3 points, no leftover; the root (b, z, t) is then alone
    // (Joe's split: 5 quads, 5 points).
    std::vector<P2> p = kDentPoints;
    const P2 x{0, -2.5}, w{-1, 1.5}, t{4.5, -2};
    for (const P2& v : {x, w, t}) p.push_back(v);  // 6, 7, 8
    auto tris = kDentTriangles;
    tris.insert(tris.begin(), {std::array<int, 3>{1, 5, 8}, {1, 0, 5}});
    tris.push_back({5, 0, 6});
    tris.push_back({6, 0, 7});
    const auto in = mesh(p, tris);
    const auto r = tri2quad(in);
    check_result(in, r, false);
    CHECK(cases_run(r) == Cases{{"4cii_B21_type3_edge_point", 1}, {"4c_quad_to_grandparent", 2},
                                {"4ci_4ciii_B11_hexagon", 1}, {"5bd_joe_split", 1}});
    const int m = edge_point(r, p[0], p[1]);
    const std::vector<P2> region = {p[1], r.points[m], p[0], w, x, p[5]};
    const Local l = local_result(r, region);
    CHECK(l.convex);
    CHECK(l.steiner <= 3);
    CHECK(l.quads == 2 + l.steiner);
    CHECK(l.area == Approx(poly_area(region)));
    CHECK(r.quads.size() == kDentQuads + l.quads + 5);
    CHECK(r.steiner == kDentSteiner + l.steiner + 5);
  }
  SECTION("4(c)(iii): a non-convex pair and a leaf, a hexagon or (cross-edge) a quadrilateral around C") {
    // P = (A, B, C) below the root (B, A, z), the pair (C, B, w), (C, w, x),
    // and the leaf (A, C, x2) (a hexagon, B.1.1) or (A, C, x) (a cross-edge
    // with the pair: the quadrilateral (A, B, w, x) around C, B.1.2). The
    // root is then alone (Joe's split: 5 quads, 5 points).
    const std::vector<P2> p = {{0, 0}, {4, 0}, {2, 2}, {4, 2}, {0.5, 3.2}, {2, -2}, {0.3, 1.5}};
    for (int cross = 0; cross < 2; ++cross) {
      INFO("cross-edge " << cross);
      const auto in = mesh(p, {{1, 0, 5}, {0, 1, 2}, {2, 1, 3}, {2, 3, 4}, {0, 2, cross ? 4 : 6}});
      const auto r = tri2quad(in);
      check_result(in, r, false);
      const std::vector<P2> region =
          cross ? std::vector<P2>{p[0], p[1], p[3], p[4]} : std::vector<P2>{p[0], p[1], p[3], p[4], p[2], p[6]};
      const Local l = local_result(r, region);
      CHECK(l.convex);
      CHECK(l.area == Approx(poly_area(region)));
      if (cross) {
        CHECK(cases_run(r) == Cases{{"4c_quad_to_grandparent", 1}, {"3b_B12_quad_point", 1}, {"5bd_joe_split", 1}});
        CHECK(l.quads == 5);
        CHECK(l.steiner == 3);
      } else {
        CHECK(cases_run(r) == Cases{{"4c_quad_to_grandparent", 1}, {"4ci_4ciii_B11_hexagon", 1}, {"5bd_joe_split", 1}});
        CHECK(l.steiner <= 3);
        CHECK(l.quads == 2 + l.steiner);
      }
      CHECK(r.quads.size() == l.quads + 5);
      CHECK(r.steiner == l.steiner + 5);
    }
  }
  SECTION("5(a): the root with two leaves (a pentagon) or a non-empty triangle") {
    const P2 A{0, 0}, B{4, 0};
    {
      // The pentagon (A, B, y, C, x): a point m on the root edge AB and
      // B.1.1 on the hexagon (A, m, B, y, C, x): 2 + k quads, 1 + k points.
      const std::vector<P2> p = {A, B, {2, 2}, {4, 2.5}, {0, 2.5}};
      const auto in = mesh(p, {{0, 1, 2}, {2, 1, 3}, {0, 2, 4}});
      const auto r = tri2quad(in);
      check_result(in, r, false);
      CHECK(cases_run(r) == Cases{{"5_B11_root_pentagon_edge_point", 1}});
      CHECK(steiner_on(r, A, B) == 1);
      CHECK(r.steiner <= 4);
      CHECK(r.quads.size() == 2 + r.steiner - 1);
      // --allow-outside: B.2.1 (type 1 here) and the leftover closed by a
      // point outside the domain (Fig. 3.16): 3 quads, 2 points.
      Tri2QuadOptions o;
      o.allow_outside = true;
      const auto r2 = tri2quad(in, o);
      check_result(in, r2, true);
      CHECK(cases_run(r2) == Cases{{"4b_B21_type1", 1}, {"5bd_outside_point", 1}});
      CHECK(r2.quads.size() == 3);
      CHECK(r2.steiner == 2);
      CHECK(r2.steiner_outside == 1);
    }
    {
      // The leaves share an edge: the non-empty triangle (A, B, y) around C;
      // m on AB makes the quadrilateral (A, m, B, y) around C (B.1.2, Fig.
      // 3.15): 5 quads, 4 points (in both modes: m stays on the edge).
      const P2 C{2, 1}, y{2, 3};
      const auto in = mesh({A, B, C, y}, {{0, 1, 2}, {2, 1, 3}, {0, 2, 3}});
      for (int outside = 0; outside < 2; ++outside) {
        Tri2QuadOptions o;
        o.allow_outside = outside == 1;
        const auto r = tri2quad(in, o);
        check_result(in, r, o.allow_outside);
        CHECK(cases_run(r) == Cases{{"3b_B12_quad_point", 1}});
        const Local l = local_result(r, {A, B, y});
        CHECK(l.convex);
        CHECK(l.quads == 5);
        CHECK(l.steiner == 4);
        CHECK(l.area == Approx(poly_area({A, B, y})));
        CHECK(steiner_on(r, A, B) == 1);
        CHECK(r.steiner_outside == 0);
      }
    }
  }
  SECTION("5(b): the root a degenerate quadrilateral with one leaf") {
    // The root P = (b, a, z) (root edge (z, b)) gets m on (b, a) and the
    // leaf (a, x, z). Default: a point on the root edge and B.1.1 on the
    // hexagon; --allow-outside: 4(a) (2 quads, 1 point) and the leftover
    // closed by a point outside: 3 quads, 2 points (Table 3.1).
    std::vector<P2> p = kDentPoints;
    const P2 x{-1, 0.3};
    p.push_back(x);
    auto tris = kDentTriangles;
    tris.insert(tris.begin(), std::array<int, 3>{1, 0, 5});
    tris.push_back({0, 6, 5});
    const auto in = mesh(p, tris);
    const auto r = tri2quad(in);
    check_result(in, r, false);
    CHECK(cases_run(r) ==
          Cases{{"4cii_B21_type3_edge_point", 1}, {"4c_quad_to_grandparent", 1}, {"5_B11_root_pentagon_edge_point", 1}});
    const int m = edge_point(r, p[0], p[1]);
    const std::vector<P2> region = {p[1], r.points[m], p[0], x, p[5]};
    const Local l = local_result(r, region);
    CHECK(l.convex);
    CHECK(l.area == Approx(poly_area(region)));
    CHECK(l.steiner <= 4);
    CHECK(l.quads == 2 + l.steiner - 1);
    CHECK(steiner_on(r, p[5], p[1]) == 1);
    Tri2QuadOptions o;
    o.allow_outside = true;
    const auto r2 = tri2quad(in, o);
    check_result(in, r2, true);
    CHECK(cases_run(r2) == Cases{{"4cii_B21_type3_edge_point", 1}, {"4c_quad_to_grandparent", 1},
                                 {"4b_B21_type1", 1}, {"5bd_outside_point", 1}});
    CHECK(r2.quads.size() == kDentQuads + 3);
    CHECK(r2.steiner == kDentSteiner + 2);
    CHECK(r2.steiner_outside == 1);
  }
  SECTION("4(c)(v)(a)-(c): two non-convex pairs with a cross-edge around C (B.2.2)") {
    // P = (A, B, C) below the root (B, A, z), the pairs (C, B, w1), (C, w1,
    // x) and (A, C, w2), (w2, C, x) meeting at (C, x): the pentagon (A, B,
    // w1, x, w2) around C. Here the leftover is (A, B, C) and B.1.1 closes
    // the hexagon left (2 + k quads, k <= 3 points).
    const std::vector<P2> p = {{0, 0}, {4, 0}, {1.75, 1.5}, {3.43, 2.12}, {3.68, 3.13}, {2, -2}, {-2.39, 2.92}};
    const auto in = mesh(p, {{1, 0, 5}, {0, 1, 2}, {2, 1, 3}, {2, 3, 4}, {0, 2, 6}, {6, 2, 4}});
    const auto r = tri2quad(in);
    check_result(in, r, false);
    CHECK(cases_run(r) ==
          Cases{{"4c_quad_to_grandparent", 2}, {"3c_B22_pentagon_point", 1}, {"4c_convex_quad", 1}});
    CHECK(fourth_corner(r, 0, 1, 5) == 2);
    const std::vector<P2> region = {p[0], p[1], p[3], p[4], p[6]};
    const Local l = local_result(r, region);
    CHECK(l.convex);
    CHECK(l.steiner <= 3);
    CHECK(l.quads == 2 + l.steiner);
    CHECK(l.area == Approx(poly_area(region) - poly_area({p[0], p[1], p[2]})));
    CHECK(r.quads.size() == l.quads + 1);
    CHECK(r.steiner == l.steiner);
  }
  SECTION("B.2.2 (3(c) without cross-edge): a pentagon with a point, its three cases") {
    // P = (A, B, C) below the root (B, A, z), the non-empty triangle
    // (C, B, X) around y and the leaf (A, C, x): the pentagon (A, B, X, C, x)
    // around y leaves a triangle on AB, which the root closes as one quad.
    const P2 A{0, 0}, B{4, 0}, z{2, -2};
    struct Form { const char* name; P2 y, C, X, x; };
    // (i) y sees AB: the leftover (A, B, y), B.1.1 on the hexagon left;
    // (ii) an ear on AB, B.1.2 on the quadrilateral with y (5 quads, 3
    // points); (iii) neither: the type-1 split of the centre triangle
    // (A, B, C) and B.1.2 on the quadrilateral holding y (6 quads, 4 points).
    const Form forms[] = {{"i", {2.61, 1.3}, {0.9, 2.62}, {2.79, 3.04}, {-1.1, 1.86}},
                          {"ii", {4.18, 0.85}, {3.16, 0.6}, {4.47, 1.18}, {1.64, 1.05}},
                          {"iii", {3.13, 1.36}, {2.06, 0.64}, {3.45, 2.51}, {1.05, 2.15}}};
    for (const Form& f : forms) {
      INFO("B.2.2 case " << f.name);
      const auto in = mesh({A, B, f.C, f.X, f.x, z, f.y},
                           {{1, 0, 5}, {0, 1, 2}, {2, 1, 6}, {1, 3, 6}, {3, 2, 6}, {0, 2, 4}});
      const auto r = tri2quad(in);
      check_result(in, r, false);
      const std::string form = f.name;
      CHECK(cases_run(r) == Cases{{"3_nonempty_triangle", 1},
                                  {form == "iii" ? "B22_middle_type1_B12" : "3c_B22_pentagon_point", 1},
                                  {"4c_convex_quad", 1}});
      const int apex = fourth_corner(r, 0, 1, 5);
      REQUIRE(apex >= 0);
      const std::vector<P2> region = {A, B, f.X, f.C, f.x};
      const Local l = local_result(r, region);
      CHECK(l.convex);
      CHECK(l.area == Approx(poly_area(region) - poly_area({A, B, r.points[apex]})));
      if (form == "i") {
        CHECK(apex == 6);
        CHECK(l.steiner <= 3);
        CHECK(l.quads == 2 + l.steiner);
      } else if (form == "ii") {
        CHECK((apex == 3 || apex == 4));
        CHECK(l.quads == 5);
        CHECK(l.steiner == 3);
      } else {
        REQUIRE(apex >= int(in.points.size()));
        CHECK(strictly_inside(A, B, f.C, r.points[apex]));
        CHECK(l.quads == 6);
        CHECK(l.steiner == 4);
      }
      CHECK(r.quads.size() == l.quads + 1);
      CHECK(r.steiner == l.steiner);
    }
  }
}

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

// Diagnostic (hidden): B.1.1 on spikier random hexagons.
TEST_CASE("B.1.1 success rate on spiky hexagons", "[.hexrate]") {
  std::mt19937 g(77);
  int done = 0, tried = 0, r3 = 0, r3done = 0;
  for (int it = 0; it < 40000; ++it) {
    auto v = random_star(g, 6, 0.03, 1.0);
    if (!simple_ccw(v)) continue;
    int reflex = 0;
    for (int i = 0; i < 6; ++i) reflex += orientation(v[(i + 5) % 6], v[i], v[(i + 1) % 6]) <= 0;
    ++tried;
    LocalPatch lp = patch_of(v);
    const bool ok = t2q::hexagon(lp, ring(6));
    done += ok;
    if (reflex == 3) { ++r3; r3done += ok; }
  }
  std::printf("spiky hexagons: %d of %d; with 3 reflex corners %d of %d\n", done, tried, r3done, r3);
}

// ------------------------------------------------------------ pairs first
namespace {

// The output segments are quad edges, none twice, each on an input
// constraint or boundary edge, and together exactly as long as those.
void check_segments(const Tri2QuadInput& in, const Tri2QuadResult& r) {
  const auto& P = r.points;
  std::set<std::pair<int, int>> quad_edges, seen;
  for (const auto& q : r.quads)
    for (int k = 0; k < 4; ++k) quad_edges.insert({std::min(q[k], q[(k + 1) % 4]), std::max(q[k], q[(k + 1) % 4])});
  std::map<std::pair<int, int>, int> te;
  for (const auto& t : in.triangles)
    for (int k = 0; k < 3; ++k) ++te[{std::min(t[k], t[(k + 1) % 3]), std::max(t[k], t[(k + 1) % 3])}];
  std::set<std::pair<int, int>> input;
  for (const auto& [e, n] : te) if (n == 1) input.insert(e);
  for (const auto& c : in.constraints) input.insert({std::min(c[0], c[1]), std::max(c[0], c[1])});
  double len_in = 0, len_out = 0;
  for (const auto& e : input) len_in += std::hypot(P[e.second][0] - P[e.first][0], P[e.second][1] - P[e.first][1]);
  std::size_t not_edge = 0, twice = 0, off = 0;
  for (const auto& s : r.segments) {
    const std::pair<int, int> e{std::min(s[0], s[1]), std::max(s[0], s[1])};
    not_edge += !quad_edges.count(e);
    twice += !seen.insert(e).second;
    len_out += std::hypot(P[e.second][0] - P[e.first][0], P[e.second][1] - P[e.first][1]);
    bool on = false;  // both ends on one input segment
    for (const auto& c : input) {
      const P2 a = P[c.first], b = P[c.second];
      const double len2 = (b[0] - a[0]) * (b[0] - a[0]) + (b[1] - a[1]) * (b[1] - a[1]);
      auto inside = [&](const P2& p) {
        const double cr = (b[0] - a[0]) * (p[1] - a[1]) - (b[1] - a[1]) * (p[0] - a[0]);
        const double t = ((p[0] - a[0]) * (b[0] - a[0]) + (p[1] - a[1]) * (b[1] - a[1])) / len2;
        return std::fabs(cr) <= 1e-9 * len2 && t >= -1e-12 && t <= 1 + 1e-12;
      };
      if (inside(P[e.first]) && inside(P[e.second])) { on = true; break; }
    }
    off += !on;
  }
  CHECK(not_edge == 0);
  CHECK(twice == 0);
  CHECK(off == 0);
  CHECK(len_out == Approx(len_in).epsilon(1e-9));
}

// An n x n grid of unit squares, each split by its "/" diagonal (or, with
// g, by a random one), the boundary as constraint segments.
Tri2QuadInput square_grid(int n, std::mt19937* g = nullptr) {
  Tri2QuadInput in;
  for (int y = 0; y <= n; ++y)
    for (int x = 0; x <= n; ++x) in.points.push_back({double(x), double(y)});
  auto id = [&](int x, int y) { return y * (n + 1) + x; };
  for (int y = 0; y < n; ++y)
    for (int x = 0; x < n; ++x) {
      const int a = id(x, y), b = id(x + 1, y), c = id(x + 1, y + 1), d = id(x, y + 1);
      if (g && (*g)() % 2) {
        in.triangles.push_back({a, b, d});
        in.triangles.push_back({b, c, d});
      } else {
        in.triangles.push_back({a, b, c});
        in.triangles.push_back({a, c, d});
      }
    }
  return in;
}

} // namespace

TEST_CASE("pairs first (--pair-above): every guarantee on random meshes", "[tri2quad][pairs][property]") {
  std::mt19937 g(1998);
  std::size_t meshes = 0, pairs = 0, returned = 0, abandoned = 0, total_q = 0, plain_q = 0;
  for (int it = 0; it < 700; ++it) {
    const int npts = 5 + int(g() % 250);
    const int holes = int(g() % 3), loops = int(g() % 3);
    const Tri2QuadInput in = random_cdt(g, npts, holes, loops);
    if (in.triangles.empty()) continue;
    Tri2QuadOptions o;
    o.pair_above = it % 2 ? 20 : 30;  // Delaunay pairs are seldom better
    o.allow_outside = it % 4 == 3;
    INFO("mesh " << it << ": " << in.triangles.size() << " triangles, " << holes << " holes, " << loops << " loops");
    const auto r = tri2quad(in, o);
    check_result(in, r, o.allow_outside);
    if (!o.allow_outside) check_segments(in, r);
    REQUIRE(r.region.size() == r.quads.size());
    std::map<std::string, std::size_t> c(r.cases.begin(), r.cases.end());
    pairs += c["pairs_first"];
    returned += c["pairs_returned"];
    abandoned += c["pairs_first_abandoned"];
    total_q += r.quads.size();
    plain_q += tri2quad(in, {}).quads.size();
    ++meshes;
  }
  WARN("pairs first on " << meshes << " random CDTs: " << pairs << " pairs, " << returned << " returned, "
                         << abandoned << " abandoned; quads " << total_q << " (plain " << plain_q << ")");
  CHECK(meshes > 500);
  CHECK(pairs > 0);
  // Groups left odd by the greedy pairs were joined to the boundary.
  CHECK(returned > 0);
}

TEST_CASE("pairs first on a square grid: every square comes back, where the BFS pairing shears", "[tri2quad][pairs]") {
  std::mt19937 g(12);
  for (int variant = 0; variant < 2; ++variant) {
    const int n = 24;
    const Tri2QuadInput in = square_grid(n, variant ? &g : nullptr);
    Tri2QuadOptions o;
    o.pair_above = 40;
    const auto r = tri2quad(in, o);
    check_result(in, r, false);
    check_segments(in, r);
    CHECK(r.quads.size() == std::size_t(n * n));
    CHECK(r.steiner == 0);
    double worst = 45;
    for (const auto& q : r.quads) worst = std::min(worst, joe_mu(r.points[q[0]], r.points[q[1]], r.points[q[2]], r.points[q[3]]));
    CHECK(worst > 45 - 1e-9);
    // The thesis's BFS pairing alone leaves parallelograms (mu 18.4).
    const auto plain = tri2quad(in, {});
    std::size_t poor = 0;
    for (const auto& q : plain.quads)
      poor += joe_mu(plain.points[q[0]], plain.points[q[1]], plain.points[q[2]], plain.points[q[3]]) < 40;
    CHECK(poor > plain.quads.size() / 10);
  }
  // An odd count (a notch triangle on one side): one group is odd, its
  // point goes on the input boundary and every guarantee still holds.
  Tri2QuadInput in = square_grid(9);
  in.points.push_back({4.5, -0.7});
  in.triangles.push_back({4, int(in.points.size()) - 1, 5});
  Tri2QuadOptions o;
  o.pair_above = 40;
  const auto r = tri2quad(in, o);
  check_result(in, r, false);
  check_segments(in, r);
  std::map<std::string, std::size_t> c(r.cases.begin(), r.cases.end());
  CHECK(c["pairs_first_abandoned"] == 0);
  CHECK(c["pairs_first"] >= 70);
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
