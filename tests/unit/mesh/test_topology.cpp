// mesh_topology (what meshinfo reports) against an independent count made
// here (sets of edges, breadth-first components) and against known
// surfaces; bdCA(X) of small images against known values, from binary
// images and from the mesher's samples; triangle quality against closed
// forms.
#include "mesh/topology.hpp"
#include "mesh/triangle_quality.hpp"
#include "shapes.hpp"
#include "util/error.hpp"

#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <queue>
#include <random>
#include <set>

using namespace imgmesh;
using namespace imgmesh::test;

namespace {

// Independent count: components by breadth-first search over face-sharing
// vertices, V - E + F per component from sets.
std::vector<long long> independent_euler(const Faces& s) {
  std::vector<std::vector<int>> vf(s.nv);
  for (std::size_t i = 0; i < s.f.size(); ++i)
    for (int v : s.f[i]) vf[v].push_back(int(i));
  std::vector<int> comp(s.f.size(), -1);
  int nc = 0;
  for (std::size_t i = 0; i < s.f.size(); ++i) {
    if (comp[i] >= 0) continue;
    std::queue<int> q;
    q.push(int(i));
    comp[i] = nc;
    while (!q.empty()) {
      const int f = q.front();
      q.pop();
      for (int v : s.f[f])
        for (int g : vf[v])
          if (comp[g] < 0) { comp[g] = nc; q.push(g); }
    }
    ++nc;
  }
  std::vector<long long> out;
  for (int c = 0; c < nc; ++c) {
    std::set<int> V;
    std::set<std::pair<int, int>> E;
    long long F = 0;
    for (std::size_t i = 0; i < s.f.size(); ++i) {
      if (comp[i] != c) continue;
      ++F;
      for (std::size_t k = 0; k < s.f[i].size(); ++k) {
        const int a = s.f[i][k], b = s.f[i][(k + 1) % s.f[i].size()];
        V.insert(a);
        E.insert(std::minmax(a, b));
      }
    }
    out.push_back((long long)V.size() - (long long)E.size() + F);
  }
  std::sort(out.begin(), out.end());
  return out;
}

std::vector<long long> sorted(std::vector<long long> v) {
  std::sort(v.begin(), v.end());
  return v;
}

// Samples of the mesher: positive outside X, negative in X.
FloatImage samples3(int n) {
  Geometry g;
  g.size = {std::size_t(n), std::size_t(n), std::size_t(n)};
  return FloatImage(g, 1.0f);
}
void block(FloatImage& img, int x0, int x1, int y0, int y1, int z0, int z1, float v = -1) {
  for (int z = z0; z < z1; ++z)
    for (int y = y0; y < y1; ++y)
      for (int x = x0; x < x1; ++x) img(x, y, z) = v;
}
MeshTopology samples_topology(const FloatImage& g) { return mesh_topology(voxel_boundary(SampleGrid(g))); }

} // namespace

