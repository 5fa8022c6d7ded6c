// Element measures and checks of lib/mesh/tet_mesh on tetrahedra whose
// figures are known in closed form, and readers on malformed files.
#include "mesh/tet_mesh.hpp"
#include "mesh/volume_io.hpp"
#include "util/error.hpp"

#include "scratch_dir.hpp"

#include <catch2/catch.hpp>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <random>

using namespace imgmesh;

TEST_CASE("regular and right-corner tetrahedra: ratio, dihedral angles, volume") {
  const std::array<double, 3> a{1, 1, 1}, b{1, -1, -1}, c{-1, 1, -1}, d{-1, -1, 1};
  REQUIRE(tet_orient(a, b, c, d) != 0);
  CHECK(tet_radius_edge_ratio(a, b, c, d) == Approx(std::sqrt(6.0) / 4));  // R = sqrt 3, edge 2 sqrt 2
  for (double angle : tet_dihedral_angles(a, b, c, d)) CHECK(angle == Approx(std::acos(1.0 / 3) * 180 / M_PI));
  // The corner of a cube: three right dihedral angles at the corner, three of acos(1/sqrt 3).
  const std::array<double, 3> o{0, 0, 0}, x{1, 0, 0}, y{0, 1, 0}, z{0, 0, 1};
  auto ang = tet_dihedral_angles(o, x, y, z);
  std::sort(ang.begin(), ang.end());
  CHECK(ang[0] == Approx(std::acos(1 / std::sqrt(3.0)) * 180 / M_PI));
  CHECK(ang[3] == Approx(90));
  CHECK(ang[5] == Approx(90));
  CHECK(tet_orient(o, x, y, z) == Approx(1));
  CHECK(tet_circumradius(o, x, y, z) == Approx(std::sqrt(3.0) / 2));

  TetMesh m;
  m.points = {o, x, y, z, {1, 1, 1}};
  m.tets = {{0, 1, 2, 3}, {1, 2, 3, 4}};
  REQUIRE(tet_orient(x, y, z, {1, 1, 1}) > 0);
  m.tet_region = {1, 2};
  TetConformity ok = tet_conformity(m);
  CHECK(ok.ok());
  CHECK(ok.interior_faces == 1);
  CHECK(ok.boundary_faces == 6);
  const TetQualityReport q = tet_quality(m);
  CHECK(q.volume_by_region.at(1) == Approx(1.0 / 6));
  CHECK(q.volume_by_region.at(2) == Approx(1.0 / 3));  // (1,0,0),(0,1,0),(0,0,1),(1,1,1): a third of the cube
  CHECK(tet_boundary(m).size() == 6);
  CHECK(tet_boundary(m, 1).size() == 4);
  // Broken on purpose: an inverted tetrahedron, then one face in three.
  m.tets[1] = {1, 3, 2, 4};
  CHECK(tet_conformity(m).nonpositive == 1);
  CHECK(tet_conformity(m).inconsistent_faces == 1);
  m.tets[1] = {1, 2, 3, 4};
  m.points.push_back({-1, -1, -1});
  m.tets.push_back({5, 1, 2, 3});  // shares face 1-2-3 with both
  if (tet_orient(m.points[5], x, y, z) < 0) m.tets.back() = {5, 1, 3, 2};
  CHECK(tet_conformity(m).overfull_faces == 1);
  CHECK(!tet_conformity(m).ok());
}

TEST_CASE("malformed tetrahedral mesh files: an Error naming the file") {
  // In the test's working folder, not the system temporary one.
  const std::filesystem::path dir = "imgmesh_test_tet_mesh";
  std::filesystem::create_directories(dir);
  auto write = [&](const std::string& name, const std::string& text) {
    std::ofstream(dir / name) << text;
    return (dir / name).string();
  };
  CHECK_THROWS_AS(read_tet_mesh(write("a.msh", "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$Nodes\n1\n1 0 0\n")), Error);
  CHECK_THROWS_AS(read_tet_mesh(write("b.msh", "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$Nodes\n1\n1 0 0 0\n$EndNodes\n$Elements\n1\n1 4 2 1 1 1 2 3 4\n$EndElements\n")), Error);
  CHECK_THROWS_AS(read_tet_mesh(write("c.mesh", "MeshVersionFormatted 2\nDimension 3\nVertices\n1\n0 0 0 0\nTetrahedra\n1\n1 2 3 4 1\nEnd\n")), Error);
  CHECK_THROWS_AS(read_tet_mesh(write("d.mesh", "MeshVersionFormatted 2\nDimension 3\nVertices\n1\n0 0 nan 0\nEnd\n")), Error);
  CHECK_THROWS_AS(read_tet_mesh(write("e.vtu", "<VTKFile type=\"UnstructuredGrid\"><Points><DataArray format=\"binary\">")), Error);
  CHECK_THROWS_AS(read_tet_mesh(write("f.msh", "")), Error);
  std::filesystem::remove_all(dir);
}

