// The conforming surface complex (conforming/conforming_surface.hpp),
// certified by the interface certificate against K(X) on hand-built
// partitions: every interface meshed once, every label's surface of the
// right topology, no crossing, every voxel centre on its label's side,
// triangles within the ratio bound.
#include "conforming/conforming_surface.hpp"
#include "conforming/label_function.hpp"
#include "conforming/mesher.hpp"
#include "image/narrow_labels.hpp"
#include "label_maps.hpp"
#include "mesh/triangle_quality.hpp"
#include "surfacenets/interface_certificate.hpp"
#include "wellcomposed/interface_complex.hpp"
#include "wellcomposed/well_composed_partition.hpp"

#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <random>

using namespace imgmesh;
using namespace imgmesh::test;

namespace {

InterfaceCertificate mesh_and_certify(const LabelImage& x, ConformingSurface& m, const ConformingOptions& o = {}) {
  const LabelFunction f(x, 0.3 * std::min({x.spacing[0], x.spacing[1], x.spacing[2]}));
  const InterfaceComplex k = interface_complex(x);
  InterfaceCertificateOptions co;
  co.lattice = false;
  ConformingOptions oc = o;
  oc.certificate = [&](const std::vector<Vec3>& p, const std::vector<std::array<int, 3>>& t,
                       const std::vector<std::array<std::int32_t, 2>>& l) {
    return certify_interface_mesh(p, t, l, x, k, co).failing_places(p, t, l, k, x);
  };
  m = conforming_surface(f, narrow_labels(x), k, oc);
  return certify_interface_mesh(m.points, m.triangles, m.pairs, x, k, co);
}

double smallest_angle(const ConformingSurface& m) {
  SurfaceMesh s;
  s.points = m.points;
  s.triangles = m.triangles;
  return triangle_quality_report(s).smallest_angle();
}

// Certified, within the ratio bound, every interface of K(X) meshed (its
// triangles carry its pair) and no other.
void check_certified(const char* name, const LabelImage& x) {
  INFO(name);
  ConformingSurface m;
  const InterfaceCertificate c = mesh_and_certify(x, m);
  INFO(c.summary());
  INFO(m.to_json().dump());
  CHECK(!m.max_points_hit);
  CHECK(c.ok());
  CHECK(smallest_angle(m) >= std::asin(1 / (2 * 1.2)) * 180 / M_PI - 1e-9);
  CHECK(c.interfaces.size() == std::size_t(std::count_if(c.interfaces.begin(), c.interfaces.end(), [](const auto& i) {
          return i.triangles > 0 && !i.complex_patches.empty();
        })));
}

} // namespace

TEST_CASE("conforming surfaces of hand-built partitions are certified", "[conforming]") {
  const std::pair<const char*, LabelImage> maps[] = {{"nested shells", nested_shells()},
                                                     {"three labels", three_labels()},
                                                     {"four labels around an edge", four_labels_around_an_edge()}};
  for (const auto& [name, x] : maps) check_certified(name, x);
}

namespace {

// A ball split in two by a helicoid: the curve where 1, 2 and the
// background meet winds twice around the ball.
LabelImage winding_curve(std::size_t n) {
  LabelImage x = label_grid(n, n, n);
  const double c = 0.5 * double(n - 1), r = 0.5 * double(n) - 2;
  for (std::size_t z = 0; z < n; ++z)
    for (std::size_t y = 0; y < n; ++y)
      for (std::size_t i = 0; i < n; ++i) {
        const double dx = double(i) - c, dy = double(y) - c, dz = double(z) - c;
        if (dx * dx + dy * dy + dz * dz > r * r) continue;
        const double a = std::atan2(dy, dx) + 2 * M_PI * dz / r;  // two turns over the height
        x(i, y, z) = std::sin(a) >= 0 ? 1 : 2;
      }
  return make_well_composed_partition(x).image;
}

// Label 2 a layer one voxel thick between 1 below and 3 above.
LabelImage thin_layer() {
  LabelImage x = label_grid(14, 12, 12);
  paint(x, {2, 2, 2}, {11, 9, 5}, 1);
  paint(x, {2, 2, 6}, {11, 9, 6}, 2);
  paint(x, {2, 2, 7}, {11, 9, 9}, 3);
  return x;
}

} // namespace