TEST_CASE("closed and open surfaces: Euler characteristic, genus, loops", "[topology]") {
  SECTION("sphere") {
    const Faces s = cube_sphere(3);
    const auto t = mesh_topology(s.nv, s.f);
    REQUIRE(t.components.size() == 1);
    CHECK(t.components[0].euler == 2);
    CHECK(t.components[0].genus == 0);
    CHECK(t.closed);
    CHECK(t.manifold);
    CHECK(t.oriented);
    CHECK(t.boundary_loops == 0);
  }
  SECTION("torus") {
    const Faces s = grid(7, 5, true, true);
    const auto t = mesh_topology(s.nv, s.f);
    REQUIRE(t.components.size() == 1);
    CHECK(t.components[0].euler == 0);
    CHECK(t.components[0].genus == 1);
    CHECK(t.closed);
    CHECK(t.oriented);
  }
  SECTION("disk") {
    const Faces s = grid(4, 6, false, false);
    const auto t = mesh_topology(s.nv, s.f);
    REQUIRE(t.components.size() == 1);
    CHECK(t.components[0].euler == 1);
    CHECK(t.components[0].boundary_loops == 1);
    CHECK(t.components[0].genus == 0);
    CHECK_FALSE(t.closed);
    CHECK(t.manifold);
  }
  SECTION("cylinder (annulus)") {
    const Faces s = grid(6, 3, true, false);
    const auto t = mesh_topology(s.nv, s.f);
    REQUIRE(t.components.size() == 1);
    CHECK(t.components[0].euler == 0);
    CHECK(t.components[0].boundary_loops == 2);
    CHECK(t.components[0].genus == 0);
  }
  SECTION("two spheres, a torus and a disk") {
    Faces s;
    s.add(cube_sphere(2));
    s.add(cube_sphere(3));
    s.add(grid(5, 5, true, true));
    s.add(grid(3, 2, false, false));
    s.nv += 4;  // isolated vertices are not components
    const auto t = mesh_topology(s.nv, s.f);
    REQUIRE(t.components.size() == 4);
    CHECK(sorted(t.euler_list()) == std::vector<long long>{0, 1, 2, 2});
    CHECK(t.isolated_vertices == 4);
    CHECK_FALSE(t.closed);
    CHECK(t.boundary_loops == 1);
    CHECK(sorted(t.euler_list()) == independent_euler(s));
  }
  SECTION("each component its own closed, oriented and edge count") {
    Faces flipped = cube_sphere(2);
    std::reverse(flipped.f[3].begin(), flipped.f[3].end());
    Faces s;
    s.add(grid(3, 2, false, false));  // disk: open, oriented
    s.add(flipped);                   // closed, one face the wrong way
    s.add(grid(5, 5, true, true));    // torus: closed, oriented
    const auto t = mesh_topology(s.nv, s.f);
    REQUIRE(t.components.size() == 3);
    int seen = 0;
    for (const auto& c : t.components) {
      CHECK(c.euler == (long long)c.vertices - (long long)c.edges + (long long)c.faces);
      if (c.euler == 1) {
        ++seen;
        CHECK_FALSE(c.closed);
        CHECK(c.oriented);
        CHECK(c.edges == 9 + 8 + 6);  // 3 x 2 quads: rows, columns, diagonals
      } else if (c.euler == 2) {
        ++seen;
        CHECK(c.closed);
        CHECK_FALSE(c.oriented);
        CHECK(c.orientable);
      } else {
        ++seen;
        CHECK(c.euler == 0);
        CHECK(c.closed);
        CHECK(c.oriented);
      }
    }
    CHECK(seen == 3);
  }
  SECTION("Moebius strip: manifold, not orientable") {
    // A strip of n quads whose ends are glued with a half twist.
    const int n = 8;
    Faces s;
    s.nv = 2 * n;
    for (int i = 0; i < n; ++i) {
      const int a = i, b = n + i;
      const int c = i + 1 < n ? n + i + 1 : 0;  // twisted: top meets bottom
      const int d = i + 1 < n ? i + 1 : n;
      s.f.push_back({a, d, c, b});
    }
    const auto t = mesh_topology(s.nv, s.f);
    REQUIRE(t.components.size() == 1);
    CHECK(t.components[0].euler == 0);
    CHECK(t.components[0].manifold);
    CHECK_FALSE(t.components[0].orientable);
    CHECK_FALSE(t.components[0].oriented);
    CHECK(t.components[0].boundary_loops == 1);
    CHECK(t.components[0].genus == 1);  // one cross-cap
  }
}

TEST_CASE("orientation and manifold defects are found", "[topology]") {
  Faces s = cube_sphere(2);
  std::reverse(s.f[3].begin(), s.f[3].end());
  auto t = mesh_topology(s.nv, s.f);
  CHECK_FALSE(t.oriented);
  CHECK(t.components[0].orientable);
  CHECK(t.inconsistent_edges == 4);
  // Three triangles on one edge.
  Faces fin;
  fin.nv = 5;
  fin.f = {{0, 1, 2}, {1, 0, 3}, {0, 1, 4}};
  t = mesh_topology(fin.nv, fin.f);
  CHECK(t.nonmanifold_edges == 1);
  CHECK_FALSE(t.manifold);
  // Two closed spheres sharing one vertex (a pinch).
  Faces pinch = cube_sphere(1);
  Faces other = cube_sphere(1);
  const std::size_t base = pinch.nv, first_faces = pinch.f.size();
  pinch.add(other);
  for (std::size_t i = first_faces; i < pinch.f.size(); ++i)
    for (int& v : pinch.f[i])
      if (v == int(base)) v = 0;  // glue the second sphere's vertex 0 onto the first's
  t = mesh_topology(pinch.nv, pinch.f);
  CHECK(t.components.size() == 1);
  CHECK(t.nonmanifold_vertices == 1);
  CHECK_FALSE(t.manifold);
  // Bad ids.
  CHECK_THROWS_AS(mesh_topology(3, std::vector<std::vector<int>>{{0, 1, 5}}), Error);
  CHECK_THROWS_AS(mesh_topology(3, std::vector<std::vector<int>>{{0, 1, 1}}), Error);
}

