// The surface certificate (certify_surface, what meshinfo --image runs and
// the meshers run on their outputs) on images in a rotated, anisotropic
// grid with an origin: right meshes pass (marching tetrahedra, smooth
// surfaces, bdCA(X) itself, each wobbled well within the tolerance);
// every wrong mesh of issue 35 and more of our own fail, each at the first
// check it breaks; random images and edits with fixed seeds.
#include "meshinfo/meshinfo.hpp"
#include "surfaces.hpp"
#include "util/error.hpp"

#include <catch2/catch.hpp>
#include <cmath>
#include <limits>

using namespace imgmesh;
using namespace imgmesh::test;

namespace {

double sq(double x) { return x * x; }

const Geometry& grid24() {
  static const Geometry g = scan_grid({24, 24, 24});
  return g;
}
const Vec3 kC{11.6, 12.2, 11.3};  // the balls' centre (index space)

const BinaryImage& ball() {
  static const BinaryImage img = solid(grid24(), [](double i, double j, double k) {
    return sq(i - kC[0]) + sq(j - kC[1]) + sq(k - kC[2]) <= 49;
  });
  return img;
}
// A hollow ball: the shell between radius 4.2 and 8.2.
const BinaryImage& hollow() {
  static const BinaryImage img = solid(grid24(), [](double i, double j, double k) {
    const double r2 = sq(i - kC[0]) + sq(j - kC[1]) + sq(k - kC[2]);
    return r2 > sq(4.2) && r2 <= sq(8.2);
  });
  return img;
}
// Two balls of radius 5 at index x = a and b in a 32 x 16 x 16 grid.
BinaryImage two_balls(double a, double b) {
  return solid(scan_grid({32, 16, 16}), [=](double i, double j, double k) {
    const double r2 = sq(j - 7.6) + sq(k - 7.8);
    return sq(i - a) + r2 <= 25 || sq(i - b) + r2 <= 25;
  });
}

SurfaceCertificate certify(const Surface& s, const BinaryImage& img, double tolerance = 0) {
  const VoxelBoundary b = voxel_boundary(img);
  CertificateOptions o;
  o.place_tolerance = tolerance;
  return certify_surface(s.points, s.tris, img, b, mesh_topology(b), o);
}
// "ok" or the first check that fails.
std::string first(const SurfaceCertificate& c) { return c.ok() ? "ok" : SurfaceCertificate::name(c.first_failed()); }

#define CHECK_FIRST(surface, image, check)                 \
  do {                                                     \
    const SurfaceCertificate c_ = certify(surface, image); \
    INFO(c_.failure());                                    \
    CHECK(first(c_) == (check));                           \
  } while (0)

// A sphere (index space) around kC, in img's world.
Surface ball_sphere(const BinaryImage& img, double r) { return to_world(sphere(kC, r), img); }

// The world vector of `voxels` steps along index axis a.
Vec3 step(const Geometry& g, int a, double voxels) {
  const Vec3 o = g.world(0, 0, 0), p = g.world(a == 0 ? voxels : 0, a == 1 ? voxels : 0, a == 2 ? voxels : 0);
  return {p[0] - o[0], p[1] - o[1], p[2] - o[2]};
}
Surface moved(Surface s, const Vec3& d) {
  for (Vec3& p : s.points) p = {p[0] + d[0], p[1] + d[1], p[2] + d[2]};
  return s;
}

// A surface between two world points p and q (poles exactly there): a
// sphere of diameter |q - p| turned onto the segment.
Surface lens(const Vec3& p, const Vec3& q) {
  const Vec3 u0{q[0] - p[0], q[1] - p[1], q[2] - p[2]};
  const double l = std::sqrt(sq(u0[0]) + sq(u0[1]) + sq(u0[2]));
  const Vec3 u{u0[0] / l, u0[1] / l, u0[2] / l};
  Vec3 v = std::abs(u[0]) < 0.9 ? Vec3{1, 0, 0} : Vec3{0, 1, 0};
  const double d = v[0] * u[0] + v[1] * u[1] + v[2] * u[2];
  v = {v[0] - d * u[0], v[1] - d * u[1], v[2] - d * u[2]};
  const double vl = std::sqrt(sq(v[0]) + sq(v[1]) + sq(v[2]));
  v = {v[0] / vl, v[1] / vl, v[2] / vl};
  const Vec3 w{u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0]};
  Surface s = sphere({l / 2, 0, 0}, l / 2, 6, 8);
  for (Vec3& x : s.points) {
    const Vec3 y = x;
    for (int a = 0; a < 3; ++a) x[std::size_t(a)] = p[std::size_t(a)] + y[0] * u[std::size_t(a)] + y[1] * v[std::size_t(a)] + y[2] * w[std::size_t(a)];
  }
  s.points.front() = p;  // exactly, not up to rounding
  s.points.back() = q;
  return s;
}

