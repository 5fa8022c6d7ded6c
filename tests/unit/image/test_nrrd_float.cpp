// The implicit function file's reader without ITK against ITK's own: the
// same samples and the same geometry to the last bit (meshes depend on it).
#include "image/io.hpp"
#include "image/nrrd_float.hpp"
#include "image/sample_grid.hpp"
#include "util/error.hpp"

#include "scratch_dir.hpp"

#include <catch2/catch.hpp>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <iterator>
#include <random>
#include <sstream>
#include <streambuf>
#include <string>
#include <unistd.h>
#include <vector>

using namespace imgmesh;

namespace {
std::string temp_path(const std::string& name) { return test::scratch_dir() + "/" + name; }

FloatImage read_without_itk(const std::string& path, std::map<std::string, std::string>* keys = nullptr) {
  std::ifstream in(path, std::ios::binary);
  const NrrdHeader h = read_nrrd_header(in, path);
  if (keys) *keys = h.keys;
  return read_nrrd_float_samples(h, in, path);
}

// Bit for bit: == on doubles would pass -0 for 0.
template <class A> bool same_bits(const A& a, const A& b) { return std::memcmp(&a, &b, sizeof a) == 0; }

void same_as_itk(const std::string& path) {
  std::map<std::string, std::string> keys, itk_keys;
  const FloatImage mine = read_without_itk(path, &keys), itk = read_float(path, &itk_keys);
  CHECK(mine.size == itk.size);
  CHECK(same_bits(mine.spacing, itk.spacing));
  CHECK(same_bits(mine.origin, itk.origin));
  CHECK(same_bits(mine.direction, itk.direction));
  REQUIRE(mine.data.size() == itk.data.size());
  CHECK(std::memcmp(mine.data.data(), itk.data.data(), mine.data.size() * sizeof(float)) == 0);
  // ITK adds its own entries (NRRD_kinds, ...): the file's key:=value pairs
  // are what must agree.
  for (const auto& [k, v] : keys) CHECK(itk_keys[k] == v);
  for (const auto& [k, v] : itk_keys)
    if (k.rfind("imgmesh_", 0) == 0) CHECK(keys.count(k) == 1);
}
} // namespace

