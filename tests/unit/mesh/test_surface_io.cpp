#include "mesh/surface_io.hpp"
#include "util/error.hpp"

#include "scratch_dir.hpp"

#include <catch2/catch.hpp>
#include <algorithm>
#include <array>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <iterator>
#include <vector>
#include <set>
#include <unistd.h>

using namespace imgmesh;

namespace {
std::string temp_dir() { return test::scratch_dir(); }
// A tetrahedron, outward oriented, with non-round coordinates.
SurfaceMesh tetra() {
  SurfaceMesh m;
  m.points = {{0.1, 0.2, 0.3}, {1.0 / 3, 0, 0}, {0, 1e-7, 2}, {-12.5, 7, 1}};
  m.triangles = {{0, 2, 1}, {0, 1, 3}, {1, 2, 3}, {0, 3, 2}};
  return m;
}
// Triangles as cycles of point coordinates, independent of vertex numbering
// and of the first vertex, but not of the winding: each cycle starts at its
// smallest point and keeps its order, so a flipped triangle compares unequal.
using Corner = std::array<float, 3>;
std::multiset<std::array<Corner, 3>> shape(const SurfaceMesh& m) {
  std::multiset<std::array<Corner, 3>> s;
  for (const auto& t : m.triangles) {
    std::array<Corner, 3> tri;
    for (int k = 0; k < 3; ++k) {
      const auto& p = m.points[std::size_t(t[k])];
      tri[k] = {float(p[0]), float(p[1]), float(p[2])};
    }
    std::rotate(tri.begin(), std::min_element(tri.begin(), tri.end()), tri.end());
    s.insert(tri);
  }
  return s;
}
} // namespace

TEST_CASE("surface meshes round-trip through OFF, PLY, OBJ and STL") {
  const SurfaceMesh m = tetra();
  for (const char* ext : {".off", ".ply", ".obj", ".stl"}) {
    DYNAMIC_SECTION(ext) {
      const std::string path = temp_dir() + "/t" + ext;
      write_surface(path, m);
      const SurfaceMesh back = read_surface(path);
      CHECK(back.triangles.size() == m.triangles.size());
      CHECK(shape(back) == shape(m));
    }
  }
  // OFF keeps full double precision.
  const std::string off = temp_dir() + "/exact.off";
  write_surface(off, m);
  CHECK(read_surface(off).points == m.points);
}

TEST_CASE("bad surface files give an Error") {
  const std::string a = temp_dir() + "/bad1.off";
  std::ofstream(a) << "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 7\n";
  CHECK_THROWS_WITH(read_surface(a), Catch::Contains("out of range"));
  const std::string b = temp_dir() + "/bad2.off";
  std::ofstream(b) << "OFF\n3 1 0\n0 0 0\n1 0\n";
  CHECK_THROWS_AS(read_surface(b), Error);
  const std::string c = temp_dir() + "/bad3.off";
  std::ofstream(c) << "OFF\n4 1 0\n0 0 0\n1 0 0\n0 1 0\n1 1 0\n4 0 1 3 2\n";
  CHECK_THROWS_WITH(read_surface(c), Catch::Contains("triangles expected"));
  const std::string d = temp_dir() + "/bad4.off";
  std::ofstream(d) << "OFF\n3 1 0\n0 0 nan\n1 0 0\n0 1 0\n3 0 1 2\n";
  CHECK_THROWS_AS(read_surface(d), Error);
  CHECK_THROWS_AS(read_surface(temp_dir() + "/missing.ply"), Error);
  CHECK_THROWS_AS(write_surface(temp_dir() + "/x.gts", tetra()), UsageError);
}