// a + b with b's vertex from_b identified with a's vertex to_a (its own
// copy left in no triangle).
Surface glued(Surface a, const Surface& b, const std::vector<std::pair<int, int>>& same) {
  const int n = int(a.points.size());
  a.add(b);
  for (auto& t : a.tris)
    for (int& v : t)
      for (const auto& [from_b, to_a] : same)
        if (v == n + from_b) v = to_a;
  return a;
}

} // namespace

TEST_CASE("certificate: right meshes pass", "[certificate]") {
  SECTION("marching tetrahedra of a ball, a hollow ball, two balls") {
    CHECK_FIRST(marching_tetrahedra(ball()), ball(), "ok");
    const SurfaceCertificate h = certify(marching_tetrahedra(hollow()), hollow());
    INFO(h.failure());
    CHECK(h.ok());
    REQUIRE(h.depth.size() == 2);
    CHECK(h.volume[1] < 0);  // the inner surface points in
    CHECK(h.depth[1] == 1);
    const BinaryImage two = two_balls(7, 24);
    CHECK_FIRST(marching_tetrahedra(two), two, "ok");
  }
  SECTION("bdCA(X) itself, and wobbled by up to 0.9 of the tolerance") {
    CHECK_FIRST(voxel_faces(hollow()), hollow(), "ok");
    const double tol = default_place_tolerance(hollow());
    for (unsigned seed : {1u, 2u, 3u}) {
      Surface s = voxel_faces(hollow());
      wobble(s, 0.9 * tol, 8 * tol, seed);
      CHECK_FIRST(s, hollow(), "ok");
    }
  }
  SECTION("smooth spheres") {
    CHECK_FIRST(ball_sphere(ball(), 7), ball(), "ok");
    Surface h = ball_sphere(hollow(), 8.2);
    h.add(ball_sphere(hollow(), 4.4).flip());
    CHECK_FIRST(h, hollow(), "ok");
  }
}

TEST_CASE("certificate: the tolerance is where the verdict turns", "[certificate]") {
  const double tol = default_place_tolerance(ball());
  CHECK(tol == Approx(std::sqrt(0.7 * 0.7 * 2 + 1.3 * 1.3)));
  // bdCA(X) moved along index axis 2 (1.3 a voxel): 0.9 of the tolerance
  // passes, 1.1 does not (the vertices on the squares facing that way are
  // that far from every square).
  const Surface s = voxel_faces(ball());
  auto along = [&](double f) { return moved(s, step(ball(), 2, f * tol / 1.3)); };
  CHECK_FIRST(along(0.9), ball(), "ok");
  CHECK_FIRST(along(1.1), ball(), "placed");
  // A larger --place-tolerance accepts what the default refuses.
  CHECK(certify(along(1.1), ball(), 1.2 * tol).ok());
  CHECK(certify(along(1.1), ball(), 1.2 * tol).correspondence.tolerance == Approx(1.2 * tol));
}