TEST_CASE("random surfaces agree with the independent count", "[topology]") {
  std::mt19937 rng(42);
  for (int trial = 0; trial < 30; ++trial) {
    Faces s;
    std::uniform_int_distribution<int> pick(0, 3);
    const int parts = 1 + trial % 4;
    for (int p = 0; p < parts; ++p) {
      switch (pick(rng)) {
        case 0: s.add(cube_sphere(1 + trial % 3)); break;
        case 1: s.add(grid(3 + trial % 4, 3, true, true)); break;
        case 2: s.add(grid(2 + trial % 3, 4, true, false)); break;
        default: s.add(grid(3, 2 + trial % 3, false, false)); break;
      }
    }
    // Drop random faces: open surfaces with holes and several pieces.
    std::bernoulli_distribution drop(0.15);
    Faces cut;
    cut.nv = s.nv;
    for (const auto& f : s.f)
      if (!drop(rng)) cut.f.push_back(f);
    if (cut.f.empty()) continue;
    const auto t = mesh_topology(cut.nv, cut.f);
    CHECK(sorted(t.euler_list()) == independent_euler(cut));
  }
}

TEST_CASE("bdCA(X) of small images", "[topology][bdca]") {
  SECTION("ball: one component, euler 2") {
    BinaryImage img = image3(12);
    for (int z = 0; z < 12; ++z)
      for (int y = 0; y < 12; ++y)
        for (int x = 0; x < 12; ++x)
          img(x, y, z) = (x - 5.5) * (x - 5.5) + (y - 5.5) * (y - 5.5) + (z - 5.5) * (z - 5.5) < 16;
    const auto t = voxel_boundary_topology(img);
    REQUIRE(t.components.size() == 1);
    CHECK(t.components[0].euler == 2);
    CHECK(t.manifold);
    CHECK(t.oriented);
    CHECK(t.closed);
  }
  SECTION("a box touching the image border") {
    BinaryImage img = image3(4);
    for (auto& v : img.data) v = 1;
    const auto t = voxel_boundary_topology(img);
    REQUIRE(t.components.size() == 1);
    CHECK(t.components[0].euler == 2);
    CHECK(t.components[0].faces == 6 * 16);
  }
  SECTION("solid torus: euler 0") {
    BinaryImage img = image3(10);
    for (int z = 3; z <= 5; ++z)
      for (int y = 1; y <= 8; ++y)
        for (int x = 1; x <= 8; ++x)
          img(x, y, z) = !(x >= 4 && x <= 5 && y >= 4 && y <= 5);
    const auto t = voxel_boundary_topology(img);
    REQUIRE(t.components.size() == 1);
    CHECK(t.components[0].euler == 0);
    CHECK(t.components[0].genus == 1);
  }
  SECTION("ball with a cavity: two components") {
    BinaryImage img = image3(9);
    for (int z = 1; z <= 7; ++z)
      for (int y = 1; y <= 7; ++y)
        for (int x = 1; x <= 7; ++x) img(x, y, z) = !(x >= 3 && x <= 5 && y >= 3 && y <= 5 && z >= 3 && z <= 5);
    const auto t = voxel_boundary_topology(img);
    REQUIRE(t.components.size() == 2);
    CHECK(t.euler_list() == std::vector<long long>{2, 2});
    CHECK(t.oriented);
  }
  SECTION("not well-composed: two voxels sharing an edge") {
    BinaryImage img = image3(4);
    img(1, 1, 1) = 1;
    img(2, 2, 1) = 1;
    const auto t = voxel_boundary_topology(img);
    CHECK_FALSE(t.manifold);
  }
  SECTION("not well-composed: two voxels sharing a vertex") {
    BinaryImage img = image3(4);
    img(1, 1, 1) = 1;
    img(2, 2, 2) = 1;
    const auto t = voxel_boundary_topology(img);
    CHECK_FALSE(t.manifold);
  }
  SECTION("2D: a ring gives two loops") {
    Geometry g;
    g.dimension = 2;
    g.size = {8, 8, 1};
    BinaryImage img(g, 0);
    for (int y = 1; y <= 6; ++y)
      for (int x = 1; x <= 6; ++x) img(x, y) = !(x >= 3 && x <= 4 && y >= 3 && y <= 4);
    const auto t = voxel_boundary_topology(img);
    CHECK(t.components.size() == 2);
    CHECK(t.euler_list() == std::vector<long long>{0, 0});
    CHECK(t.manifold);
  }
  SECTION("empty image") {
    CHECK_THROWS_AS(voxel_boundary_topology(image3(3)), Error);
  }
}