TEST_CASE("a triangle set that is not a manifold is still written as PLY, OBJ and STL") {
  // Three triangles on one edge: OpenMesh's halfedge mesh cannot hold it.
  SurfaceMesh m;
  m.points = {{0, 0, 0}, {1, 0, 0}, {0.5, 1, 0}, {0.5, -1, 0}, {0.5, 0, 1.25}};
  m.triangles = {{0, 1, 2}, {1, 0, 3}, {0, 1, 4}};
  auto bytes = [](const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    return std::string((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  };
  auto f32 = [](const std::string& b, std::size_t at) {
    float v;
    std::memcpy(&v, b.data() + at, 4);
    return v;
  };
  SECTION("PLY: header counts, float coordinates, faces as given") {
    write_surface(temp_dir() + "/nm.ply", m);
    const std::string b = bytes(temp_dir() + "/nm.ply");
    const auto body = b.find("end_header\n") + 11;
    REQUIRE(body > 11);
    CHECK(b.find("element vertex 5\n") != std::string::npos);
    CHECK(b.find("element face 3\n") != std::string::npos);
    REQUIRE(b.size() == body + 5 * 12 + 3 * 17);  // a face: count, 3 ids, its component id
    CHECK(f32(b, body + 4 * 12 + 8) == 1.25f);  // z of the last point
    const std::size_t face2 = body + 5 * 12 + 2 * 17;
    CHECK(b[face2] == 3);
    std::int32_t ids[4];
    std::memcpy(ids, b.data() + face2 + 1, 16);
    CHECK((ids[0] == 0 && ids[1] == 1 && ids[2] == 4 && ids[3] == 0));
  }
  SECTION("OBJ: every vertex and face, 1-based") {
    write_surface(temp_dir() + "/nm.obj", m);
    std::ifstream in(temp_dir() + "/nm.obj");
    std::string line;
    int v = 0;
    std::vector<std::string> faces;
    while (std::getline(in, line)) {
      if (line.rfind("v ", 0) == 0) ++v;
      if (line.rfind("f ", 0) == 0) faces.push_back(line);
    }
    CHECK(v == 5);
    CHECK(faces == std::vector<std::string>{"f 1 2 3", "f 2 1 4", "f 1 2 5"});
  }
  SECTION("STL: the count and each triangle's corners") {
    write_surface(temp_dir() + "/nm.stl", m);
    const std::string b = bytes(temp_dir() + "/nm.stl");
    REQUIRE(b.size() == 84 + 3 * 50);
    std::uint32_t n;
    std::memcpy(&n, b.data() + 80, 4);
    CHECK(n == 3);
    // Third triangle (0, 1, 4): normal (0, -1, 0), last corner (0.5, 0, 1.25).
    const std::size_t t2 = 84 + 2 * 50;
    CHECK(f32(b, t2 + 4) == -1.0f);
    CHECK(f32(b, t2 + 12 + 24 + 8) == 1.25f);
  }
}

TEST_CASE("binary and ASCII PLY and STL read back to the same floats and triangles") {
  const SurfaceMesh m = tetra();
  for (const char* ext : {".ply", ".stl"}) {
    DYNAMIC_SECTION(ext) {
      SurfaceWriteOptions text;
      text.ascii = true;
      const std::string a = temp_dir() + "/a" + ext, b = temp_dir() + "/b" + ext;
      write_surface(a, m, text);
      write_surface(b, m);
      std::ifstream in(a);
      std::string first;
      in >> first;
      CHECK(first == (std::string(ext) == ".ply" ? "ply" : "solid"));
      const SurfaceMesh ra = read_surface(a), rb = read_surface(b);
      CHECK(ra.points == rb.points);
      CHECK(ra.triangles == rb.triangles);
      CHECK(shape(ra) == shape(m));
      for (std::size_t i = 0; i < ra.points.size(); ++i)
        for (int k = 0; k < 3; ++k) CHECK(std::abs(ra.points[i][std::size_t(k)]) == std::abs(float(ra.points[i][std::size_t(k)])));
    }
  }
}

namespace {
// Three triangles on one edge (0, 1), as at a curve where labels 1, 2 and
// 3 meet: no manifold, each triangle with its (behind, front) pair.
SurfaceMesh three_sheets() {
  SurfaceMesh m;
  m.points = {{0, 0, 0}, {0, 0, 1.25}, {1, 0, 0.5}, {-0.5, 0.75, 0.5}, {-0.5, -0.75, 0.5}};
  m.triangles = {{0, 1, 2}, {1, 0, 3}, {0, 1, 4}};
  m.interfaces = {{2, 1}, {3, 2}, {3, 1}};
  return m;
}
// Each triangle as its cycle of corners (shape's) with its pair: .msh 4.1
// writes nodes and triangles grouped by physical group.
std::multiset<std::pair<std::array<Corner, 3>, std::array<int, 2>>> labelled_shape(const SurfaceMesh& m) {
  std::multiset<std::pair<std::array<Corner, 3>, std::array<int, 2>>> s;
  for (std::size_t i = 0; i < m.triangles.size(); ++i) {
    SurfaceMesh one;
    one.points = m.points;
    one.triangles = {m.triangles[i]};
    s.insert({*shape(one).begin(), m.interfaces.at(i)});
  }
  return s;
}
} // namespace

TEST_CASE("label pairs round-trip through .vtp, .vtk, .ply and .msh, each triangle in its place") {
  SurfaceMesh m = three_sheets();
  SECTION("numbers") {}
  SECTION("names") { m.label_names = {{1, "grey matter"}, {3, "csf"}}; }
  struct Case {
    const char* ext;
    SurfaceWriteOptions options;
  };
  SurfaceWriteOptions ascii, msh22, msh_binary;
  ascii.ascii = true;
  msh22.msh_version = "2.2";
  msh_binary.msh_binary = true;
  for (const Case& c : {Case{".vtp", {}}, Case{".vtp", ascii}, Case{".vtk", {}}, Case{".vtk", ascii}, Case{".ply", {}},
                        Case{".ply", ascii}, Case{".msh", {}}, Case{".msh", msh22}, Case{".msh", msh_binary}}) {
    INFO(c.ext << (c.options.ascii ? " ascii" : "") << " msh " << c.options.msh_version << c.options.msh_binary);
    const std::string path = temp_dir() + "/pairs" + c.ext;
    write_surface(path, m, c.options);
    const SurfaceMesh back = read_surface(path);
    CHECK(labelled_shape(back) == labelled_shape(m));
    CHECK(back.labels.empty());
    if (std::string(c.ext) == ".msh") continue;
    CHECK(back.points == m.points);  // exact in floats too
    CHECK(back.triangles == m.triangles);
    CHECK(back.interfaces == m.interfaces);
  }
}

// A pair whose every vertex lies in another pair's node block (a small
// patch of a conforming mesh, its vertices all on curves): its $Entities
// box still holds its triangles (it was empty, written as inf).
TEST_CASE("a .msh 4.1 entity with no node of its own gets its triangles' box") {
  SurfaceMesh m;
  m.points = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  m.triangles = {{0, 2, 1}, {0, 1, 3}, {1, 2, 3}, {0, 3, 2}};
  m.interfaces = {{2, 0}, {1, 0}, {1, 0}, {1, 0}};  // (2, 0)'s vertices all in (1, 0)'s faces after it
  for (bool binary : {false, true}) {
    SurfaceWriteOptions o;
    o.msh_binary = binary;
    const std::string path = temp_dir() + "/shared.msh";
    write_surface(path, m, o);
    const SurfaceMesh back = read_surface(path);
    CHECK(labelled_shape(back) == labelled_shape(m));
    if (binary) continue;
    std::ifstream in(path);
    std::string line;
    while (std::getline(in, line) && line != "$Entities") {}
    std::getline(in, line);  // counts
    std::getline(in, line);  // entity 1: pair (1, 0) (pairs in increasing order)
    std::getline(in, line);  // entity 2: pair (2, 0), triangle {0, 2, 1}
    CHECK(line == "2 0 0 0 1 1 0 1 2 0");
  }
}

TEST_CASE("single labels read back from .vtp, .vtk and .msh; a .msh's groups named a|b are pairs") {
  SurfaceMesh m = three_sheets();
  m.interfaces.clear();
  for (const char* ext : {".vtp", ".vtk", ".msh"}) {
    // .msh: a physical group per component (one here), so one label.
    m.labels = std::string(ext) == ".msh" ? std::vector<int>{4, 4, 4} : std::vector<int>{4, 4, 9};
    const std::string path = temp_dir() + "/single" + ext;
    write_surface(path, m);
    const SurfaceMesh back = read_surface(path);
    std::vector<int> sorted = back.labels;
    std::sort(sorted.begin(), sorted.end());
    CHECK(sorted == m.labels);  // .msh: grouped
    CHECK(back.interfaces.empty());
  }
  // As Gmsh writes the file again: the physical names, no $LabelPairs.
  const std::string gmsh = temp_dir() + "/gmsh.msh";
  std::ofstream(gmsh) << "$MeshFormat\n4.1 0 8\n$EndMeshFormat\n$PhysicalNames\n2\n2 1 \"2|1\"\n2 2 \"3|2\"\n"
                         "$EndPhysicalNames\n$Entities\n0 0 2 0\n1 0 0 0 1 1 1 1 1 0\n2 0 0 0 1 1 1 1 2 0\n"
                         "$EndEntities\n$Nodes\n1 4 1 4\n2 1 0 4\n1\n2\n3\n4\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n$EndNodes\n"
                         "$Elements\n2 2 1 2\n2 1 2 1\n1 1 2 3\n2 2 2 1\n2 1 2 4\n$EndElements\n";
  const SurfaceMesh back = read_surface(gmsh);
  CHECK(back.interfaces == std::vector<std::array<int, 2>>{{2, 1}, {3, 2}});
  CHECK(back.triangles == std::vector<std::array<int, 3>>{{0, 1, 2}, {0, 1, 3}});
}

TEST_CASE("a legacy VTK 5.1 file (OFFSETS, CONNECTIVITY, METADATA) as VTK 9 writes it") {
  const std::string path = temp_dir() + "/v51.vtk";
  std::ofstream(path) << "# vtk DataFile Version 5.1\nvtk output\nASCII\nDATASET POLYDATA\nPOINTS 4 float\n"
                         "0 0 0 1 0 0 0 1 0\n0 0 1\nPOLYGONS 3 6\nOFFSETS vtktypeint64\n0 3 6\n"
                         "CONNECTIVITY vtktypeint64\n0 1 2 0 1 3\nCELL_DATA 2\nFIELD FieldData 1\nlabels 2 2 int\n"
                         "2 1 3 2\nMETADATA\nINFORMATION 0\n\n";
  const SurfaceMesh back = read_surface(path);
  CHECK(back.triangles == std::vector<std::array<int, 3>>{{0, 1, 2}, {0, 1, 3}});
  CHECK(back.interfaces == std::vector<std::array<int, 2>>{{2, 1}, {3, 2}});
  std::ofstream(path) << "# vtk DataFile Version 5.1\nvtk output\nASCII\nDATASET POLYDATA\nPOINTS 4 float\n"
                         "0 0 0 1 0 0 0 1 0\n0 0 1\nPOLYGONS 2 4\nOFFSETS vtktypeint64\n0 4\n"
                         "CONNECTIVITY vtktypeint64\n0 1 2 3\n";
  CHECK_THROWS_WITH(read_surface(path), Catch::Contains("only triangles"));
}

// A .vtp in the layouts VTK writes (values packed, zlib-compressed and
// base64-encoded by Python's struct, zlib, base64): points inline binary,
// connectivity and labels in base64 appended data (VTK's default), offsets
// ASCII followed by the InformationKey VTK writes after the values.
TEST_CASE("a .vtp of inline binary, base64 appended and ASCII arrays as VTK writes them") {
  const std::string path = temp_dir() + "/vtk.vtp";
  auto vtp = [&](const std::string& compressor) {
    std::ofstream(path)
        << "<?xml version=\"1.0\"?>\n<VTKFile type=\"PolyData\" version=\"0.1\" byte_order=\"LittleEndian\" "
           "header_type=\"UInt32\" compressor=\""
        << compressor
        << "\">\n  <PolyData>\n    <Piece NumberOfPoints=\"4\" NumberOfPolys=\"2\">\n      <CellData>\n"
           "        <DataArray type=\"Int32\" Name=\"labels\" NumberOfComponents=\"2\" format=\"appended\" offset=\"56\"/>\n"
           "      </CellData>\n      <Points>\n        <DataArray type=\"Float32\" Name=\"Points\" "
           "NumberOfComponents=\"3\" format=\"binary\">\n          AQAAAACAAAAwAAAAEAAAAA==eJxjYEAGDfYMBPgAJ70CPg==\n"
           "        </DataArray>\n      </Points>\n      <Polys>\n"
           "        <DataArray type=\"Int32\" Name=\"connectivity\" format=\"appended\" offset=\"0\"/>\n"
           "        <DataArray type=\"Int32\" Name=\"offsets\" format=\"ascii\">\n          3 6\n"
           "          <InformationKey name=\"L2_NORM_RANGE\" location=\"vtkDataArray\" length=\"2\">\n"
           "            <Value index=\"0\">\n              3\n            </Value>\n          </InformationKey>\n"
           "        </DataArray>\n      </Polys>\n    </Piece>\n  </PolyData>\n  <AppendedData encoding=\"base64\">\n"
           "   _AQAAAACAAAAYAAAAFgAAAA==eJxjYGBgYAJiRgYIANHMQAwAAGQACA==AQAAAACAAAAQAAAADgAAAA==eJxjZIAAJigNAAAwAAQ=\n"
           "  </AppendedData>\n</VTKFile>\n";
    return path;
  };
  const SurfaceMesh m = read_surface(vtp("vtkZLibDataCompressor"));
  CHECK(m.points == std::vector<std::array<double, 3>>{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}});
  CHECK(m.triangles == std::vector<std::array<int, 3>>{{0, 2, 1}, {0, 1, 3}});
  CHECK(m.interfaces == std::vector<std::array<int, 2>>{{1, 0}, {2, 0}});
  // Compressors we do not decode: refused naming the compressor.
  CHECK_THROWS_WITH(read_surface(vtp("vtkLZ4DataCompressor")), Catch::Contains("compressed by vtkLZ4DataCompressor"));
}