TEST_CASE("certificate: the wrong meshes of issue 35 fail at their first wrong check", "[certificate][wrong]") {
  const BinaryImage& img = ball();
  const Surface right = ball_sphere(img, 7);
  SECTION("glued to a second sphere at two vertices: not a manifold") {
    // Two vertices of the fourth ring, three apart, are the lens's poles.
    const int p = 1 + 28 * 3, q = p + 3;
    const Surface s = glued(right, lens(right.points[std::size_t(p)], right.points[std::size_t(q)]),
                            {{0, p}, {int(lens({0, 0, 0}, {1, 0, 0}).points.size()) - 1, q}});
    CHECK_FIRST(s, img, "manifold");
  }
  SECTION("one triangle flipped: not oriented") {
    Surface s = right;
    std::swap(s.tris[40][1], s.tris[40][2]);
    CHECK_FIRST(s, img, "oriented");
  }
  SECTION("inside out: not oriented (outward)") {
    Surface s = right;
    const SurfaceCertificate c = certify(s.flip(), img);
    CHECK(first(c) == "oriented");
    CHECK(c.failure().find("points inward") != std::string::npos);
  }
  SECTION("folding through itself: intersections") {
    Surface s = sphere(kC, 7);
    for (Vec3& p : s.points)
      if (p[0] - kC[0] > 5.6) p[0] = kC[0] + 5.6 - 10 * (p[0] - kC[0] - 5.6);
    CHECK_FIRST(to_world(s, img), img, "intersections");
  }
  SECTION("a hollow ball whose inner surface is stretched through the outer one: intersections") {
    Surface inner = sphere(kC, 4.4);
    for (Vec3& p : inner.points)
      if (p[0] > kC[0]) p[0] = kC[0] + 3 * (p[0] - kC[0]);
    Surface s = ball_sphere(hollow(), 8.2);
    s.add(to_world(inner, hollow()).flip());
    CHECK_FIRST(s, hollow(), "intersections");
  }
  SECTION("shifted by 5 or 10 voxels: placed") {
    for (double v : {5.0, 10.0}) {
      CHECK_FIRST(moved(right, step(img, 0, v)), img, "placed");
      CHECK_FIRST(moved(marching_tetrahedra(img), step(img, 1, v)), img, "placed");
    }
  }
  SECTION("in voxel-index coordinates (spacing 0.7/0.7/1.3, an origin): placed") {
    BinaryImage index = img;
    index.origin = {0, 0, 0};
    index.spacing = {1, 1, 1};
    index.direction = {1, 0, 0, 0, 1, 0, 0, 0, 1};
    CHECK_FIRST(marching_tetrahedra(index), img, "placed");
  }
  SECTION("a sphere of radius 100 with one vertex on bdCA(X): placed") {
    const VoxelBoundary b = voxel_boundary(img);
    const Vec3 on = corner_position(img, b, b.lattice_ids.size() / 2);
    CHECK_FIRST(sphere({on[0] + 100, on[1], on[2]}, 100), img, "placed");  // the first vertex there
    CHECK_FIRST(sphere({on[0] - 100, on[1], on[2]}, 100), img, "placed");  // the last
  }
  SECTION("two balls touching at a point: intersections, or not a manifold when they share the vertex") {
    const BinaryImage two = two_balls(8, 20);  // a voxel of background between them
    const Surface a = to_world(sphere({8, 7.6, 7.8}, 6), two), b = to_world(sphere({20, 7.6, 7.8}, 6), two);
    REQUIRE(a.points.back() == b.points.front());  // a's last pole, b's first: the same point
    Surface touching = a;
    touching.add(b);
    CHECK_FIRST(touching, two, "intersections");
    CHECK_FIRST(glued(a, b, {{0, int(a.points.size()) - 1}}), two, "manifold");
  }
  SECTION("two mirror-image wrong dumbbells (the vote tied 465:465): both placed") {
    for (bool mirror : {false, true}) {
      const BinaryImage two = two_balls(6.5, 24.5);
      std::vector<std::array<double, 2>> profile;
      for (double x = 1.5; x <= 29.5 + 1e-9; x += 0.5) {
        double r = 1.5;
        for (double c : {6.5, 24.5}) r = std::max(r, std::sqrt(std::max(0.0, 25 - sq(x - c))));
        profile.push_back({x, x < 1.6 || x > 29.4 ? 0.0 : r});
      }
      Surface s = revolve(profile, {0, 7.6, 7.8}, 24);
      s.add(sphere({mirror ? 6.5 : 24.5, 7.6, 14.1}, 1));  // a small sphere just above one ball
      const SurfaceCertificate c = certify(to_world(s, two), two);
      INFO(c.failure());
      CHECK(first(c) == "placed");
      CHECK(c.correspondence.mesh[0].verdict == "unplaced");
    }
  }
}