TEST_CASE("the voxel-boundary mesh of a ball matches bdCA(X)", "[topology][bdca]") {
  // Mesh the cube sphere and compare with a voxel box: same topology.
  const Faces s = cube_sphere(2);
  BinaryImage img = image3(5);
  img(2, 2, 2) = 1;
  const auto mt = mesh_topology(s.nv, s.f);
  const auto it = voxel_boundary_topology(img);
  CHECK(same_topology(mt, it));
  Faces two = cube_sphere(2);
  two.add(cube_sphere(1));
  CHECK_FALSE(same_topology(mesh_topology(two.nv, two.f), it));
}

TEST_CASE("bdCA(X) of the mesher's samples X = {g < 0}: blocks, rings, shells", "[topology][bdca]") {
  auto img = samples3(12);
  block(img, 2, 5, 2, 5, 2, 5);
  CHECK(sorted(samples_topology(img).euler_list()) == std::vector<long long>{2});
  block(img, 7, 10, 7, 10, 7, 10);
  CHECK(sorted(samples_topology(img).euler_list()) == std::vector<long long>{2, 2});

  auto ring = samples3(12);
  block(ring, 2, 9, 2, 9, 4, 6);
  block(ring, 4, 7, 4, 7, 4, 6, 1);  // a hole through it: genus 1
  auto t = samples_topology(ring);
  CHECK(t.euler_list() == std::vector<long long>{0});
  CHECK(t.manifold);

  auto shell = samples3(12);
  block(shell, 1, 11, 1, 11, 1, 11);
  block(shell, 4, 8, 4, 8, 4, 8, 1);  // cavity: two boundary components
  CHECK(samples_topology(shell).euler_list() == std::vector<long long>{2, 2});

  auto pinch = samples3(8);  // two voxels sharing only an edge: not well-composed
  block(pinch, 2, 3, 2, 3, 2, 3);
  block(pinch, 3, 4, 3, 4, 2, 3);
  CHECK_FALSE(samples_topology(pinch).manifold);
  CHECK(samples_topology(pinch).nonmanifold_edges == 1);

  // Zero is not inside (X = {g < 0}), and no sample below zero is no quad.
  auto zero = samples3(5);
  block(zero, 1, 4, 1, 4, 1, 4, 0);
  CHECK(voxel_boundary(SampleGrid(zero)).offsets.size() == 1);
  CHECK(samples_topology(zero).components.empty());
}

TEST_CASE("bdCA(X) of a solid torus has Euler characteristic 0", "[topology][bdca]") {
  // Voxels within 2.5 of a circle of radius 6: a solid torus, genus 1 (and
  // well-composed at this size).
  auto g = samples3(20);
  for (int z = 0; z < 20; ++z)
    for (int y = 0; y < 20; ++y)
      for (int x = 0; x < 20; ++x) {
        const double dx = x - 9.5, dy = y - 9.5, dz = z - 9.5;
        const double r = std::sqrt(dx * dx + dy * dy) - 6;
        g(x, y, z) = float(r * r + dz * dz - 2.5 * 2.5);
      }
  const auto t = samples_topology(g);
  REQUIRE(t.components.size() == 1);
  CHECK(t.manifold);
  CHECK(t.components[0].euler == 0);
  CHECK(t.components[0].genus == 1);
}

