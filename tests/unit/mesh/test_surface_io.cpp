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
