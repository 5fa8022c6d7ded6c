// The 2D certificate by correspondence (pixel_regions, mesh_regions,
// match_regions): a square "disk" and a square "annulus" with the same outer
// square, so that mirroring x puts each where the other is, in a grid with
// an origin and anisotropic spacing. A planar mesh of the pixel squares (with
// background faces, region labels per face, vertices jittered) must pass;
// the mirrored mesh, a mesh missing the hole, one with the disk doubled or
// the annulus dropped, and one with labels swapped must be refused, naming
// the region and why.
#include "mesh/topology.hpp"
#include "shapes.hpp"

#include <catch2/catch.hpp>

using namespace imgmesh;
using namespace imgmesh::test;

namespace {

ComponentCorrespondence certify(const PixelMesh& m, const LabelImage& img) {
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
  const PixelMesh m = pixel_mesh(disk_and_annulus(false));
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
    const PixelMesh m = pixel_mesh(img, true, 0, !labelled);
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
    PixelMesh m = pixel_mesh(img);
    const PixelMesh d = pixel_mesh(img, false, 0.2, false, 7);
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
    PixelMesh m = pixel_mesh(img);
    for (std::size_t f = 0; f < m.faces.size(); ++f)
      if (m.points[std::size_t(m.faces[f][0])][0] > 9) m.region[f] = 0;
    const ComponentCorrespondence r = certify(m, img);
    CHECK_FALSE(r.matches());
    CHECK(r.boundary[1].verdict == "unmatched");
    CHECK(has(r.failed_guarantee(), "pixel region 1 (label 1) (euler 0): no mesh region"));
  }
  {  // labels 1 and 2 swapped: no face lies on a pixel of its label
    const LabelImage two = disk_and_annulus(false, 2);
    PixelMesh m = pixel_mesh(two);
    for (auto& l : m.region) l = l ? 3 - l : 0;
    const ComponentCorrespondence r = certify(m, two);
    CHECK_FALSE(r.matches());
    CHECK(r.mesh[0].verdict == "unplaced");
    CHECK(has(r.failed_guarantee(), "mesh region 0 (label 2): no face lies on a pixel of its label"));
  }
}