TEST_CASE("two balls: two components of Euler characteristic 2, each found by place", "[topology][bdca]") {
  // A larger ball around (5, 5, 5) and a smaller one around (14, 13, 12).
  auto g = samples3(20);
  for (int z = 0; z < 20; ++z)
    for (int y = 0; y < 20; ++y)
      for (int x = 0; x < 20; ++x) {
        const double a = (x - 5) * (x - 5) + (y - 5) * (y - 5) + (z - 5) * (z - 5);
        const double b = (x - 14) * (x - 14) + (y - 13) * (y - 13) + (z - 12) * (z - 12);
        g(x, y, z) = float(std::min(a - 16, b - 6.25));
      }
  const VoxelBoundary b = voxel_boundary(SampleGrid(g));
  const auto t = mesh_topology(b);
  REQUIRE(t.components.size() == 2);
  CHECK(t.euler_list() == std::vector<long long>{2, 2});
  CHECK(t.manifold);
  CHECK(t.components[0].faces > t.components[1].faces);
  // Each component's corner lies on its own ball's boundary: among the eight
  // voxels meeting there, some are in X and some are not, and all are
  // within reach of that ball's centre only.
  const std::array<std::array<double, 3>, 2> centre{{{5, 5, 5}, {14, 13, 12}}};
  for (std::size_t c = 0; c < 2; ++c) {
    const auto k = b.corner(t.components[c].first_vertex);
    int in = 0;
    for (int d = 0; d < 8; ++d) {
      const std::size_t x = k[0] - 1 + (d & 1), y = k[1] - 1 + ((d >> 1) & 1), z = k[2] - 1 + ((d >> 2) & 1);
      in += g(x, y, z) < 0;
    }
    CHECK(in > 0);
    CHECK(in < 8);
    // The corner is the point (k - 1/2) in voxel indices.
    auto dist = [&](std::size_t i) {
      double s = 0;
      for (int a = 0; a < 3; ++a) s += (double(k[a]) - 0.5 - centre[i][a]) * (double(k[a]) - 0.5 - centre[i][a]);
      return std::sqrt(s);
    };
    CHECK(dist(c) < dist(1 - c));
    CHECK(dist(c) < (c == 0 ? 4 : 2.5) + 1);
  }
}

TEST_CASE("bdCA(X) from samples agrees with bdCA(X) from the binary image", "[topology][bdca]") {
  std::mt19937 rng(7);
  for (int trial = 0; trial < 200; ++trial) {
    const int n = 3 + trial % 5;
    Geometry geo;
    geo.size = {std::size_t(n), std::size_t(n + trial % 2), std::size_t(n + 1)};
    FloatImage g(geo, 1.0f);
    BinaryImage x(geo, 0);
    std::uniform_real_distribution<float> u(-1, 2);
    for (std::size_t i = 0; i < g.data.size(); ++i) {
      g.data[i] = u(rng);
      x.data[i] = g.data[i] < 0;
    }
    if (std::find(x.data.begin(), x.data.end(), 1) == x.data.end()) continue;
    const auto from_samples = mesh_topology(voxel_boundary(SampleGrid(g)));
    const auto from_image = voxel_boundary_topology(x);
    CHECK(from_samples.to_json().dump(-1) == from_image.to_json().dump(-1));
    CHECK(voxel_boundary(SampleGrid(g)).corners == voxel_boundary(x).corners);
  }
}

