// The pu-implicit file: round trip and rejection of anything else.
#include "helpers.hpp"
#include "image/io.hpp"
#include "implicit/implicit_file.hpp"
#include "util/error.hpp"

#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <random>
#include <string>
#include <unistd.h>

using namespace imgmesh;
using namespace imgmesh::test;

namespace {
std::string temp_path(const std::string& name) {
  return "imgmesh_test_implicit_" + std::to_string(::getpid()) + "_" + name;
}
} // namespace

TEST_CASE("write_implicit / read_implicit round trip keeps g, d and the world geometry", "[file]") {
  BinaryImage im = random_wc(10, 9, 11, 7, {0.7, 1.0, 1.3});
  rotate(im);
  const PartitionOfUnity f = implicit_from_well_composed(im);
  const std::string path = temp_path("rt.nrrd");
  write_implicit(path, f);
  const PartitionOfUnity h = read_implicit(path);
  std::remove(path.c_str());
  const Geometry &a = h.samples(), &b = f.samples();
  REQUIRE(a.size == b.size);
  for (int i = 0; i < 3; ++i) {
    REQUIRE(a.spacing[i] == Approx(b.spacing[i]).epsilon(1e-12));
    REQUIRE(a.origin[i] == Approx(b.origin[i]).epsilon(1e-12).margin(1e-12));
  }
  for (int i = 0; i < 9; ++i) REQUIRE(a.direction[i] == Approx(b.direction[i]).margin(1e-12));
  REQUIRE(h.samples().to_image().data == f.samples().to_image().data);
  for (int i = 0; i < 3; ++i) REQUIRE(h.d()[i] == f.d()[i]);  // %.17g: exact
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(0, 1);
  const Geometry& g = f.samples();
  for (int i = 0; i < 1000; ++i) {
    const Vec3 p = g.world(u(rng) * (g.size[0] - 1), u(rng) * (g.size[1] - 1), u(rng) * (g.size[2] - 1));
    REQUIRE(h.value(p) == Approx(f.value(p)).epsilon(1e-9).margin(1e-9));  // world geometry travels through NRRD text
  }
}

TEST_CASE("A file clamped at covered_clamp gives the meshers the samples of the whole g", "[file]") {
  // A foreground far enough from the grid's sides that many samples clamp.
  BinaryImage im = random_wc(24, 22, 20, 5, {0.7, 1.0, 1.3});
  rotate(im);
  const PartitionOfUnity f = implicit_from_well_composed(im);
  const float t = covered_clamp(f.samples());
  const std::string whole = temp_path("whole.nrrd"), band = temp_path("band.nrrd");
  write_implicit(whole, f);
  write_implicit(band, f, {}, t);
  // The file holds g clamped to [-T, T], and says so.
  std::map<std::string, std::string> fields;
  const std::vector<float> gb = read_float(band, &fields).data, &gf = f.samples().to_image().data;
  REQUIRE(std::stof(fields.at("imgmesh_clamp")) == t);
  REQUIRE(read_implicit(band).samples().clamp() == t);
  std::size_t clamped = 0;
  for (std::size_t i = 0; i < gf.size(); ++i) {
    REQUIRE(gb[i] == std::max(-t, std::min(gf[i], t)));
    clamped += std::abs(gf[i]) > t;
  }
  REQUIRE(clamped > gf.size() / 4);
  // A mesher at a --max-distance under the covered one (0.3 world units
  // against 0.5 voxel = 0.35) holds the same samples from either file.
  const auto at = [](double e) {
    return [e](const Geometry& grid) { return PartitionOfUnity::clamp_for(grid, e); };
  };
  REQUIRE(read_implicit(band, at(0.3)).samples().to_image().data ==
          read_implicit(whole, at(0.3)).samples().to_image().data);
  // At a larger one it gets the file's clamp: the same signs, and f itself
  // (as read from the whole file: the geometry went through text) wherever
  // |f| <= 2 E of the covered E (clamp_for's argument).
  const PartitionOfUnity wide = read_implicit(band, at(3.0)), exact = read_implicit(whole);
  REQUIRE(wide.samples().clamp() == t);
  std::remove(whole.c_str());
  std::remove(band.c_str());
  const double e = kCoveredMaxDistance * 0.7;
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> u(0, 1);
  const Geometry& g = exact.samples();
  std::size_t near = 0;
  for (int i = 0; i < 4000; ++i) {
    const Vec3 p = g.world(u(rng) * (g.size[0] - 1), u(rng) * (g.size[1] - 1), u(rng) * (g.size[2] - 1));
    const double v = exact.value(p), w = wide.value(p);
    REQUIRE((v < 0) == (w < 0));
    REQUIRE((std::abs(v) <= 2 * e) == (std::abs(w) <= 2 * e));
    if (std::abs(v) <= 2 * e) {
      REQUIRE(w == v);
      ++near;
    }
  }
  REQUIRE(near > 100);
}