namespace {

// A noisy map (Voronoi cells of four labels, a sixth of the voxels
// relabelled at random), repaired: patches of one or two faces between
// curves, as k-means segmentations have (the bundled brain map).
LabelImage noisy_map(unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(3, 13);
  LabelImage x = label_grid(16, 16, 16);
  std::vector<std::array<double, 4>> cells;
  for (int i = 0; i < 8; ++i) cells.push_back({u(rng), u(rng), u(rng), double(1 + i % 4)});
  for (std::size_t z = 2; z < 14; ++z)
    for (std::size_t y = 2; y < 14; ++y)
      for (std::size_t i = 2; i < 14; ++i) {
        double best = 1e9;
        for (const auto& c : cells) {
          const double d = std::hypot(double(i) - c[0], double(y) - c[1], double(z) - c[2]);
          if (d < best) best = d, x(i, y, z) = std::int32_t(c[3]);
        }
        if (rng() % 6 == 0) x(i, y, z) = std::int32_t(rng() % 5);
      }
  return make_well_composed_partition(x).image;
}

} // namespace

TEST_CASE("noisy maps are certified", "[conforming]") {
  for (unsigned seed : {1u, 2u, 3u}) {
    const LabelImage x = noisy_map(seed);
    const InterfaceComplex k = interface_complex(x);
    INFO("seed " << seed << ": " << k.patches.size() << " patches");
    check_certified("noisy", x);
  }
}

TEST_CASE("a winding triple curve and a one-voxel layer are certified", "[conforming]") {
  const std::pair<const char*, LabelImage> maps[] = {{"winding curve", winding_curve(20)}, {"thin layer", thin_layer()}};
  for (const auto& [name, x] : maps) check_certified(name, x);
}


// The pass's walks along the Voronoi edges run on `threads` threads, each
// into its facet's slot, and VoxelSides' voxels are located on them first,
// each into its own entry: the same mesh whatever their number.
TEST_CASE("the same mesh whatever the number of threads", "[conforming]") {
  const LabelImage x = noisy_map(2);
  const LabelFunction f(x, 0.3);
  const InterfaceComplex k = interface_complex(x);
  const NarrowLabelImage narrow = narrow_labels(x);
  ConformingOptions o;
  const ConformingSurface one = conforming_surface(f, narrow, k, o);
  o.threads = 3;
  const ConformingSurface three = conforming_surface(f, narrow, k, o);
  CHECK(one.passes == three.passes);
  CHECK(one.pairs == three.pairs);
  CHECK(one.triangles == three.triangles);
  CHECK(one.points == three.points);
}

// The certificate's rounds insert where it fails, in an order of their
// own (not the triangulation's storage order): the same mesh every run.
TEST_CASE("the same mesh every run, the certificate's rounds included", "[conforming]") {
  const LabelImage x = noisy_map(2);
  ConformingSurface a, b;
  mesh_and_certify(x, a);
  mesh_and_certify(x, b);
  REQUIRE(a.certificate_rounds > 0);
  CHECK(a.passes == b.passes);
  CHECK(a.pairs == b.pairs);
  CHECK(a.triangles == b.triangles);
  CHECK(a.points == b.points);
}

// VoxelSides alone (no certificate rounds): every voxel centre next to an
// interface ends in a cell of its own label, so none is on the wrong side
// of its label's surface.
TEST_CASE("VoxelSides leaves no voxel centre on the wrong side", "[conforming]") {
  const std::pair<const char*, LabelImage> maps[] = {{"nested shells", nested_shells()},
                                                     {"winding curve", winding_curve(20)},
                                                     {"thin layer", thin_layer()}};
  for (const auto& [name, x] : maps) {
    INFO(name);
    const LabelFunction f(x, 0.3);
    const InterfaceComplex k = interface_complex(x);
    ConformingOptions o;
    o.max_distance = 0.6;  // coarse: centres near the surface fall on the wrong side unless refined
    const ConformingSurface m = conforming_surface(f, narrow_labels(x), k, o);
    InterfaceCertificateOptions co;
    co.lattice = false;
    const InterfaceCertificate c = certify_interface_mesh(m.points, m.triangles, m.pairs, x, k, co);
    std::size_t wrong = 0;
    for (const auto& l : c.labels) wrong += l.sides_checked ? l.sides.wrong() : 0;
    INFO(c.summary());
    CHECK(wrong == 0);
  }
}

