#include "mesh/surface_io.hpp"
#include "util/error.hpp"

#include <catch2/catch.hpp>
#include <fstream>
#include <set>
#include <unistd.h>

using namespace imgmesh;

namespace {
std::string temp_dir() {
  static std::string dir = [] {
    char templ[] = "/tmp/imgmesh-mesh-XXXXXX";
    return std::string(mkdtemp(templ));
  }();
  return dir;
}
// A tetrahedron, outward oriented, with non-round coordinates.
SurfaceMesh tetra() {
  SurfaceMesh m;
  m.points = {{0.1, 0.2, 0.3}, {1.0 / 3, 0, 0}, {0, 1e-7, 2}, {-12.5, 7, 1}};
  m.triangles = {{0, 2, 1}, {0, 1, 3}, {1, 2, 3}, {0, 3, 2}};
  return m;
}
// Triangles as sets of point coordinates, independent of vertex numbering.
std::multiset<std::multiset<std::array<float, 3>>> shape(const SurfaceMesh& m) {
  std::multiset<std::multiset<std::array<float, 3>>> s;
  for (const auto& t : m.triangles) {
    std::multiset<std::array<float, 3>> tri;
    for (int v : t) {
      const auto& p = m.points[std::size_t(v)];
      tri.insert({float(p[0]), float(p[1]), float(p[2])});
    }
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
  CHECK_THROWS_AS(write_surface(temp_dir() + "/x.vtk", tetra()), UsageError);
}