TEST_CASE("a float NRRD written by ITK reads as ITK reads it, rotated and anisotropic") {
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> u(-1, 1);
  for (int trial = 0; trial < 20; ++trial) {
    Geometry g;
    g.size = {5 + rng() % 4, 3 + rng() % 5, 4 + rng() % 3};
    g.spacing = {0.3 + 2 * std::abs(u(rng)), 0.01 + std::abs(u(rng)), 1.0 / 3 + std::abs(u(rng))};
    g.origin = {100 * u(rng), 100 * u(rng), 100 * u(rng)};
    // A random rotation (Gram-Schmidt): columns of unit length whose norms
    // and quotients round differently from axis-aligned ones.
    Vec3 a{u(rng), u(rng), u(rng)}, b{u(rng), u(rng), u(rng)};
    auto unit = [](Vec3 v) {
      const double n = std::sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
      return Vec3{v[0] / n, v[1] / n, v[2] / n};
    };
    a = unit(a);
    const double ab = a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
    b = unit({b[0] - ab * a[0], b[1] - ab * a[1], b[2] - ab * a[2]});
    const Vec3 c{a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
    for (int r = 0; r < 3; ++r) g.direction[r * 3 + 0] = a[r], g.direction[r * 3 + 1] = b[r], g.direction[r * 3 + 2] = c[r];
    FloatImage f(g);
    for (float& v : f.data) v = float(u(rng) * 10);
    const std::string path = temp_path("rotated.nrrd");
    write_image(path, f, {{"imgmesh_kind", "pu-implicit"}, {"imgmesh_d", "0.5 0.25 0.125"}});
    same_as_itk(path);
  }
}

TEST_CASE("raw, big-endian, RAS and spacings headers read as ITK reads them") {
  const float values[8] = {1.5f, -2.25f, 3.0f, -0.125f, 7.0f, 1e-7f, -1e7f, 0.0f};
  auto write = [&](const std::string& name, const std::string& header, bool big) {
    std::ofstream out(temp_path(name), std::ios::binary);
    out << header << "\n";
    for (float v : values) {
      unsigned char b[4];
      std::memcpy(b, &v, 4);
      if (big) std::swap(b[0], b[3]), std::swap(b[1], b[2]);
      out.write(reinterpret_cast<const char*>(b), 4);
    }
    return temp_path(name);
  };
  const std::string head = "NRRD0004\ntype: float\ndimension: 3\nsizes: 2 2 2\nencoding: raw\n";
  const std::string little = head + "endian: little\n";
  same_as_itk(write("lps.nrrd", little + "space: left-posterior-superior\nspace directions: (0.3,0.1,0) (0,0.7,0) (0,0,1.1)\nspace origin: (1,-2,3.5)\n", false));
  same_as_itk(write("ras.nrrd", little + "space: right-anterior-superior\nspace directions: (0.3,0.1,0) (0,0.7,0) (0,0,1.1)\nspace origin: (1,-2,3.5)\n", false));
  same_as_itk(write("big.nrrd", head + "endian: big\nspacings: 0.5 2 3\n", true));
  same_as_itk(write("plain.nrrd", little + "# a comment\nimgmesh_d:=1 2 3\n", false));
}

TEST_CASE("bad float NRRDs are refused with one line naming the file") {
  auto refused = [](const std::string& name, const std::string& bytes, const std::string& reason) {
    const std::string path = temp_path(name);
    {
      std::ofstream out(path, std::ios::binary);
      out << bytes;
    }
    try {
      read_without_itk(path);
      FAIL("accepted " << name);
    } catch (const Error& e) {
      const std::string what = e.what();
      INFO(name << ": " << what);
      CHECK(what.find(reason) != std::string::npos);
      CHECK(e.path() == path);
      CHECK(what.find('\n') == std::string::npos);
    }
  };
  const std::string head = "NRRD0004\ntype: float\ndimension: 3\nsizes: 2 2 2\nendian: little\n";
  refused("no-endian.nrrd", "NRRD0004\ntype: float\ndimension: 3\nsizes: 2 2 2\nencoding: raw\n\n" + std::string(32, '\0'), "endian ''");
  refused("empty.nrrd", "", "not a NRRD file");
  refused("png.nrrd", "\x89PNG\r\n\x1a\n", "not a NRRD file");
  refused("endless.nrrd", head + "encoding: raw\n", "no end");
  refused("binary.nrrd", head + "encoding: raw\n\x01\x02\n\n", "bad NRRD header line '?\?'");
  refused("double.nrrd", "NRRD0004\ntype: double\ndimension: 3\nsizes: 2 2 2\nencoding: raw\n\n", "type 'double'");
  refused("2d.nrrd", "NRRD0004\ntype: float\ndimension: 2\nsizes: 2 2\nencoding: raw\n\n", "dimension '2'");
  refused("zero.nrrd", "NRRD0004\ntype: float\ndimension: 3\nsizes: 2 0 2\nencoding: raw\n\n", "size is zero");
  refused("short.nrrd", head + "encoding: raw\n\n" + std::string(31, '\0'), "more than the 31 bytes");
  refused("huge.nrrd", "NRRD0004\ntype: float\ndimension: 3\nsizes: 4096 4096 4096\nendian: little\nencoding: gzip\n\n" + std::string(100, '\0'),
          "more than the 100 compressed bytes");
  refused("corrupt.nrrd", head + "encoding: gzip\n\n" + std::string("\x1f\x8b\x08\x00\xff\xff\xff\xff\xff\xff", 10) + std::string(40, '\xff'),
          "corrupt gzip data");
  refused("ascii.nrrd", head + "encoding: ascii\n\n1 2 3 4 5 6 7 8\n", "encoding 'ascii'");
  refused("detached.nrrd", head + "encoding: raw\ndata file: other.raw\n\n", "'data file' is not supported");
  refused("space.nrrd", head + "encoding: raw\nspace: scanner-xyz\nspace directions: (1,0,0) (0,1,0) (0,0,1)\n\n" + std::string(32, '\0'),
          "space 'scanner-xyz'");
  refused("flat.nrrd", head + "encoding: raw\nspace: LPS\nspace directions: (1,0,0) (0,0,0) (0,0,1)\n\n" + std::string(32, '\0'),
          "spacing must be positive");
  refused("mins.nrrd", head + "encoding: raw\naxis mins: 5 5 5\n\n" + std::string(32, '\0'), "origin without space directions");
  refused("origin.nrrd", head + "encoding: raw\nspace origin: (5,5,5)\n\n" + std::string(32, '\0'), "origin without space directions");
}

TEST_CASE("truncated gzip samples are refused, the count said") {
  Geometry g;
  g.size = {16, 16, 16};
  FloatImage f(g);
  std::mt19937 rng(5);
  for (float& v : f.data) v = float(rng() % 1000) / 7.f;
  const std::string path = temp_path("whole.nrrd");
  write_image(path, f);
  std::string bytes;
  {
    std::ifstream in(path, std::ios::binary);
    bytes.assign(std::istreambuf_iterator<char>(in), {});
  }
  REQUIRE(bytes.find("encoding: gzip") != std::string::npos);
  {
    std::ofstream out(path, std::ios::binary | std::ios::trunc);
    out.write(bytes.data(), std::streamsize(bytes.size() - 200));
  }
  REQUIRE_THROWS_WITH(read_without_itk(path), Catch::Contains("truncated gzip data (expected 16384 bytes but received"));
}

namespace {
// A stream that cannot seek (a pipe).
struct PipeBuf : std::streambuf {
  explicit PipeBuf(const std::string& s) : data(s) { setg(data.data(), data.data(), data.data() + data.size()); }
  std::string data;
};
} // namespace

TEST_CASE("samples stream in any chunks, from a pipe too, as they read whole") {
  Geometry g;
  g.size = {13, 9, 7};
  g.spacing = {0.5, 0.25, 2};
  FloatImage f(g);
  std::mt19937 rng(8);
  for (float& v : f.data) v = float(int(rng() % 2001) - 1000) / 8.f;
  for (bool raw : {false, true}) {
    const std::string path = temp_path(raw ? "stream-raw.nrrd" : "stream-gz.nrrd");
    write_image(path, f);
    std::string bytes;
    {
      std::ifstream in(path, std::ios::binary);
      bytes.assign(std::istreambuf_iterator<char>(in), {});
    }
    if (raw) {  // ITK compresses: a raw copy of the same samples
      const std::size_t body = bytes.find("\n\n") + 2;
      std::string head = bytes.substr(0, body);
      head.replace(head.find("encoding: gzip"), 14, "encoding: raw");
      bytes = head + std::string(reinterpret_cast<const char*>(f.data.data()), f.data.size() * sizeof(float));
    }
    PipeBuf buf(bytes);
    std::istream pipe(&buf);
    REQUIRE(pipe.tellg() == std::streampos(-1));
    const NrrdHeader h = read_nrrd_header(pipe, path);
    NrrdFloatStream s(h, pipe, path);
    CHECK(s.geometry().size == g.size);
    std::vector<float> got(f.data.size());
    for (std::size_t at = 0, n = 1; at < got.size(); n = 3 * n + 1) {  // chunks of 1, 4, 13... samples
      const std::size_t k = std::min(n, got.size() - at);
      s.read(got.data() + at, k);
      at += k;
    }
    CHECK(got == f.data);
    CHECK_THROWS_AS(s.read(got.data(), 1), Error);  // beyond what the header declares
  }
}

TEST_CASE("samples streamed into SampleGrid's blocks are those of the file read whole, raw and gzip", "[samples]") {
  // Odd sizes: the last blocks of each axis partly outside the grid. g
  // crosses zero inside, near the clamp T and beyond it on both sides.
  Geometry g;
  g.size = {13, 10, 7};
  g.spacing = {0.5, 0.25, 2};
  FloatImage f(g);
  std::mt19937 rng(11);
  for (std::size_t z = 0; z < 7; ++z)
    for (std::size_t y = 0; y < 10; ++y)
      for (std::size_t x = 0; x < 13; ++x)
        f(x, y, z) = float(std::hypot((double(x) - 6.2) * 0.5, (double(y) - 4.6) * 0.25, (double(z) - 3.1) * 2) - 2.0 +
                           double(rng() % 100) * 1e-4);
  const float t = 1.5f;
  for (bool raw : {false, true}) {
    const std::string path = temp_path(raw ? "blocks-raw.nrrd" : "blocks-gz.nrrd");
    write_image(path, f);
    if (raw) {  // ITK compresses: a raw copy of the same samples
      std::string bytes;
      {
        std::ifstream in(path, std::ios::binary);
        bytes.assign(std::istreambuf_iterator<char>(in), {});
      }
      std::string head = bytes.substr(0, bytes.find("\n\n") + 2);
      head.replace(head.find("encoding: gzip"), 14, "encoding: raw");
      std::ofstream out(path, std::ios::binary | std::ios::trunc);
      out << head;
      out.write(reinterpret_cast<const char*>(f.data.data()), std::streamsize(f.data.size() * sizeof(float)));
    }
    const FloatImage whole = read_without_itk(path);
    REQUIRE(whole.data == f.data);
    std::ifstream in(path, std::ios::binary);
    const NrrdHeader h = read_nrrd_header(in, path);
    NrrdFloatStream s(h, in, path);
    const std::size_t slice = g.size[0] * g.size[1];
    const SampleGrid streamed(s.geometry(), {0, 0, 0}, g.size, t, SampleGrid::Storage::blocks,
                              [&](float* out) { s.read(out, slice); });
    const SampleGrid dense(whole, t, SampleGrid::Storage::blocks);
    REQUIRE(!streamed.dense());
    CHECK(streamed.stored_blocks() == dense.stored_blocks());
    CHECK(streamed.stored_blocks() < streamed.blocks());  // some blocks clamp whole
    for (std::size_t z = 0; z < 7; ++z)
      for (std::size_t y = 0; y < 10; ++y)
        for (std::size_t x = 0; x < 13; ++x) {
          REQUIRE(streamed(x, y, z) == std::clamp(f(x, y, z), -t, t));
          REQUIRE(streamed(x, y, z) == dense(x, y, z));
        }
  }
}