// seg2tet's tetrahedra (tets.on): every label's cells, conforming, their
// boundary stated once (each interface once, out of the higher label), every
// ratio within R, every voxel centre in a cell of its own label, and the
// interfaces still certified.
TEST_CASE("the labels' tetrahedra conform, bound their labels and hold their voxel centres", "[conforming]") {
  const std::pair<const char*, LabelImage> maps[] = {{"nested shells", nested_shells()},
                                                     {"four labels around an edge", four_labels_around_an_edge()},
                                                     {"thin layer", thin_layer()}};
  for (const auto& [name, x] : maps) {
    INFO(name);
    ConformingOptions o;
    o.tets.on = true;
    ConformingSurface m;
    const InterfaceCertificate c = mesh_and_certify(x, m, o);
    INFO(c.summary());
    INFO(m.to_json().dump());
    CHECK(c.ok());
    CHECK(!m.max_points_hit);
    CHECK(!m.cell_rounds_exhausted);
    const TetMesh& t = m.tets;
    REQUIRE(!t.tets.empty());
    CHECK(tet_conformity(t).ok());
    CHECK(boundary_mismatch(t).empty());
    const TetQualityReport q = tet_quality(t);
    CHECK(q.max_radius_edge_ratio <= 2 + 1e-9);
    CHECK(m.centres_checked == x.count());
    CHECK(m.centres_wrong == 0);
    // Every label of the map is a region, and the regions are its labels.
    std::vector<int> regions(t.tet_region), labels;
    std::sort(regions.begin(), regions.end());
    regions.erase(std::unique(regions.begin(), regions.end()), regions.end());
    for (std::int32_t v : x.data)
      if (v != 0) labels.push_back(int(v));
    std::sort(labels.begin(), labels.end());
    labels.erase(std::unique(labels.begin(), labels.end()), labels.end());
    CHECK(regions == labels);
    // Each label's tetrahedra fill about its voxels' volume (the interfaces
    // lie within a voxel of the voxel faces).
    for (const int l : labels) {
      std::size_t voxels = 0;
      for (std::int32_t v : x.data) voxels += v == l;
      const double volume = q.volume_by_region.at(l) / (x.spacing[0] * x.spacing[1] * x.spacing[2]);
      INFO("label " << l << ": " << volume << " against " << voxels << " voxels");
      CHECK(std::abs(volume - double(voxels)) < 0.5 * double(voxels));
    }
  }
}

// Two slabs on each other (a flat interface, its seeds a square lattice,
// four cocircular) with tetrahedra of circumradius at most one voxel: a
// sliver's encroached facet took its surface centre, a lattice as fine
// again, and the slivers ran down to the insertion floor (seg2tet before
// the off-centre rule, capped at 30,000 cell points: 10,430 under 10
// degrees). Its surface point off the centre: every dihedral angle at
// least the bound.
TEST_CASE("slivers on a flat interface refined away without smaller ones", "[conforming]") {
  LabelImage x = label_grid(24, 24, 10);
  paint(x, {2, 2, 2}, {21, 21, 4}, 1);
  paint(x, {2, 2, 5}, {21, 21, 7}, 2);
  ConformingOptions o;
  o.tets.on = true;
  o.tets.cell_size = 1;
  o.tets.max_cell_points = 30000;
  ConformingSurface m;
  const InterfaceCertificate c = mesh_and_certify(x, m, o);
  INFO(c.summary());
  INFO(m.to_json().dump());
  CHECK(c.ok());
  CHECK(!m.cell_points_exhausted);
  CHECK(!m.cell_rounds_exhausted);
  const TetQualityReport q = tet_quality(m.tets);
  CHECK(q.max_radius_edge_ratio <= 2 + 1e-9);
  CHECK(q.min_dihedral >= o.tets.sliver_angle);
  // The direction off the centre drawn from vertex ids: the same mesh again.
  ConformingSurface again;
  mesh_and_certify(x, again, o);
  CHECK(again.tets.points == m.tets.points);
  CHECK(again.tets.tets == m.tets.tets);
}