TEST_CASE("an ASCII .vtu's cell errors name the line of the value") {
  const std::filesystem::path dir = "imgmesh_test_tet_mesh_vtu";
  std::filesystem::create_directories(dir);
  // Line 4: the points; 5: connectivity; 6: offsets; 7: types.
  auto vtu = [&](const std::string& connectivity, const std::string& offsets) {
    const std::string path = (dir / "t.vtu").string();
    std::ofstream(path) << "<VTKFile type=\"UnstructuredGrid\" version=\"0.1\">\n<UnstructuredGrid>\n"
                           "<Piece NumberOfPoints=\"4\" NumberOfCells=\"1\"><Points>\n"
                           "<DataArray type=\"Float64\" NumberOfComponents=\"3\" format=\"ascii\">0 0 0 1 0 0 0 1 0 0 0 1</DataArray></Points><Cells>\n"
                           "<DataArray type=\"Int64\" Name=\"connectivity\" format=\"ascii\">"
                        << connectivity << "</DataArray>\n<DataArray type=\"Int64\" Name=\"offsets\" format=\"ascii\">" << offsets
                        << "</DataArray>\n<DataArray type=\"UInt8\" Name=\"types\" format=\"ascii\">10</DataArray>\n"
                           "</Cells></Piece></UnstructuredGrid></VTKFile>\n";
    return path;
  };
  CHECK(read_tet_mesh(vtu("0 1 2 3", "4")).tets.size() == 1);
  CHECK_THROWS_WITH(read_tet_mesh(vtu("0 1 2 9", "4")), Catch::Contains("line 5: cell refers to unknown point 9"));
  CHECK_THROWS_WITH(read_tet_mesh(vtu("0 1\n2\n\n 9", "4")), Catch::Contains("line 8: cell refers to unknown point 9"));
  CHECK_THROWS_WITH(read_tet_mesh(vtu("0 1 2 3", "-1")), Catch::Contains("line 6: decreasing offsets"));
  CHECK_THROWS_WITH(read_tet_mesh(vtu("0 1 2\n", "4")), Catch::Contains("line 6: unexpected end of file"));
  std::filesystem::remove_all(dir);
}

