// The local crossing search of the surface-nets mesh (crossings.cpp): the
// same pairs as a box intersection over all triangles (complete), the
// same rules as CGAL's self_intersections on each label's surface, the
// incremental search (some quads only) the same as the global pairs with a
// triangle of those quads; a crossing of two interfaces with no label in
// common (1|2 against 3|4) found and untangled; no crossing left after
// untangling.
#include "surfacenets/surface_nets.hpp"

#include "mesh/embedding.hpp"
#include "surfacenets/certify_labels.hpp"
#include "surfacenets/surface_nets_detail.hpp"
#include "util/error.hpp"
#include "wellcomposed/label_images.hpp"
#include "wellcomposed/well_composed_partition.hpp"

#include <catch2/catch.hpp>

#include <algorithm>
#include <random>
#include <set>

using namespace imgmesh;
using namespace imgmesh::test;

namespace {

using Pairs = std::vector<std::array<std::size_t, 2>>;

// Every vertex at a random point of its closed cell (strict: of its open
// cell), on the quarter-voxel grid, so that vertices on cell faces,
// touching and coplanar triangles and degenerate ones are common.
void jitter(InterfaceMesh& m, std::mt19937_64& rng, bool strict = false) {
  std::uniform_int_distribution<int> quarter(strict ? 1 : 0, strict ? 3 : 4);
  for (std::size_t v = 0; v < m.points.size(); ++v) {
    const auto c = m.corner(v);
    Vec3 p;
    for (std::size_t a = 0; a < 3; ++a) p[a] = double(c[a]) - 1 + quarter(rng) / 4.0;
    m.points[v] = m.grid.world(p[0], p[1], p[2]);
  }
  split_quads(m);
}

// Per label, the local pairs among its triangles against CGAL's
// self_intersections on its surface alone.
void check_labels_against_cgal(const InterfaceMesh& m, const Pairs& local) {
  std::set<std::int32_t> labels;
  for (const auto& l : m.labels) labels.insert(l.begin(), l.end());
  for (std::int32_t l : labels) {
    std::vector<std::size_t> face_of;
    const auto tris = label_triangles(m, l, &face_of);
    const SurfaceGeometry g(m.points, tris, std::vector<int>(tris.size(), 0), 1);
    Pairs cgal;
    for (const auto& p : g.intersecting_pairs(1u << 24)) {
      const std::size_t a = face_of[p[0]], b = face_of[p[1]];
      cgal.push_back({std::min(a, b), std::max(a, b)});
    }
    std::sort(cgal.begin(), cgal.end());
    std::vector<std::uint8_t> in(m.triangles.size(), 0);
    for (std::size_t t : face_of) in[t] = 1;
    Pairs mine;
    for (const auto& p : local)
      if (in[p[0]] && in[p[1]]) mine.push_back(p);
    INFO("label " << l);
    CHECK(mine == cgal);
  }
}

// The incremental search from random sets of quads against the global
// pairs with a triangle of the set.
void check_incremental(const InterfaceMesh& m, const Pairs& global, std::mt19937_64& rng) {
  const surfacenets_detail::CrossingSearch search(m);
  for (int share : {1, 10}) {
    std::vector<std::size_t> quads;
    std::vector<std::uint8_t> in(m.quads.size(), 0);
    for (std::size_t f = 0; f < m.quads.size(); ++f)
      if (std::uniform_int_distribution<int>(0, 99)(rng) < share) {
        quads.push_back(f);
        in[f] = 1;
      }
    Pairs expected;
    for (const auto& p : global)
      if (in[p[0] / 2] || in[p[1] / 2]) expected.push_back(p);
    CHECK(search.pairs(quads) == expected);
  }
}

void check_in_cells(const InterfaceMesh& m) {
  for (std::size_t v = 0; v < m.points.size(); ++v) {
    const Vec3 p = m.grid.continuous_index(m.points[v]);
    const auto c = m.corner(v);
    for (std::size_t a = 0; a < 3; ++a) {
      REQUIRE(p[a] >= double(c[a]) - 1 - 1e-9);
      REQUIRE(p[a] <= double(c[a]) + 1e-9);
    }
  }
}

} // namespace