TEST_CASE("triangle meshes: tetrahedron, a flipped face, a duplicated face, a hole", "[topology]") {
  const std::vector<std::array<int, 3>> tet = {{0, 2, 1}, {0, 1, 3}, {0, 3, 2}, {1, 2, 3}};
  auto t = mesh_topology(4, tet);
  CHECK(t.euler_list() == std::vector<long long>{2});
  CHECK(t.closed);
  CHECK(t.manifold);
  CHECK(t.oriented);

  auto flipped = tet;
  flipped[3] = {1, 3, 2};
  t = mesh_topology(4, flipped);
  CHECK_FALSE(t.oriented);
  CHECK(t.inconsistent_edges == 3);
  CHECK(t.manifold);

  auto twice = tet;
  twice.push_back(tet[1]);
  t = mesh_topology(4, twice);
  CHECK_FALSE(t.manifold);
  CHECK(t.nonmanifold_edges == 3);

  auto open = tet;
  open.pop_back();
  t = mesh_topology(4, open);
  CHECK_FALSE(t.closed);
  CHECK(t.boundary_edges == 3);
  CHECK(t.euler_list() == std::vector<long long>{1});
}

TEST_CASE("triangle quality: closed forms, degenerate triangles", "[quality]") {
  SurfaceMesh m{{{0, 0, 0}, {1, 0, 0}, {0.5, std::sqrt(3.0) / 2, 0}, {0, 1, 1}}, {{0, 1, 2}}, {}};
  auto q = triangle_quality_report(m);
  CHECK(q.triangles == 1);
  CHECK(q.max_radius_edge_ratio == Approx(1 / std::sqrt(3.0)));
  CHECK(q.min_angle == Approx(60));
  CHECK(q.smallest_angle() == Approx(60));
  CHECK(q.total_area == Approx(std::sqrt(3.0) / 4));
  CHECK(q.min_angle_histogram[5] == 1);
  // A right triangle in a tilted plane, legs 1 and sqrt(2): R is half the
  // hypotenuse sqrt(3), the smallest angle atan(1 / sqrt(2)).
  m.triangles = {{0, 1, 3}};
  q = triangle_quality_report(m);
  CHECK(q.min_angle == Approx(std::atan(1 / std::sqrt(2.0)) * 180 / M_PI));
  CHECK(q.max_angle == Approx(90));
  CHECK(q.max_radius_edge_ratio == Approx(std::sqrt(3.0) / 2));
  // A degenerate triangle does not enter the figures but fails every bound.
  m.points.push_back({2, 0, 0});
  m.triangles = {{0, 1, 2}, {0, 1, 4}};
  q = triangle_quality_report(m);
  CHECK(q.triangles == 1);
  CHECK(q.degenerate == 1);
  CHECK(q.min_angle == Approx(60));
  CHECK(q.smallest_angle() == 0);
  CHECK(std::isinf(q.largest_radius_edge_ratio()));
  CHECK(q.to_json().at("degenerate").integer() == 1);
  // No triangle: only the counts.
  m.triangles.clear();
  q = triangle_quality_report(m);
  CHECK(q.to_json().keys().size() == 2);
  CHECK(q.largest_radius_edge_ratio() == 0);
}

