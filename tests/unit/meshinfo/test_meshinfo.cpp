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

TEST_CASE("image_comparison: the cube sphere matches bdCA(X) of one voxel", "[meshinfo]") {
  BinaryImage img = image3(5);
  img(2, 2, 2) = 1;
  const Faces s = cube_sphere(2);
  const Json j = image_comparison(mesh_topology(s.nv, s.f), voxel_boundary_topology(img));
  CHECK(j.at("matches").boolean());
  Faces two = cube_sphere(2);
  two.add(cube_sphere(1));
  CHECK_FALSE(image_comparison(mesh_topology(two.nv, two.f), voxel_boundary_topology(img)).at("matches").boolean());
}

TEST_CASE("mesh_info: the --image guarantee and its report", "[meshinfo]") {
  auto poly = [](const Faces& s) {
    PolyMesh m;
    for (std::size_t i = 0; i < s.nv; ++i) m.points.push_back({double(i % 3), double(i % 5), double(i % 7)});
    m.faces = s.f;
    return m;
  };
  BinaryImage img = image3(5);
  img(2, 2, 2) = 1;
  const MeshInfo same = mesh_info(poly(cube_sphere(2)), "m.off", &img, "x.nrrd");
  CHECK(same.failed_guarantee().empty());
  CHECK(same.to_json().at("matches_image").boolean());
  CHECK(same.report.at("image").at("matches").boolean());
  Faces two = cube_sphere(2);
  two.add(cube_sphere(1));
  const MeshInfo differ = mesh_info(poly(two), "m.off", &img, "x.nrrd");
  CHECK(differ.failed_guarantee().find("x.nrrd") != std::string::npos);
  CHECK_FALSE(differ.to_json().at("matches_image").boolean());
  CHECK(differ.to_json().at("components").integer() == 2);
  // Without an image there is nothing to fail and no matches_image.
  const MeshInfo alone = mesh_info(poly(two), "m.off");
  CHECK(alone.failed_guarantee().empty());
  CHECK_FALSE(alone.to_json().contains("matches_image"));
  // A non-well-composed image and a mesh without faces are refused.
  img(3, 3, 2) = 1;
  CHECK_THROWS_AS(mesh_info(poly(cube_sphere(2)), "m.off", &img, "x.nrrd"), Error);
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
  CHECK(swapped.failed_guarantee().find("mesh component 0: euler") != std::string::npos);
  const std::string text = format_report(swapped.report);
  CHECK(text.find("DOES NOT MATCH") != std::string::npos);
  CHECK(text.find("mesh #0: euler differs") != std::string::npos);
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