TEST_CASE("certificate: the intersections checked later give the same certificate", "[certificate]") {
  // The mesher certifies without them while its triangulation stands
  // (check_surface_intersections afterwards): every field as in one call.
  const BinaryImage two = two_balls(8, 20);
  Surface touching = to_world(sphere({8, 7.6, 7.8}, 6), two);
  touching.add(to_world(sphere({20, 7.6, 7.8}, 6), two));
  Surface folded = sphere(kC, 7);
  for (Vec3& p : folded.points)
    if (p[0] - kC[0] > 5.6) p[0] = kC[0] + 5.6 - 10 * (p[0] - kC[0] - 5.6);
  Surface open = ball_sphere(ball(), 7);
  open.tris.pop_back();
  const std::vector<std::pair<Surface, const BinaryImage*>> cases{
      {ball_sphere(ball(), 7), &ball()}, {touching, &two}, {to_world(folded, ball()), &ball()}, {open, &ball()}};
  for (const auto& [s, img] : cases) {
    const SurfaceCertificate whole = certify(s, *img);
    const VoxelBoundary b = voxel_boundary(*img);
    CertificateOptions o;
    o.intersections = false;
    SurfaceCertificate later = certify_surface(s.points, s.tris, *img, b, mesh_topology(b), o);
    check_surface_intersections(later, s.points, s.tris);
    INFO(whole.failure());
    CHECK(later.state == whole.state);
    CHECK(later.why == whole.why);
    CHECK(later.intersections.pairs == whole.intersections.pairs);
    CHECK(later.intersections.first == whole.intersections.first);
    CHECK(later.failure() == whole.failure());
  }
}

TEST_CASE("certificate: a mesh as near to two components is a tie, not broken by index", "[certificate]") {
  // Two voxels four apart on an integer grid, a voxel's cube midway: with
  // a tolerance of 4 both are within reach of every vertex, and the
  // farthest vertex is 2 from each, exactly.
  Geometry g;
  g.dimension = 3;
  g.size = {9, 3, 3};
  BinaryImage img(g, 0);
  img(2, 1, 1) = img(6, 1, 1) = 1;
  BinaryImage mid(g, 0);
  mid(4, 1, 1) = 1;
  const SurfaceCertificate c = certify(voxel_faces(mid), img, 4);
  INFO(c.failure());
  CHECK(first(c) == "matched");
  REQUIRE(c.correspondence.mesh.size() == 1);
  CHECK(c.correspondence.mesh[0].verdict == "tie");
  CHECK(c.correspondence.mesh[0].tied == std::vector<int>{0, 1});
  CHECK(c.failure().find("as near to bdCA(X) components 0 and 1 (a tie, not broken)") != std::string::npos);
  // Moved a quarter voxel towards the second, it is that one's.
  const SurfaceCertificate d = certify(moved(voxel_faces(mid), {0.25, 0, 0}), img, 4);
  CHECK(d.correspondence.mesh[0].boundary == 1);
  CHECK(first(d) == "matched");  // the first voxel has no mesh component
}