TEST_CASE("binary .vtu and .msh read back to the mesh their ASCII form holds, exactly") {
  // Random points (fixed seed) filling more than one 32 KiB zlib block,
  // tetrahedra and boundary triangles in two regions.
  TetMesh m;
  std::mt19937 rng(37);
  std::uniform_real_distribution<double> u(-100, 100);
  for (int i = 0; i < 3000; ++i) m.points.push_back({u(rng), u(rng), u(rng)});
  for (int i = 0; i + 3 < 3000; i += 3) {
    m.tets.push_back({i, i + 1, i + 2, i + 3});
    m.tet_region.push_back(1 + i % 2);
    m.triangles.push_back({i + 3, i + 1, i});
    m.triangle_region.push_back(1 + i % 2);
  }
  const std::string dir = test::scratch_dir();
  auto bytes = [](const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    return std::string((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  };
  for (const std::string name : {"t.vtu", "t.msh", "t22.msh"}) {
    DYNAMIC_SECTION(name) {
      TetWriteOptions text, binary;
      text.ascii = true;
      binary.msh_binary = true;
      text.msh_version = binary.msh_version = name == "t22.msh" ? "2.2" : "4.1";
      write_tet_mesh(dir + "/a" + name, m, text);
      write_tet_mesh(dir + "/b" + name, m, binary);
      const std::string a = bytes(dir + "/a" + name), b = bytes(dir + "/b" + name);
      if (name == "t.vtu") CHECK(b.find("<AppendedData encoding=\"raw\">") != std::string::npos);
      if (name == "t.vtu") CHECK(b.size() < a.size() / 2);
      else CHECK(b.find(text.msh_version + " 1 8\n") != std::string::npos);
      const TetMesh ra = read_tet_mesh(dir + "/a" + name), rb = read_tet_mesh(dir + "/b" + name);
      CHECK(rb.points == ra.points);
      CHECK(rb.tets == ra.tets);
      CHECK(rb.triangles == ra.triangles);
      CHECK(rb.tet_region == ra.tet_region);
      CHECK(rb.triangle_region == ra.triangle_region);
      // 17 digits in ASCII: the doubles themselves.
      CHECK(ra.points == m.points);
      if (name == "t.vtu") {
        CHECK(ra.tets == m.tets);
        CHECK(rb.tet_region == m.tet_region);
      }
      // A byte lost in the binary data is an Error, not another mesh.
      std::string cut = b;
      cut.erase(b.size() / 2, 1);
      std::ofstream(dir + "/c" + name, std::ios::binary) << cut;
      CHECK_THROWS_AS(read_tet_mesh(dir + "/c" + name), Error);
    }
  }
}

TEST_CASE("a legacy .vtk UNSTRUCTURED_GRID (4.2 and 5.1) read as tetrahedra with their region") {
  const std::string path = test::scratch_dir() + "/grid.vtk";
  // Two tetrahedra, a triangle and a line (left out), regions 3 7 5 9.
  const std::string points = "POINTS 5 double\n0 0 0 1 0 0 0 1 0 0 0 1 1 1 1\n";
  const std::string data = "CELL_TYPES 4\n10 10 5 3\nCELL_DATA 4\nFIELD FieldData 1\nregion 1 4 int\n3 7 5 9\n";
  for (const std::string cells : {"CELLS 4 17\n4 0 1 2 3\n4 1 2 3 4\n3 0 1 2\n2 0 4\n",
                                  "CELLS 5 13\nOFFSETS vtktypeint64\n0 4 8 11 13\nCONNECTIVITY vtktypeint64\n"
                                  "0 1 2 3 1 2 3 4 0 1 2 0 4\n"}) {
    std::ofstream(path) << "# vtk DataFile Version 5.1\nvtk output\nASCII\nDATASET UNSTRUCTURED_GRID\n" << points << cells << data;
    const TetMesh m = read_tet_mesh(path);
    CHECK(m.points.size() == 5);
    CHECK(m.tets == std::vector<std::array<int, 4>>{{0, 1, 2, 3}, {1, 2, 3, 4}});
    CHECK(m.tet_region == std::vector<int>{3, 7});
    CHECK(m.triangles == std::vector<std::array<int, 3>>{{0, 1, 2}});
    CHECK(m.triangle_region == std::vector<int>{5});
  }
  // BINARY (big-endian, bytes by hand), with the type names of VTK 9 and
  // meshio: vtkIdType 4 bytes, vtktypeint32.
  const std::string f0(4, '\0'), f1("\x3f\x80\0\0", 4);
  const auto be32 = [](char v) { return std::string(3, '\0') + v; };
  std::ofstream(path, std::ios::binary)
      << "# vtk DataFile Version 5.1\nvtk output\nBINARY\nDATASET UNSTRUCTURED_GRID\nPOINTS 4 float\n"
      << f0 + f0 + f0 + f1 + f0 + f0 + f0 + f1 + f0 + f0 + f0 + f1 << "\nCELLS 1 5\n"
      << be32(4) + be32(0) + be32(1) + be32(2) + be32(3) << "\nCELL_TYPES 1\n" << be32(10)
      << "\nCELL_DATA 1\nFIELD FieldData 2\nids 1 1 vtkIdType\n" << be32(42) << "\nregion 1 1 vtktypeint32\n" << be32(7)
      << "\n";
  const TetMesh b = read_tet_mesh(path);
  CHECK(b.points == std::vector<std::array<double, 3>>{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}});
  CHECK(b.tets == std::vector<std::array<int, 4>>{{0, 1, 2, 3}});
  CHECK(b.tet_region == std::vector<int>{7});
  std::ofstream(path) << "# vtk DataFile Version 4.2\nvtk output\nASCII\nDATASET UNSTRUCTURED_GRID\n" << points
                      << "CELLS 1 5\n4 0 1 2 3\nCELL_TYPES 2\n10 10\n";
  CHECK_THROWS_WITH(read_tet_mesh(path), Catch::Contains("not one CELL_TYPES value a cell"));
  std::ofstream(path) << "# vtk DataFile Version 4.2\nvtk output\nASCII\nDATASET POLYDATA\n" << points
                      << "POLYGONS 1 4\n3 0 1 2\n";
  CHECK_THROWS_WITH(read_tet_mesh(path), Catch::Contains("DATASET UNSTRUCTURED_GRID"));
}

TEST_CASE("the stated boundary against the tetrahedra's: a missing, flipped, doubled or misplaced triangle named") {
  TetMesh m;
  m.points = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}, {1, 1, 1}};
  m.tets = {{0, 1, 2, 3}, {1, 2, 3, 4}};
  m.tet_region = {1, 2};
  // Region 1's boundary, then region 2's but the face they share (1 2 3).
  for (const int r : {1, 2})
    for (const auto& t : tet_boundary(m, r)) {
      auto s = t;
      std::sort(s.begin(), s.end());
      if (r == 2 && s == std::array<int, 3>{1, 2, 3}) continue;
      m.triangles.push_back({t[1], t[2], t[0]});  // rotated: the same oriented triangle
      m.triangle_region.push_back(r);
    }
  REQUIRE(m.triangles.size() == 7);
  CHECK(boundary_mismatch(m).empty());
  {
    TetMesh flipped = m;
    std::swap(flipped.triangles[5][0], flipped.triangles[5][1]);
    CHECK(boundary_mismatch(flipped).find("triangle 5 (region 2) is not a face") == 0);
  }
  {
    TetMesh dropped = m;
    dropped.triangles.pop_back();
    dropped.triangle_region.pop_back();
    CHECK(boundary_mismatch(dropped) == "1 face(s) of the regions' boundaries not among the triangles");
  }
  {
    TetMesh doubled = m;  // the shared face stated on both sides
    for (const auto& t : tet_boundary(m, 2)) {
      auto s = t;
      std::sort(s.begin(), s.end());
      if (s != std::array<int, 3>{1, 2, 3}) continue;
      doubled.triangles.push_back(t);
      doubled.triangle_region.push_back(2);
    }
    REQUIRE(doubled.triangles.size() == 8);
    CHECK(boundary_mismatch(doubled).find("states a boundary face twice") != std::string::npos);
  }
  {
    TetMesh misplaced = m;
    misplaced.triangle_region[0] = 2;  // region 1's outer face said to bound region 2
    CHECK(boundary_mismatch(misplaced).find("triangle 0 (region 2) is not a face") == 0);
  }
}