TEST_CASE("crossings: the local search finds every pair the global one finds", "[surfacenets]") {
  std::mt19937_64 rng(3939);
  std::size_t jittered_pairs = 0, moves = 0, tangled_before = 0;
  for (int i = 0; i < 8; ++i) {
    INFO("case " << i);
    const PartitionResult r = make_well_composed_partition(random_balls(rng, 3, 2 + i % 5));
    REQUIRE(r.failed_guarantee().empty());
    const InterfaceMesh rest = interface_mesh(r.image, interface_complex(r.image));
    // Relaxed without untangling: the folds relaxation makes.
    InterfaceMesh m = rest;
    SmoothingOptions o;
    o.untangle = false;
    o.margin = i % 2 ? 0.0 : 0.1;
    smooth_interface_mesh(m, o);
    Pairs local = crossing_pairs(m);
    CHECK(local == soup_crossing_pairs(m.points, m.triangles));
    {  // smoothed and untangled: no pair crosses (the verdict seg2mesh --fast's certificate takes)
      InterfaceMesh untangled = rest;
      SmoothingOptions u = o;
      u.untangle = true;
      smooth_interface_mesh(untangled, u);
      CHECK(soup_crossing_pairs(untangled.points, untangled.triangles).empty());
      tangled_before += !local.empty();
    }
    // Every vertex strictly inside its cell (the search's smaller reach),
    // then anywhere in its closed cell: tangles.
    jitter(m, rng, true);
    CHECK(crossing_pairs(m) == soup_crossing_pairs(m.points, m.triangles));
    jitter(m, rng);
    local = crossing_pairs(m);
    const Pairs global = soup_crossing_pairs(m.points, m.triangles);
    CHECK(local == global);
    CHECK(crossing_pairs(m, 3) == local);  // threads search slices: the same pairs
    jittered_pairs += local.size();
    check_labels_against_cgal(m, local);
    check_incremental(m, global, rng);
    InterfaceMesh threaded = m;
    moves += untangle_interface_mesh(m, rest.points);
    untangle_interface_mesh(threaded, rest.points, 2);
    CHECK((threaded.points == m.points && threaded.triangles == m.triangles));
    CHECK(soup_crossing_pairs(m.points, m.triangles).empty());
    check_in_cells(m);
    certify_labels(m, r.image, false);  // a jittered vertex may leave a voxel centre on the wrong side
  }
  CHECK(jittered_pairs > 1000);  // the comparison saw crossings of every kind
  CHECK(tangled_before > 0);     // relaxation alone left crossings to untangle
  CHECK(moves > 0);
}

// What seg2mesh --fast's certificate takes from the untangling (no pair
// left: label_surface_nets.cpp): from vertices at corners of their cells
// (the folds farthest from rest) one halving back does not undo every
// crossing; the rounds after it, which test the moved quads only, go on
// until none is left, as a search of every pair finds.
TEST_CASE("crossings: untangling over several rounds leaves no pair", "[surfacenets]") {
  std::mt19937_64 rng(3940);
  std::size_t again = 0;  // vertices moved more than once: more than one round
  for (int i = 0; i < 16; ++i) {
    INFO("case " << i);
    const PartitionResult r = make_well_composed_partition(random_balls(rng, 3, 2 + i % 5));
    REQUIRE(r.failed_guarantee().empty());
    const InterfaceMesh rest = interface_mesh(r.image, interface_complex(r.image));
    InterfaceMesh m = rest;
    std::bernoulli_distribution coin(0.5);
    for (std::size_t v = 0; v < m.points.size(); ++v) {
      const auto c = m.corner(v);
      Vec3 p;
      for (std::size_t a = 0; a < 3; ++a) p[a] = double(c[a]) - (coin(rng) ? 1.0 : 0.0);
      m.points[v] = m.grid.world(p[0], p[1], p[2]);
    }
    split_quads(m);
    const InterfaceMesh folded = m;
    const std::size_t moves = untangle_interface_mesh(m, rest.points);
    std::size_t moved = 0;
    for (std::size_t v = 0; v < m.points.size(); ++v) moved += m.points[v] != folded.points[v];
    again += moves - moved;
    CHECK(crossing_pairs(m).empty());
    CHECK(soup_crossing_pairs(m.points, m.triangles).empty());
  }
  CHECK(again > 0);
}