TEST_CASE("certificate: more wrong meshes, each at its first wrong check", "[certificate][wrong]") {
  const BinaryImage& img = ball();
  const Surface right = ball_sphere(img, 7);
  SECTION("a triangle missing: closed") {
    Surface s = right;
    s.tris.erase(s.tris.begin() + 100);
    CHECK_FIRST(s, img, "closed");
  }
  SECTION("a triangle twice: manifold") {
    Surface s = right;
    s.tris.push_back(s.tris[100]);
    CHECK_FIRST(s, img, "manifold");
  }
  SECTION("a membrane across the inside (the equator's edges in three triangles): manifold") {
    Surface s = right;
    s.points.push_back(img.world(kC[0], kC[1], kC[2]));
    const int centre = int(s.points.size()) - 1, ring = 1 + 28 * 8;  // the ninth ring: the equator
    for (int j = 0; j < 28; ++j) s.tris.push_back({centre, ring + j, ring + (j + 1) % 28});
    CHECK_FIRST(s, img, "manifold");
  }
  SECTION("a hollow ball's inner surface pointing out: oriented") {
    Surface s = ball_sphere(hollow(), 8.2);
    s.add(ball_sphere(hollow(), 4.4));
    const SurfaceCertificate c = certify(s, hollow());
    CHECK(first(c) == "oriented");
    CHECK(c.failure().find("a cavity's surface points in") != std::string::npos);
  }
  SECTION("two copies of the mesh on each other: intersections") {
    Surface s = right;
    s.add(right);
    CHECK_FIRST(s, img, "intersections");
  }
  SECTION("a vertex moved onto its neighbour (degenerate triangles): intersections") {
    Surface s = right;
    s.points[50] = s.points[51];
    const SurfaceCertificate c = certify(s, img);
    CHECK(first(c) == "intersections");
    CHECK(c.intersections.degenerate > 0);
  }
  SECTION("scaled by 0.6 about the centre: placed") {
    CHECK_FIRST(ball_sphere(img, 7 * 0.6), img, "placed");
  }
  SECTION("a spike: one vertex pulled 4 voxels out: placed") {
    Surface s = sphere(kC, 7);
    s.points[200] = {kC[0] + (s.points[200][0] - kC[0]) * 11 / 7, kC[1] + (s.points[200][1] - kC[1]) * 11 / 7,
                     kC[2] + (s.points[200][2] - kC[2]) * 11 / 7};
    CHECK_FIRST(to_world(s, img), img, "placed");
  }
  SECTION("a box around the ball: placed") {
    Surface s = voxel_faces(solid(grid24(), [](double i, double j, double k) {
      return std::abs(i - kC[0]) <= 7 && std::abs(j - kC[1]) <= 7 && std::abs(k - kC[2]) <= 7;
    }));
    CHECK_FIRST(s, img, "placed");
  }
  SECTION("an elongated ball transposed (x and y swapped), and in RAS instead of LPS: placed") {
    const BinaryImage egg = solid(grid24(), [](double i, double j, double k) {
      return sq((i - kC[0]) / 9) + sq((j - kC[1]) / 5) + sq((k - kC[2]) / 6) <= 1;
    });
    Surface t = marching_tetrahedra(egg);
    const Surface right_egg = t;
    for (Vec3& p : t.points) {
      const Vec3 ci = egg.continuous_index(p);
      p = egg.world(ci[1] - kC[1] + kC[0], ci[0] - kC[0] + kC[1], ci[2]);
    }
    CHECK_FIRST(t.flip(), egg, "placed");
    Surface ras = right_egg;
    for (Vec3& p : ras.points) p = {-p[0], -p[1], p[2]};
    CHECK_FIRST(ras, egg, "placed");
  }
  SECTION("a bubble at the centre (a cavity the image has not): placed") {
    Surface s = right;
    s.add(ball_sphere(img, 1.5).flip());
    CHECK_FIRST(s, img, "placed");
  }
  SECTION("a bubble just under the surface: matched (bdCA(X) matched twice)") {
    Surface s = right;
    s.add(to_world(sphere({kC[0] + 6.2, kC[1], kC[2]}, 0.5), img).flip());
    const SurfaceCertificate c = certify(s, img);
    CHECK(first(c) == "matched");
    CHECK(c.correspondence.boundary[0].verdict == "matched twice");
  }
  SECTION("one of two balls missing, a hollow ball's inner surface missing: matched (unmatched)") {
    const BinaryImage two = two_balls(7, 24);
    CHECK_FIRST(to_world(sphere({7, 7.6, 7.8}, 5), two), two, "matched");
    CHECK_FIRST(ball_sphere(hollow(), 8.2), hollow(), "matched");
  }
  SECTION("the balls' sizes swapped: placed") {
    const BinaryImage two = solid(scan_grid({32, 16, 16}), [](double i, double j, double k) {
      const double r2 = sq(j - 7.6) + sq(k - 7.8);
      return sq(i - 8) + r2 <= 36 || sq(i - 23) + r2 <= sq(4);
    });
    Surface s = to_world(sphere({8, 7.6, 7.8}, 4), two);
    s.add(to_world(sphere({23, 7.6, 7.8}, 6), two));
    CHECK_FIRST(s, two, "placed");
  }
  SECTION("a ring meshed as a disk (its hole filled): topology") {
    // 2 voxels thick, a 2 x 2 voxel hole: the filled disk lies within the
    // tolerance of the ring both ways, but has euler 2, not 0.
    auto ring = [](bool filled) {
      return solid(scan_grid({20, 20, 8}), [=](double i, double j, double k) {
        const bool hole = std::abs(i - 9.5) < 1 && std::abs(j - 9.5) < 1;
        return k >= 3 && k <= 4 && std::abs(i - 9.5) < 7 && std::abs(j - 9.5) < 7 && (filled || !hole);
      });
    };
    const BinaryImage torus_img = ring(false);
    REQUIRE(mesh_topology(voxel_boundary(torus_img)).euler_list() == std::vector<long long>{0});
    const SurfaceCertificate c = certify(marching_tetrahedra(ring(true)), torus_img);
    INFO(c.failure());
    CHECK(first(c) == "topology");
    CHECK(c.failure().find("euler 2, its bdCA(X) component 0 has 0") != std::string::npos);
  }
}