TEST_CASE("read_implicit rejects other files", "[file]") {
  FloatImage g(grid(5, 5, 5), 1.0f);
  g(2, 2, 2) = -0.5f;
  SECTION("a float image without the fields") {
    const std::string path = temp_path("plain.nrrd");
    write_image(path, g);
    REQUIRE_THROWS_AS(read_implicit(path), Error);
    std::remove(path.c_str());
  }
  SECTION("wrong kind, version or d") {
    const std::string path = temp_path("bad.nrrd");
    for (auto fields : std::vector<std::map<std::string, std::string>>{
             {{"imgmesh_kind", "other"}, {"imgmesh_version", "1"}, {"imgmesh_d", "0.1 0.1 0.1"}},
             {{"imgmesh_kind", "pu-implicit"}, {"imgmesh_version", "7"}, {"imgmesh_d", "0.1 0.1 0.1"}},
             {{"imgmesh_kind", "pu-implicit"}, {"imgmesh_version", "1"}, {"imgmesh_d", "0.1 0.1"}},
             {{"imgmesh_kind", "pu-implicit"}, {"imgmesh_version", "1"}, {"imgmesh_d", "0.1 nan 0.1"}},
             {{"imgmesh_kind", "pu-implicit"}, {"imgmesh_version", "1"}, {"imgmesh_d", "0.5 0.5 0.5"}},
             {{"imgmesh_kind", "pu-implicit"}, {"imgmesh_version", "1"}},
             // a clamp under the stencil's diameter 2 |spacing| = 3.46, or not one number
             {{"imgmesh_kind", "pu-implicit"}, {"imgmesh_version", "1"}, {"imgmesh_d", "0.04 0.04 0.04"}, {"imgmesh_clamp", "3"}},
             {{"imgmesh_kind", "pu-implicit"}, {"imgmesh_version", "1"}, {"imgmesh_d", "0.04 0.04 0.04"}, {"imgmesh_clamp", "nan"}},
             {{"imgmesh_kind", "pu-implicit"}, {"imgmesh_version", "1"}, {"imgmesh_d", "0.04 0.04 0.04"}, {"imgmesh_clamp", "4 5"}}}) {
      write_image(path, g, fields);
      REQUIRE_THROWS_AS(read_implicit(path), Error);
    }
    write_image(path, g, {{"imgmesh_kind", "pu-implicit"}, {"imgmesh_version", "1"}, {"imgmesh_d", "0.04 0.04 0.04"},
                          {"imgmesh_clamp", "4"}});
    REQUIRE(read_implicit(path).samples().clamp() == 4.0f);
    std::remove(path.c_str());
  }
  SECTION("a truncated file") {
    const std::string path = temp_path("trunc.nrrd");
    BinaryImage im = random_wc(10, 10, 10, 2);
    write_implicit(path, implicit_from_well_composed(im));
    std::string bytes;
    {
      std::ifstream in(path, std::ios::binary);
      bytes.assign(std::istreambuf_iterator<char>(in), {});
    }
    {
      std::ofstream out(path, std::ios::binary | std::ios::trunc);
      out.write(bytes.data(), std::streamsize(bytes.size() / 2));
    }
    REQUIRE_THROWS_AS(read_implicit(path), Error);
    std::remove(path.c_str());
  }
  SECTION("a missing file") { REQUIRE_THROWS_AS(read_implicit(temp_path("nonexistent.nrrd")), Error); }
}
