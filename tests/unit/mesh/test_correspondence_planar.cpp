// The 2D certificate by correspondence (pixel_regions, mesh_regions,
// match_regions): a square "disk" and a square "annulus" with the same outer
// square, so that mirroring x puts each where the other is, in a grid with
// an origin and anisotropic spacing. A planar mesh of the pixel squares (with
// background faces, region labels per face, vertices jittered) must pass;
// the mirrored mesh, a mesh missing the hole, one with the disk doubled or
// the annulus dropped, and one with labels swapped must be refused, naming
// the region and why.
#include "mesh/meshinfo.hpp"
#include "mesh/topology.hpp"

#include <catch2/catch.hpp>

#include <random>

using namespace imgmesh;

namespace {

constexpr int kNx = 36, kNy = 16;

// Disk: x 3..12; annulus: x 23..32 with the hole x 26..29, y 6..9; both y 3..12.
LabelImage disk_and_annulus(bool fill_hole, std::int32_t annulus_label = 1) {
  Geometry g;
  g.dimension = 2;
  g.size = {kNx, kNy, 1};
  g.origin = {-5, 3, 0};
  g.spacing = {0.8, 1.5, 1};
  LabelImage img(g, 0);
  for (int y = 3; y <= 12; ++y)
    for (int x = 0; x < kNx; ++x) {
      if (x >= 3 && x <= 12) img(x, y) = 1;
      const bool hole = x >= 26 && x <= 29 && y >= 6 && y <= 9;
      if (x >= 23 && x <= 32 && (fill_hole || !hole)) img(x, y) = annulus_label;
    }
  return img;
}

// One counter-clockwise quad per pixel of `img` split into two triangles,
// labelled as the pixel; background faces too unless foreground_only. Points
// in world coordinates, mirrored in x about the grid's centre when asked,
// each moved by up to `jitter` pixels per axis.
PolyMesh pixel_mesh(const LabelImage& img, bool mirror = false, double jitter = 0, bool foreground_only = false,
                    unsigned seed = 1) {
  PolyMesh m;
  m.planar = true;
  m.format = "ele";
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-jitter, jitter);
  const std::size_t W = img.size[0] + 1;
  for (std::size_t j = 0; j <= img.size[1]; ++j)
    for (std::size_t i = 0; i < W; ++i) {
      double x = double(i) - 0.5 + u(rng), y = double(j) - 0.5 + u(rng);
      if (mirror) x = double(img.size[0] - 1) - x;
      const Vec3 p = img.world(0, 0, 0);
      m.points.push_back({p[0] + x * img.spacing[0], p[1] + y * img.spacing[1], 0.0});
    }
  for (std::size_t y = 0; y < img.size[1]; ++y)
    for (std::size_t x = 0; x < img.size[0]; ++x) {
      const std::int32_t l = img(x, y);
      if (foreground_only && !l) continue;
      const int a = int(x + W * y), b = a + 1, c = b + int(W), d = a + int(W);
      m.faces.push_back({a, b, c});
      m.faces.push_back({a, c, d});
      m.region.push_back(l);
      m.region.push_back(l);
    }
  if (foreground_only) m.region.clear();
  return m;
}

ComponentCorrespondence certify(const PolyMesh& m, const LabelImage& img) {
  LabelImage fg = img;
  if (m.region.empty())
    for (auto& v : fg.data) v = v != 0;
  return match_regions(mesh_regions(m.points.size(), m.faces, m.region), m.points, m.faces, pixel_regions(fg), 2);
}

bool has(const std::string& s, const std::string& part) { return s.find(part) != std::string::npos; }

} // namespace

TEST_CASE("pixel regions: 4-connected components of one nonzero label, euler V - E + F", "[correspondence2d]") {
  const PixelRegions r = pixel_regions(disk_and_annulus(false));
  REQUIRE(r.label.size() == 2);
  CHECK(r.euler == std::vector<long long>{1, 0});  // disk first (its first pixel comes first)
  CHECK(r.pixels == std::vector<std::size_t>{100, 84});
  // Two labels touching: two regions. A pixel ring closed at a corner only:
  // V - E + F of the closed squares counts the corner once.
  LabelImage img = disk_and_annulus(false, 2);
  CHECK(pixel_regions(img).label == std::vector<std::int32_t>{1, 2});
  LabelImage diag(img.geometry(), 0);
  diag(1, 1) = diag(2, 2) = 1;
  const PixelRegions d = pixel_regions(diag);
  CHECK(d.label.size() == 2);
  CHECK(d.euler == std::vector<long long>{1, 1});
}

TEST_CASE("mesh regions: faces of one nonzero label joined by edges", "[correspondence2d]") {
  const PolyMesh m = pixel_mesh(disk_and_annulus(false));
  const MeshRegions r = mesh_regions(m.points.size(), m.faces, m.region);
  CHECK(r.label == std::vector<std::int32_t>{1, 1});
  CHECK(r.euler == std::vector<long long>{1, 0});
  CHECK(r.faces == std::vector<std::size_t>{200, 168});
  const MeshRegions all = mesh_regions(m.points.size(), m.faces, {});  // every face foreground: the rectangle
  CHECK(all.euler == std::vector<long long>{1});
}