// The certificate's rounds insert the surface centres near a failing place
// as REFINE does, each only while its facet is still there: two centres of
// neighbouring facets would land 1e-4 voxel apart, and QUALITY would grade
// the mesh down to them (hundreds of triangles in a thousandth of a voxel).
TEST_CASE("the certificate's rounds put no two vertices a hair apart", "[conforming]") {
  for (unsigned seed : {1u, 2u, 3u, 4u}) {
    const LabelImage x = noisy_map(seed);
    ConformingSurface m;
    const InterfaceCertificate c = mesh_and_certify(x, m);
    INFO("seed " << seed << ": " << m.to_json().dump());
    REQUIRE(c.ok());
    double shortest = 1e9;
    for (const auto& t : m.triangles)
      for (int e = 0; e < 3; ++e) {
        const Vec3 &a = m.points[std::size_t(t[e])], &b = m.points[std::size_t(t[(e + 1) % 3])];
        shortest = std::min(shortest, std::hypot(a[0] - b[0], a[1] - b[1], a[2] - b[2]));
      }
    INFO("shortest edge " << shortest);
    CHECK(shortest > 0.01);
  }
}

// The distance bound decided on a bracket (walk_facets: the change not
// placed): beyond_distance on the box of x0 and x1 false only when false at
// every point of the box. Random facets and boxes, the bound a few ulps
// around the largest distance at a corner, so that the decisions are close;
// the box's corners and points inside.
TEST_CASE("the distance bound on a bracket holds wherever in it the point is", "[conforming]") {
  using namespace conforming_detail;
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> u(-1, 1), s(0, 1);
  std::size_t settled = 0, refused = 0;
  for (int n = 0; n < 20000; ++n) {
    Vec3 p[3], x0, x1;
    for (auto& q : p)
      for (int m = 0; m < 3; ++m) q[m] = 10 + u(rng);
    for (int m = 0; m < 3; ++m) x0[m] = 10 + u(rng), x1[m] = x0[m] + 0.3 * u(rng);
    auto inside = [&](int corner) {  // corner 0..7 of the box, else a point in it
      Vec3 x;
      for (int m = 0; m < 3; ++m) {
        const double w = corner >= 0 ? double(corner >> m & 1) : s(rng);
        x[m] = w == 0 ? x0[m] : w == 1 ? x1[m] : x0[m] + w * (x1[m] - x0[m]);
      }
      return x;
    };
    const Vec3 nrm = cross(sub(p[1], p[0]), sub(p[2], p[0]));
    const double nn = dot(nrm, nrm);
    double e = 0;
    for (int c = 0; c < 8; ++c) {
      const Vec3 y = inside(c);
      const double h = dot(nrm, sub(y, p[0]));
      // At a point: the bound's own formula.
      CHECK(beyond_distance(p[0], p[1], p[2], y, y, 0.1) == (h * h > 0.1 * 0.1 * nn));
      e = std::max(e, std::fabs(h) / std::sqrt(nn));
    }
    e *= 1 + 1e-15 * double(n % 7 - 3);
    if (beyond_distance(p[0], p[1], p[2], x0, x1, e)) {
      ++refused;
      continue;
    }
    ++settled;
    for (int c = -8; c < 8; ++c) {
      const Vec3 x = inside(c < 0 ? -1 : c);
      REQUIRE_FALSE(beyond_distance(p[0], p[1], p[2], x, x, e));
    }
  }
  CHECK(settled > 5000);
  CHECK(refused > 5000);
}

