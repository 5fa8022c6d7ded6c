// Abaqus .inp read back (mesh/volume_io.hpp): write_inp's meshes with their
// regions and boundary, Gmsh's layout, and malformed files refused naming
// the line or what is wrong.
#include "mesh/tet_mesh.hpp"
#include "mesh/volume_io.hpp"
#include "util/error.hpp"

#include "scratch_dir.hpp"

#include <catch2/catch.hpp>
#include <algorithm>
#include <fstream>

using namespace imgmesh;

namespace {

// Tetrahedra and triangles with their regions, each element's vertices
// rotated to start at its smallest (the same oriented simplex), sorted.
std::vector<std::pair<int, std::array<int, 4>>> with_regions(const TetMesh& t) {
  std::vector<std::pair<int, std::array<int, 4>>> e;
  for (std::size_t i = 0; i < t.triangles.size(); ++i) {
    auto v = t.triangles[i];
    std::rotate(v.begin(), std::min_element(v.begin(), v.end()), v.end());
    e.push_back({t.triangle_region[i], {v[0], v[1], v[2], -1}});
  }
  for (std::size_t i = 0; i < t.tets.size(); ++i) e.push_back({t.tet_region[i], t.tets[i]});
  std::sort(e.begin(), e.end());
  return e;
}

} // namespace

TEST_CASE("an .inp written then read: the same tetrahedra, regions and oriented boundary") {
  // Three tetrahedra around the edge 0-1 in regions 7, 3, 3 (7 named), the
  // boundary of each region stated out of it, their interface once.
  TetMesh m;
  m.points = {{0, 0, 0}, {0, 0, 1}, {1, 0, 0}, {0, 1, 0}, {-1, -1, 0}};
  m.tets = {{0, 2, 3, 1}, {0, 3, 4, 1}, {0, 4, 2, 1}};
  for (const auto& t : m.tets) REQUIRE(tet_orient(m.points[std::size_t(t[0])], m.points[std::size_t(t[1])], m.points[std::size_t(t[2])], m.points[std::size_t(t[3])]) > 0);
  m.tet_region = {7, 3, 3};
  for (const int r : {7, 3})
    for (const auto& t : tet_boundary(m, r)) {
      auto s = t;
      std::sort(s.begin(), s.end());
      if (r == 3 && (s == std::array<int, 3>{0, 1, 2} || s == std::array<int, 3>{0, 1, 3})) continue;
      m.triangles.push_back(t);
      m.triangle_region.push_back(r);
    }
  REQUIRE(boundary_mismatch(m).empty());
  m.region_names[7] = "grey matter";
  const std::string path = test::scratch_dir() + "/m.inp";
  write_tet_mesh(path, m);
  const TetMesh r = read_tet_mesh(path);
  CHECK(r.points == m.points);
  CHECK(with_regions(r) == with_regions(m));
  CHECK(boundary_mismatch(r).empty());
}

TEST_CASE("Gmsh's .inp: regions from PhysicalVolumeR, triangles from CPS3, any case, trailing commas") {
  const std::string path = test::scratch_dir() + "/g.inp";
  std::ofstream(path) << "*Heading\n g.msh\n*NODE\n1, 0, 0, 0\n2, 1, 0, 0\n3, 0, 1, 0\n4, 0, 0, 1\n5, 1, 1, 1\n"
                         "******* E L E M E N T S *************\n*ELEMENT, type=CPS3, ELSET=Surface1\n1, 2, 3, 4\n"
                         "*ELEMENT, type=T3D2, ELSET=Line1\n2, 1, 2\n"
                         "*ELEMENT, type=C3D4, ELSET=Volume1\n3, 1, 2, 3, 4\n4, 2, 3, 4, 5\n"
                         "*ELSET,ELSET=PhysicalSurface9\n1, \n*ELSET,ELSET=PhysicalVolume4\n3, \n"
                         "*elset, elset=physicalvolume6, generate\n4, 4\n*ELSET,ELSET=white matter\n4, \n";
  const TetMesh m = read_tet_mesh(path);
  CHECK(m.points.size() == 5);
  CHECK(m.tets == std::vector<std::array<int, 4>>{{0, 1, 2, 3}, {1, 2, 3, 4}});
  CHECK(m.tet_region == std::vector<int>{4, 6});
  CHECK(m.triangles == std::vector<std::array<int, 3>>{{1, 2, 3}});
  CHECK(m.triangle_region == std::vector<int>{9});
}

TEST_CASE("malformed .inp files: one Error naming the file and what is wrong") {
  const std::string dir = test::scratch_dir();
  const std::string nodes = "*NODE\n1, 0, 0, 0\n2, 1, 0, 0\n3, 0, 1, 0\n4, 0, 0, 1\n";
  const std::string tet = "*ELEMENT, TYPE=C3D4, ELSET=REGION_1\n1, 1, 2, 3, 4\n";
  int k = 0;
  auto fails = [&](const std::string& text, const std::string& why) {
    const std::string path = dir + "/bad" + std::to_string(k++) + ".inp";
    std::ofstream(path) << text;
    try {
      read_tet_mesh(path);
      FAIL("read: " << why);
    } catch (const Error& e) {
      CHECK(e.path() == path);
      CHECK_THAT(e.what(), Catch::Contains(why));
    }
  };
  fails(nodes + "*ELEMENT, TYPE=C3D4\n1, 1, 2, 3, 4\n", "tetrahedron 1 is in no region set");
  fails(nodes + "*ELEMENT, TYPE=C3D4, ELSET=ball\n1, 1, 2, 3, 4\n", "tetrahedron 1 is in no region set");
  fails(nodes + tet + "*ELSET, ELSET=REGION_2\n1\n", "element 1 is in the sets of regions 1 and 2");
  fails(nodes + "*ELEMENT, TYPE=C3D10, ELSET=REGION_1\n1, 1, 2, 3, 4\n", "line 6: unsupported element type C3D10");
  fails(nodes + "*ELEMENT, TYPE=C3D4, ELSET=REGION_1\n1, 1, 2, 3, 9\n", "line 7: element 1 refers to unknown node 9");
  fails(nodes + "*ELEMENT, TYPE=C3D4, ELSET=REGION_1\n1, 1, 2, 3\n", "line 7: element 1: 4 nodes expected");
  fails("*NODE\n1, 0, 0, nan\n", "line 2: ");
  fails("*NODE\n1, 0, 0\n", "line 2: a node is 'id, x, y, z'");
  fails("*NODE\n1, 0, 0, 0\n1, 1, 0, 0\n", "line 3: node 1 defined twice");
  fails("1, 0, 0, 0\n", "line 1: data before any keyword");
  fails("*INCLUDE, INPUT=mesh.inp\n", "line 1: *INCLUDE is not supported");
  fails(nodes + tet + "*ELSET, ELSET=ALL\nREGION_1, ball\n*SURFACE, NAME=BOUNDARY_1\nALL, S1\n", "element set BALL is not defined");
  fails(nodes + tet + "*SURFACE, NAME=BOUNDARY_1\n1, S5\n", "face S5 is not S1-S4");
  fails(nodes, "no tetrahedron");
}