// The quads of voxel_boundary against the voxel faces counted here: every
// face between a voxel of X and one not in X (or beyond the grid) once, a
// unit square of the lattice with its lowest corner first, counter-clockwise
// seen from outside; the vertices every corner used, ascending, none else;
// faces' bits at each quad's first corner. Random sets in a box of a larger
// grid of unequal sides, some touching the grid's sides; from the binary
// image and from samples (whose box is X's).
TEST_CASE("voxel_boundary: the faces of X, each once, oriented, on ascending corners", "[topology][bdca]") {
  std::mt19937 rng(3939);
  for (int trial = 0; trial < 60; ++trial) {
    INFO("trial " << trial);
    Geometry geo;
    geo.size = {std::size_t(4 + trial % 5), std::size_t(3 + trial % 3), std::size_t(5 + trial % 4)};
    BinaryImage x(geo, 0);
    FloatImage g(geo, 1.0f);
    std::array<std::size_t, 3> lo, hi;
    for (std::size_t a = 0; a < 3; ++a) {
      lo[a] = trial % 3 == 0 ? 0 : std::size_t(rng() % 2);
      hi[a] = geo.size[a] - 1 - (trial % 4 == 0 ? 0 : std::size_t(rng() % 2));
    }
    std::bernoulli_distribution in(0.4);
    for (std::size_t z = lo[2]; z <= hi[2]; ++z)
      for (std::size_t y = lo[1]; y <= hi[1]; ++y)
        for (std::size_t i = lo[0]; i <= hi[0]; ++i)
          if (in(rng)) x(i, y, z) = 1, g(i, y, z) = -1.0f;
    const std::uint64_t W = geo.size[0] + 1, H = geo.size[1] + 1;
    auto id = [&](long i, long j, long k) { return std::uint64_t((k * long(H) + j) * long(W) + i); };
    auto inside = [&](long i, long j, long k) { return x.inside(i, j, k) && x(std::size_t(i), std::size_t(j), std::size_t(k)); };
    // Each face as its corner ids (lowest first, then counter-clockwise
    // about the outward normal), and its first corner's bit.
    std::multiset<std::vector<std::uint64_t>> expected;
    std::set<std::uint64_t> corners;
    for (long k = 0; k < long(geo.size[2]); ++k)
      for (long j = 0; j < long(geo.size[1]); ++j)
        for (long i = 0; i < long(geo.size[0]); ++i) {
          if (!inside(i, j, k)) continue;
          for (int a = 0; a < 3; ++a)
            for (int s : {-1, 1}) {
              std::array<long, 3> n{i, j, k};
              n[std::size_t(a)] += s;
              if (inside(n[0], n[1], n[2])) continue;
              // The face's corners: the plane at the side s, the other two axes u, v with e_u x e_v = e_a.
              const int u = (a + 1) % 3, v = (a + 2) % 3;
              std::array<long, 3> c{i, j, k};
              c[std::size_t(a)] += s > 0 ? 1 : 0;
              std::vector<std::array<long, 3>> q(4, c);
              q[1][std::size_t(u)] += 1;
              q[2][std::size_t(u)] += 1, q[2][std::size_t(v)] += 1;
              q[3][std::size_t(v)] += 1;
              if (s < 0) std::swap(q[1], q[3]);  // outward -e_a: clockwise about e_a
              std::vector<std::uint64_t> ids;
              for (const auto& p : q) ids.push_back(id(p[0], p[1], p[2])), corners.insert(ids.back());
              ids.push_back(std::uint64_t((VoxelBoundary::kNormalAxis | (s > 0 ? VoxelBoundary::kPlus : 0)) << a));
              expected.insert(ids);
            }
        }
    for (const VoxelBoundary& vb : {voxel_boundary(x), voxel_boundary(SampleGrid(g))}) {
      CHECK(vb.lattice_ids == std::vector<std::uint64_t>(corners.begin(), corners.end()));
      REQUIRE(vb.corners.size() == 4 * expected.size());
      REQUIRE(vb.offsets.size() == expected.size() + 1);
      std::multiset<std::vector<std::uint64_t>> found;
      std::vector<std::uint8_t> bits(vb.lattice_ids.size(), 0);
      for (std::size_t f = 0; f + 1 < vb.offsets.size(); ++f) {
        REQUIRE(vb.offsets[f + 1] - vb.offsets[f] == 4);
        std::vector<std::uint64_t> ids;
        for (std::size_t i = vb.offsets[f]; i < vb.offsets[f + 1]; ++i) ids.push_back(vb.lattice_ids[std::size_t(vb.corners[i])]);
        CHECK(ids[0] == *std::min_element(ids.begin(), ids.end()));
        const auto e = std::find_if(expected.begin(), expected.end(), [&](const std::vector<std::uint64_t>& w) {
          return std::equal(ids.begin(), ids.end(), w.begin());
        });
        REQUIRE(e != expected.end());
        bits[std::size_t(vb.corners[vb.offsets[f]])] |= std::uint8_t((*e)[4]);
        ids.push_back((*e)[4]);
        found.insert(ids);
      }
      CHECK(found == expected);
      CHECK(vb.faces == bits);
    }
  }
}

TEST_CASE("euler_summary: ascending, each value once with how often", "[topology]") {
  CHECK(euler_summary({2, -2, 2, 0, 2}) == "-2, 0, 2 (x3)");
  CHECK(euler_summary({-1502, 2, 2}) == "-1502, 2 (x2)");
  CHECK(euler_summary({2}) == "2");
  CHECK(euler_summary({}).empty());
}