TEST_CASE("the right planar mesh passes, exact and jittered, with and without labels", "[correspondence2d]") {
  const LabelImage img = disk_and_annulus(false);
  for (const double jitter : {0.0, 0.45}) {
    const ComponentCorrespondence r = certify(pixel_mesh(img, false, jitter), img);
    INFO("jitter " << jitter << ": " << r.failed_guarantee());
    CHECK(r.matches());
    CHECK(r.planar);
    REQUIRE(r.mesh.size() == 2);
    CHECK(r.mesh[0].boundary != r.mesh[1].boundary);
    CHECK(r.mesh[0].placed == r.mesh[0].vertices);  // every face placed
  }
  CHECK(certify(pixel_mesh(img, false, 0.3, true), img).matches());
  const LabelImage two = disk_and_annulus(false, 2);
  CHECK(certify(pixel_mesh(two, false, 0.3), two).matches());
}

TEST_CASE("a mirrored planar mesh (the disk where the annulus is) is refused", "[correspondence2d]") {
  const LabelImage img = disk_and_annulus(false);
  for (const bool labelled : {true, false}) {
    const PolyMesh m = pixel_mesh(img, true, 0, !labelled);
    // Same sorted Euler list as the right mesh: only places tell them apart.
    const ComponentCorrespondence r = certify(m, img);
    INFO(r.failed_guarantee());
    CHECK_FALSE(r.matches());
    REQUIRE(r.mesh.size() == 2);
    CHECK(r.mesh[0].verdict == "euler differs");
    CHECK(r.mesh[1].verdict == "euler differs");
    CHECK(has(r.failed_guarantee(), "mesh region 0 (label 1): euler 1, its pixel region 1 (label 1) has 0"));
  }
}

TEST_CASE("a planar mesh missing the hole, doubling or dropping a region, or with labels swapped is refused",
          "[correspondence2d]") {
  const LabelImage img = disk_and_annulus(false);
  {
    const ComponentCorrespondence r = certify(pixel_mesh(disk_and_annulus(true), false, 0.2), img);
    CHECK_FALSE(r.matches());
    CHECK(has(r.failed_guarantee(), "euler 1, its pixel region 1 (label 1) has 0"));
  }
  {  // the disk's faces twice, on vertices of their own
    PolyMesh m = pixel_mesh(img);
    const PolyMesh d = pixel_mesh(img, false, 0.2, false, 7);
    const int n = int(m.points.size());
    m.points.insert(m.points.end(), d.points.begin(), d.points.end());
    for (std::size_t f = 0; f < d.faces.size(); ++f)
      if (d.region[f] && m.points[std::size_t(d.faces[f][0])][0] < 9) {  // world x < 9: the disk
        auto c = d.faces[f];
        for (int& v : c) v += n;
        m.faces.push_back(c);
        m.region.push_back(1);
      }
    const ComponentCorrespondence r = certify(m, img);
    CHECK_FALSE(r.matches());
    CHECK(r.boundary[0].verdict == "matched twice");
    CHECK(has(r.failed_guarantee(), "pixel region 0 (label 1): matched by mesh regions 0, 2"));
  }
  {  // the annulus's faces become background
    PolyMesh m = pixel_mesh(img);
    for (std::size_t f = 0; f < m.faces.size(); ++f)
      if (m.points[std::size_t(m.faces[f][0])][0] > 9) m.region[f] = 0;
    const ComponentCorrespondence r = certify(m, img);
    CHECK_FALSE(r.matches());
    CHECK(r.boundary[1].verdict == "unmatched");
    CHECK(has(r.failed_guarantee(), "pixel region 1 (label 1) (euler 0): no mesh region"));
  }
  {  // labels 1 and 2 swapped: no face lies on a pixel of its label
    const LabelImage two = disk_and_annulus(false, 2);
    PolyMesh m = pixel_mesh(two);
    for (auto& l : m.region) l = l ? 3 - l : 0;
    const ComponentCorrespondence r = certify(m, two);
    CHECK_FALSE(r.matches());
    CHECK(r.mesh[0].verdict == "unplaced");
    CHECK(has(r.failed_guarantee(), "mesh region 0 (label 2): no face lies on a pixel of its label"));
  }
}

TEST_CASE("planar_mesh_info reports the regions and names the failure", "[correspondence2d]") {
  const LabelImage img = disk_and_annulus(false);
  const MeshInfo ok = planar_mesh_info(pixel_mesh(img, false, 0.3), "right.ele", img, "img.png");
  CHECK(ok.matches);
  CHECK(ok.report.at("image").at("euler").items().size() == 2);
  const MeshInfo bad = planar_mesh_info(pixel_mesh(img, true), "mirrored.ele", img, "img.png");
  CHECK_FALSE(bad.matches);
  CHECK(has(bad.failed_guarantee(), "the mesh's regions do not match the pixel regions of img.png"));
  CHECK(has(format_report(bad.report), "euler differs"));
}