// insert()'s floor without the nearest-vertex search: inner_distance2 is
// the squared radius of the largest ball about p inside the cell (so none
// of its vertices is nearer): points a hair inside that radius, in every
// direction, are inside the cell, one a hair beyond it, towards the
// nearest facet's plane, is not. Random cells, flat ones among them.
TEST_CASE("the ball of inner_distance2 lies in the cell", "[conforming]") {
  using namespace conforming_detail;
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> u(-1, 1), s(0, 1);
  auto inside = [](const std::array<Vec3, 4>& v, const Vec3& q) {  // all four facets see q on v's side
    for (int i = 0; i < 4; ++i) {
      const Vec3 &a = v[std::size_t((i + 1) & 3)], &b = v[std::size_t((i + 2) & 3)], &c = v[std::size_t((i + 3) & 3)];
      const Vec3 n = cross(sub(b, a), sub(c, a));
      if (dot(n, sub(q, a)) * dot(n, sub(v[std::size_t(i)], a)) <= 0) return false;
    }
    return true;
  };
  std::size_t beyond = 0;
  for (int n = 0; n < 3000; ++n) {
    std::array<Vec3, 4> v;
    for (auto& q : v)
      for (int m = 0; m < 3; ++m) q[m] = 50 + u(rng);
    if (n % 3 == 0) v[3][2] = 50 + 1e-3 * u(rng), v[0][2] = v[1][2] = v[2][2] = 50;  // nearly flat
    double w[4], sum = 0;
    for (double& x : w) sum += x = s(rng) + 1e-3;
    Vec3 p{0, 0, 0};
    for (int i = 0; i < 4; ++i)
      for (int m = 0; m < 3; ++m) p[m] += w[i] / sum * v[std::size_t(i)][m];
    const double d2 = inner_distance2(v, p), r = std::sqrt(d2);
    REQUIRE(d2 > 0);
    for (const Vec3& q : v) REQUIRE(dist2(q, p) >= d2);
    for (int k = 0; k < 20; ++k) {
      Vec3 dir{u(rng), u(rng), u(rng)};
      const double len = std::sqrt(dot(dir, dir));
      Vec3 q;
      for (int m = 0; m < 3; ++m) q[m] = p[m] + (1 - 1e-6) * r * dir[m] / len;
      REQUIRE(inside(v, q));
    }
    // Towards the nearest facet's plane, a hair beyond: outside.
    for (int i = 0; i < 4; ++i) {
      const Vec3 &a = v[std::size_t((i + 1) & 3)], &b = v[std::size_t((i + 2) & 3)], &c = v[std::size_t((i + 3) & 3)];
      const Vec3 nrm = cross(sub(b, a), sub(c, a));
      const double h = dot(nrm, sub(p, a)), nn = dot(nrm, nrm);
      if (h * h / nn > d2 * (1 + 1e-9)) continue;
      Vec3 q;
      for (int m = 0; m < 3; ++m) q[m] = p[m] - (1 + 1e-6) * r * (h > 0 ? 1 : -1) * nrm[m] / std::sqrt(nn);
      CHECK_FALSE(inside(v, q));
      ++beyond;
      break;
    }
  }
  CHECK(beyond == 3000);
}

// The vertex checks run in any order; their candidates (one a vertex) then
// go after the facets' in the order of their vertices' ids, as checks by id
// made them. And a link vertex's name: its address, the bounding box's
// corners (which share the id -1) one name.
TEST_CASE("vertex checks' candidates in vertex-id order, corners one link vertex", "[conforming]") {
  using namespace conforming_detail;
  std::vector<int> list{100, 101, 7, 3, 5, 9};  // two facets' candidates, then vertices 7, 3, 5, 9's
  std::vector<std::pair<int, std::size_t>> ids{{7, 0}, {3, 1}, {5, 2}, {9, 3}};
  std::vector<int> scratch;
  order_by_id(list, 2, ids, scratch);
  CHECK(list == std::vector<int>{100, 101, 3, 5, 7, 9});
  const std::array<std::intptr_t, 8> corners{80, 88, 96, 104, 112, 120, 128, 136};
  for (std::intptr_t c : corners) CHECK(link_name(c, corners) == 80);
  CHECK(link_name(84, corners) == 84);
  CHECK(link_name(1000, corners) == 1000);
  CHECK(link_name(1000, {}) == 1000);  // seg2tet --outside: no shared corners
}
