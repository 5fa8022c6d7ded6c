// meshinfo's library on the meshes of tests/unit/mesh/shapes.hpp: the
// report (components and euler first, its text), the comparison with
// bdCA(X) of an image, in 3D by component (a mesh with the components in
// each other's places fails, naming them) and in 2D by region.
#include "mesh/shapes.hpp"
#include "meshinfo/meshinfo.hpp"
#include "util/error.hpp"

#include <catch2/catch.hpp>

using namespace imgmesh;
using namespace imgmesh::test;

namespace {

// A planar mesh of pixel squares as meshinfo reads a Triangle .ele.
PolyMesh as_poly_mesh(const PixelMesh& p) {
  PolyMesh m;
  m.points = p.points;
  m.faces = p.faces;
  m.region = p.region;
  m.planar = true;
  m.format = "ele";
  return m;
}

bool has(const std::string& s, const std::string& part) { return s.find(part) != std::string::npos; }

} // namespace

TEST_CASE("mesh_report puts components and euler first", "[meshinfo]") {
  PolyMesh m;
  const Faces s = grid(3, 3, true, true);
  for (std::size_t i = 0; i < s.nv; ++i) m.points.push_back({double(i), double(i * i % 7), 1.0});
  m.faces = s.f;
  m.format = "off";
  const Json j = mesh_report(m);
  CHECK(j.at("components").integer() == 1);
  REQUIRE(j.at("euler").items().size() == 1);
  CHECK(j.at("euler").items()[0].integer() == 0);
  const std::string text = format_report(j);
  CHECK(text.find("components  1") != std::string::npos);
  // Round trip through the JSON parser.
  const Json back = Json::parse(j.dump(-1));
  CHECK(back.at("faces").integer() == long(s.f.size()));
}

TEST_CASE("mesh_info: the --image certificate and its report", "[meshinfo]") {
  BinaryImage img = image3(5);
  img(2, 2, 2) = 1;
  // The voxel's six faces as quads (split into fans for the certificate).
  auto cube = [&](const Vec3& shift) {
    const VoxelBoundary b = voxel_boundary(img);
    PolyMesh m;
    for (std::size_t v = 0; v < b.lattice_ids.size(); ++v) {
      const Vec3 p = corner_position(img, b, v);
      m.points.push_back({p[0] + shift[0], p[1] + shift[1], p[2] + shift[2]});
    }
    for (std::size_t f = 0; f + 1 < b.offsets.size(); ++f)
      m.faces.push_back({b.corners[b.offsets[f]], b.corners[b.offsets[f] + 1], b.corners[b.offsets[f] + 2], b.corners[b.offsets[f] + 3]});
    m.format = "off";
    return m;
  };
  const MeshInfo same = mesh_info(cube({0, 0, 0}), "m.off", &img, "x.nrrd");
  CHECK(same.failed_guarantee().empty());
  CHECK(same.to_json().at("matches_image").boolean());
  CHECK(same.report.at("image").at("matches").boolean());
  CHECK(same.report.at("image").at("certificate").at("verdict").string() == "ok");
  CHECK(has(format_report(same.report), "MATCHES (certificate holds)"));
  // The cube and a copy of it three voxels away: the copy is placed nowhere.
  PolyMesh two = cube({0, 0, 0});
  const PolyMesh far = cube({3, 0, 0});
  for (auto f : far.faces) {
    for (int& v : f) v += int(two.points.size());
    two.faces.push_back(f);
  }
  two.points.insert(two.points.end(), far.points.begin(), far.points.end());
  const MeshInfo differ = mesh_info(two, "m.off", &img, "x.nrrd");
  CHECK(has(differ.failed_guarantee(), "the mesh is not certified against bdCA(X) of x.nrrd: placed: mesh component 1"));
  CHECK_FALSE(differ.to_json().at("matches_image").boolean());
  CHECK(differ.to_json().at("components").integer() == 2);
  CHECK(has(format_report(differ.report), "first failure: placed"));
  // A --place-tolerance of 4 voxels places the copy, on the voxel already matched.
  CertificateOptions wide;
  wide.place_tolerance = 4;
  CHECK(has(mesh_info(two, "m.off", &img, "x.nrrd", wide).failed_guarantee(), "matched: bdCA(X) component 0: matched by mesh components 0, 1"));
  // Without an image there is nothing to fail and no matches_image.
  const MeshInfo alone = mesh_info(two, "m.off");
  CHECK(alone.failed_guarantee().empty());
  CHECK_FALSE(alone.to_json().contains("matches_image"));
  // A non-well-composed image and a mesh without faces are refused.
  img(3, 3, 2) = 1;
  CHECK_THROWS_AS(mesh_info(cube({0, 0, 0}), "m.off", &img, "x.nrrd"), Error);
  CHECK_THROWS_AS(mesh_info(PolyMesh{}, "m.off"), Error);
}

TEST_CASE("meshinfo --image: the swapped mesh fails with a per-component verdict", "[meshinfo][correspondence]") {
  const BinaryImage img = two_solids(false);
  auto poly = [](const Tri& t) {
    PolyMesh m;
    m.points = t.points;
    for (const auto& f : t.tris) m.faces.push_back({f[0], f[1], f[2]});
    return m;
  };
  const MeshInfo right = mesh_info(poly(triangulate(img, {0, 1}, false)), "m.off", &img, "wc.nrrd");
  CHECK(right.failed_guarantee().empty());
  CHECK(right.report.at("image").at("correspondence").at("matches").boolean());
  const MeshInfo swapped = mesh_info(poly(triangulate(img, {0, 1}, true)), "s.off", &img, "wc.nrrd");
  CHECK_FALSE(swapped.to_json().at("matches_image").boolean());
  CHECK_FALSE(swapped.report.at("image").at("matches").boolean());
  // The torus where the ball is: its hole's walls are far from the ball's
  // faces. The sphere where the torus is lies on its outer faces: placed,
  // with the wrong Euler characteristic.
  CHECK(has(swapped.failed_guarantee(), "placed: mesh component "));
  const std::string text = format_report(swapped.report);
  CHECK(has(text, "DOES NOT MATCH"));
  CHECK(has(text, "euler differs"));
  CHECK(has(text, "unplaced"));
}

TEST_CASE("planar_mesh_info reports the regions and names the failure", "[correspondence2d]") {
  const LabelImage img = disk_and_annulus(false);
  const MeshInfo ok = planar_mesh_info(as_poly_mesh(pixel_mesh(img, false, 0.3)), "right.ele", img, "img.png");
  CHECK(ok.matches);
  CHECK(ok.report.at("image").at("euler").items().size() == 2);
  const MeshInfo bad = planar_mesh_info(as_poly_mesh(pixel_mesh(img, true)), "mirrored.ele", img, "img.png");
  CHECK_FALSE(bad.matches);
  CHECK(has(bad.failed_guarantee(), "the mesh's regions do not match the pixel regions of img.png"));
  CHECK(has(format_report(bad.report), "euler differs"));
}