TEST_CASE("certificate: random images and edits (fixed seeds)", "[certificate][random]") {
  for (unsigned seed = 1; seed <= 6; ++seed) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> u(0, 1);
    // A random grid: spacing 0.5..2, an origin, a rotation from a random unit quaternion.
    double q[4];
    double qn = 0;
    for (double& x : q) { x = u(rng) * 2 - 1; qn += x * x; }
    for (double& x : q) x /= std::sqrt(qn);
    const double w = q[0], x = q[1], y = q[2], z = q[3];
    Geometry g = scan_grid({22, 22, 22}, {0.5 + 1.5 * u(rng), 0.5 + 1.5 * u(rng), 0.5 + 1.5 * u(rng)},
                           {100 * u(rng) - 50, 100 * u(rng) - 50, 100 * u(rng) - 50});
    g.direction = {1 - 2 * (y * y + z * z), 2 * (x * y - z * w),     2 * (x * z + y * w),
                   2 * (x * y + z * w),     1 - 2 * (x * x + z * z), 2 * (y * z - x * w),
                   2 * (x * z - y * w),     2 * (y * z + x * w),     1 - 2 * (x * x + y * y)};
    // An ellipsoid, with an ellipsoidal cavity in every other seed.
    const Vec3 c{10.5 + u(rng), 10.5 + u(rng), 10.5 + u(rng)}, a{4 + 3 * u(rng), 4 + 3 * u(rng), 4 + 3 * u(rng)};
    const bool cavity = seed % 2 == 0;
    const BinaryImage img = solid(g, [&](double i, double j, double k) {
      const double r = sq((i - c[0]) / a[0]) + sq((j - c[1]) / a[1]) + sq((k - c[2]) / a[2]);
      return r <= 1 && (!cavity || r > 0.2);
    });
    INFO("seed " << seed);
    const double tol = default_place_tolerance(img);
    const double big = std::max({img.spacing[0], img.spacing[1], img.spacing[2]});
    Surface right = marching_tetrahedra(img);
    wobble(right, 0.3 * tol, 6 * big, seed);  // Lipschitz below 1: still embedded
    CHECK_FIRST(right, img, "ok");
    Surface flipped = right, holed = right, shifted = right, shrunk = right;
    std::uniform_int_distribution<std::size_t> tri(0, right.tris.size() - 1);
    const std::size_t f = tri(rng);
    std::swap(flipped.tris[f][1], flipped.tris[f][2]);
    holed.tris.erase(holed.tris.begin() + std::ptrdiff_t(tri(rng)));
    CHECK_FIRST(flipped, img, "oriented");
    CHECK_FIRST(holed, img, "closed");
    Vec3 d{u(rng) - 0.5, u(rng) - 0.5, u(rng) - 0.5};
    const double dn = std::sqrt(sq(d[0]) + sq(d[1]) + sq(d[2]));
    CHECK_FIRST(moved(shifted, {2 * tol * d[0] / dn, 2 * tol * d[1] / dn, 2 * tol * d[2] / dn}), img, "placed");
    const Vec3 o = img.world(c[0], c[1], c[2]);
    for (Vec3& p : shrunk.points)
      for (int k = 0; k < 3; ++k) p[std::size_t(k)] = o[std::size_t(k)] + 0.5 * (p[std::size_t(k)] - o[std::size_t(k)]);
    // Shrunk by half: with a cavity, the outer surface lands on the cavity's
    // (which is then matched twice), else it is too far from bdCA(X).
    CHECK_FIRST(shrunk, img, cavity ? "matched" : "placed");
  }
}