// Label pairs on the triangles (seg2tet): Gmsh 4.1 a group per pair beside
// each region's boundary group, read back as the triangles' regions; 2.2
// the same regions with an elementary tag per pair; Abaqus a surface per pair.
TEST_CASE("triangles with label pairs: a group per pair, the regions read back") {
  TetMesh m;
  m.points = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}, {1, 1, 1}};
  m.tets = {{0, 1, 2, 3}, {1, 2, 3, 4}};
  m.tet_region = {7, 3};
  // Region 7's boundary (its face shared with 3 once, out of 7), then 3's others.
  for (const int r : {7, 3})
    for (const auto& t : tet_boundary(m, r)) {
      auto s = t;
      std::sort(s.begin(), s.end());
      const bool shared = s == std::array<int, 3>{1, 2, 3};
      if (r == 3 && shared) continue;
      m.triangles.push_back(t);
      m.triangle_region.push_back(r);
      m.triangle_pair.push_back({r, shared ? 3 : 0});
    }
  REQUIRE(boundary_mismatch(m).empty());
  m.region_names[7] = "grey matter";
  const std::string dir = test::scratch_dir();
  auto bytes = [](const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    return std::string((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  };
  for (const std::string version : {"4.1", "2.2"}) {
    TetWriteOptions o;
    o.msh_version = version;
    write_tet_mesh(dir + "/p.msh", m, o);
    // The same triangles and tetrahedra with their regions (in blocks, so in another order).
    auto with_regions = [](const TetMesh& t) {
      std::vector<std::pair<int, std::array<int, 4>>> e;
      for (std::size_t i = 0; i < t.triangles.size(); ++i)
        e.push_back({t.triangle_region[i], {t.triangles[i][0], t.triangles[i][1], t.triangles[i][2], -1}});
      for (std::size_t i = 0; i < t.tets.size(); ++i) e.push_back({t.tet_region[i], t.tets[i]});
      std::sort(e.begin(), e.end());
      return e;
    };
    CHECK(with_regions(read_tet_mesh(dir + "/p.msh")) == with_regions(m));
    // Names do not decide region 0: a region 3 named "background" stays 3;
    // a region 0 named "air" comes back as 0.
    for (const int zero : {3, 0}) {
      TetMesh n = m;
      if (zero == 0) {
        for (int& r : n.tet_region) r = r == 3 ? 0 : r;
        for (int& r : n.triangle_region) r = r == 3 ? 0 : r;
        for (auto& p : n.triangle_pair) p[1] = p[1] == 3 ? 0 : p[1];
        n.region_names[0] = "air";
      } else {
        n.region_names[3] = "background";
      }
      write_tet_mesh(dir + "/n.msh", n, o);
      CHECK(with_regions(read_tet_mesh(dir + "/n.msh")) == with_regions(n));
    }
    const std::string text = bytes(dir + "/p.msh");
    CHECK((text.find("\"grey matter|3\"") != std::string::npos) == (version == "4.1"));
    CHECK(text.find("\"grey matter boundary\"") != std::string::npos);
  }
  write_tet_mesh(dir + "/p.inp", m);
  const std::string inp = bytes(dir + "/p.inp");
  for (const char* s : {"NAME=INTERFACE_7_3\n", "NAME=INTERFACE_7_0\n", "NAME=INTERFACE_3_0\n", "NAME=BOUNDARY_7\n",
                        "ELSET=grey_matter\nREGION_7\n"})
    CHECK(inp.find(s) != std::string::npos);
}