TEST_CASE("crossings: two interfaces with no label in common (1|2 against 3|4)", "[surfacenets]") {
  // 1 below z = 2; above it, 2 for y < 2, 3 and 4 for y >= 2 (x < 2, x >= 2):
  // the 1|2 sheet (z = 2) and the 3|4 sheet (x = 2) meet at corner v =
  // (2, 2, 2) only.
  LabelImage img = label_grid(4, 4, 4);
  paint(img, {0, 0, 0}, {3, 3, 1}, 1);
  paint(img, {0, 0, 2}, {3, 1, 3}, 2);
  paint(img, {0, 2, 2}, {1, 3, 3}, 3);
  paint(img, {2, 2, 2}, {3, 3, 3}, 4);
  const InterfaceComplex k = interface_complex(img);
  REQUIRE(k.failed_guarantee().empty());
  const InterfaceMesh rest = interface_mesh(img, k);
  InterfaceMesh m = rest;
  auto vertex = [&](std::size_t x, std::size_t y, std::size_t z) {
    const std::uint64_t id = x + m.lattice[0] * (y + m.lattice[1] * z);
    const auto it = std::lower_bound(m.corners.begin(), m.corners.end(), id);
    REQUIRE((it != m.corners.end() && *it == id));
    return std::size_t(it - m.corners.begin());
  };
  // Offsets from v's corner position, each vertex within its cell (at most
  // 0.5 from its own corner's): the 1|2 quad at x, y in 1..2 tilted up
  // toward x = 1, the 3|4 quad's diagonal b1 b2 folded down through it.
  const Vec3 v = rest.points[vertex(2, 2, 2)];
  auto place = [&](std::size_t w, double dx, double dy, double dz) {
    m.points[w] = {v[0] + dx, v[1] + dy, v[2] + dz};
  };
  place(vertex(1, 2, 2), -1, 0, 0.4375);
  place(vertex(1, 1, 2), -1, -1, 0.4375);
  const std::size_t b1 = vertex(2, 2, 3), b2 = vertex(2, 3, 2);
  place(b1, -0.4375, -0.4375, 0.5625);
  place(b2, -0.4375, 0.5625, -0.4375);
  split_quads(m);
  // The 3|4 quad split along b1 b2.
  for (std::size_t f = 0; f < m.quads.size(); ++f) {
    const auto& q = m.quads[f];
    if (m.labels[f] != std::array<std::int32_t, 2>{4, 3}) continue;
    for (std::size_t i = 0; i < 2; ++i)
      if ((std::size_t(q[i]) == b1 && std::size_t(q[i + 2]) == b2) || (std::size_t(q[i]) == b2 && std::size_t(q[i + 2]) == b1)) {
        m.triangles[2 * f] = {q[i], q[i + 1], q[(i + 2) % 4]};
        m.triangles[2 * f + 1] = {q[i], q[(i + 2) % 4], q[(i + 3) % 4]};
      }
  }
  check_in_cells(m);
  const Pairs pairs = crossing_pairs(m);
  CHECK(pairs == soup_crossing_pairs(m.points, m.triangles));
  std::size_t foreign = 0;  // pairs of a 1|2 triangle and a 3|4 triangle
  for (const auto& p : pairs) {
    auto l = m.triangle_labels(p[0]), r = m.triangle_labels(p[1]);
    if (l[0] < r[0]) std::swap(l, r);
    foreign += l == std::array<std::int32_t, 2>{4, 3} && r == std::array<std::int32_t, 2>{2, 1};
  }
  CHECK(foreign > 0);
  CHECK(untangle_interface_mesh(m, rest.points) > 0);
  CHECK(crossing_pairs(m).empty());
  CHECK(soup_crossing_pairs(m.points, m.triangles).empty());
  certify_labels(m, img);
}

TEST_CASE("crossings: a vertex outside its cell is refused", "[surfacenets]") {
  const LabelImage img = [] {
    LabelImage i = label_grid(4, 4, 4);
    paint(i, {1, 1, 1}, {2, 2, 2}, 1);
    return i;
  }();
  InterfaceMesh m = interface_mesh(img, interface_complex(img));
  CHECK(crossing_pairs(m).empty());
  m.points[3][0] += 0.75;
  CHECK_THROWS_AS(crossing_pairs(m), Error);
}