TEST_CASE("meshinfo --image: voxel centres on the wrong side of the mesh (issue 38), reported", "[certificate][sides]") {
  auto poly = [](const Surface& s) {
    PolyMesh m;
    m.points = s.points;
    for (const auto& t : s.tris) m.faces.push_back({t[0], t[1], t[2]});
    m.format = "off";
    return m;
  };
  auto sides = [&](const Surface& s, const BinaryImage& img) {
    const MeshInfo info = mesh_info(poly(s), "m.off", &img, "x.nrrd");
    REQUIRE(info.report.at("image").contains("voxel_sides"));
    return info.report.at("image").at("voxel_sides");
  };
  // Marching tetrahedra of a well-composed image: every centre on its side,
  // by construction (the centres are the tetrahedra's corners).
  for (const BinaryImage* img : {&ball(), &hollow()}) {
    const Json s = sides(marching_tetrahedra(*img), *img);
    CHECK(s.at("voxel_centres_checked").integer() > 300);
    CHECK(s.at("wrong_side").integer() == 0);
  }
  // bdCA(X) itself (marching cubes' staircase): every centre half a voxel
  // inside its side.
  for (const BinaryImage* img : {&ball(), &hollow()}) {
    const Json s = sides(voxel_faces(*img), *img);
    CHECK(s.at("voxel_centres_checked").integer() > 300);
    CHECK(s.at("wrong_side").integer() == 0);
    CHECK(s.at("on_surface").integer() == 0);
  }
  // Shifted by two voxels: the centres on the leading side are outside,
  // those on the trailing side inside: many, of both kinds.
  for (const Surface& s : {marching_tetrahedra(hollow()), voxel_faces(hollow())}) {
    const Json shifted = sides(moved(s, step(hollow(), 0, 2)), hollow());
    CHECK(shifted.at("foreground_outside").integer() > 50);
    CHECK(shifted.at("background_inside").integer() > 50);
  }
  // A small sphere on the ball's surface in place of the ball: each vertex
  // near bdCA(X), one to one, the same Euler characteristic, so certified
  // (that bdCA(X) lies near the mesh is not: the meshers do not guarantee
  // it); the count shows it: every foreground centre but a few is outside.
  const Surface bubble = to_world(sphere({kC[0] + 7, kC[1], kC[2]}, 0.7), ball());
  CHECK(certify(bubble, ball()).ok());
  const Json b = sides(bubble, ball());
  CHECK(b.at("foreground_outside").integer() > b.at("voxel_centres_checked").integer() / 3);
  // Not counted on a surface with no sides.
  Surface open = marching_tetrahedra(ball());
  open.tris.pop_back();
  CHECK_FALSE(mesh_info(poly(open), "m.off", &ball(), "x.nrrd").report.at("image").contains("voxel_sides"));
}

TEST_CASE("certificate: a vertex that is not a number is an error, not a verdict", "[certificate]") {
  Surface s = ball_sphere(ball(), 7);
  s.points[3][1] = std::nan("");
  CHECK_THROWS_AS(certify(s, ball()), Error);
  s.points[3][1] = std::numeric_limits<double>::infinity();
  CHECK_THROWS_AS(certify(s, ball()), Error);
}
