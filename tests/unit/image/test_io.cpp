#include "image/io.hpp"
#include "util/error.hpp"

#include "scratch_dir.hpp"

#include <catch2/catch.hpp>
#include <cstdio>
#include <algorithm>
#include <fstream>
#include <random>
#include <string>
#include <unistd.h>

using namespace imgmesh;

namespace {
std::string temp_dir() { return test::scratch_dir(); }

BinaryImage sample(int dimension) {
  Geometry g;
  g.dimension = dimension;
  g.size = {7, 5, dimension == 2 ? 1u : 4u};
  g.origin = {-12.5, 3.25, dimension == 2 ? 0.0 : 7.0};  // 2D files have no z
  g.spacing = {0.6, 0.7, dimension == 2 ? 1.0 : 1.3};
  if (dimension == 3) g.direction = {0, -1, 0, 1, 0, 0, 0, 0, 1};
  BinaryImage img(g, 0);
  std::mt19937 rng(7);
  for (auto& v : img.data) v = rng() % 3 == 0;
  img.data[3] = 1;
  return img;
}

void same(const BinaryImage& a, const BinaryImage& b) {
  REQUIRE(a.size == b.size);
  CHECK(a.dimension == b.dimension);
  for (int i = 0; i < 3; ++i) {
    CHECK(a.origin[i] == Approx(b.origin[i]).margin(1e-6));
    CHECK(a.spacing[i] == Approx(b.spacing[i]).margin(1e-6));
  }
  for (int i = 0; i < 9; ++i) CHECK(a.direction[i] == Approx(b.direction[i]).margin(1e-6));
  CHECK(a.data == b.data);
}
} // namespace

TEST_CASE("3D images keep voxels and world geometry through every format") {
  const BinaryImage img = sample(3);
  for (const char* ext : {".nrrd", ".mha", ".nii.gz", ".nii"}) {
    DYNAMIC_SECTION(ext) {
      const std::string path = temp_dir() + "/img" + ext;
      write_image(path, img);
      same(read_foreground(path, {}), img);
      const ImageInfo info = read_image_info(path);
      CHECK(info.integer);
      CHECK(info.geometry.dimension == 3);
    }
  }
}

TEST_CASE("2D images keep voxels and geometry (NRRD and PNG)") {
  const BinaryImage img = sample(2);
  for (const char* ext : {".nrrd", ".png"}) {
    DYNAMIC_SECTION(ext) {
      const std::string path = temp_dir() + "/img2" + ext;
      write_image(path, img);
      BinaryImage back = read_foreground(path, {});
      REQUIRE(back.dimension == 2);
      CHECK(back.data == img.data);
      if (std::string(ext) == ".nrrd") same(back, img);
    }
  }
}

TEST_CASE("float images carry NRRD key/value fields") {
  Geometry g;
  g.size = {3, 3, 3};
  g.spacing = {1, 2, 3};
  FloatImage f(g, -1.5f);
  f(1, 2, 0) = 4.25f;
  const std::string path = temp_dir() + "/f.nrrd";
  write_image(path, f, {{"imgmesh_kind", "test"}, {"imgmesh_d", "0.1 0.2 0.3"}});
  std::map<std::string, std::string> fields;
  FloatImage back = read_float(path, &fields);
  CHECK(back.data == f.data);
  CHECK(fields["imgmesh_kind"] == "test");
  CHECK(fields["imgmesh_d"] == "0.1 0.2 0.3");
}

TEST_CASE("labels and thresholds select the foreground") {
  Geometry g;
  g.size = {4, 1, 1};
  FloatImage f(g);
  f.data = {0.f, 1.f, 2.f, 3.f};
  const std::string fpath = temp_dir() + "/grey.nrrd";
  write_image(fpath, f);
  Selection thr;
  thr.has_threshold = true;
  thr.threshold = 2;
  CHECK(read_foreground(fpath, thr).data == std::vector<std::uint8_t>{0, 0, 1, 1});
  Selection lab;
  lab.labels = {1};
  CHECK_THROWS_AS(read_foreground(fpath, lab), UsageError);  // float image with --label

  BinaryImage b(g);
  b.data = {0, 1, 1, 0};
  const std::string bpath = temp_dir() + "/b.nrrd";
  write_image(bpath, b);
  CHECK(read_foreground(bpath, lab).data == std::vector<std::uint8_t>{0, 1, 1, 0});
  Selection absent;
  absent.labels = {5};
  CHECK_THROWS_WITH(read_foreground(bpath, absent), Catch::Contains("label 5"));
  Selection none;
  none.has_threshold = true;
  none.threshold = 10;
  CHECK_THROWS_WITH(read_foreground(bpath, none), Catch::Contains("empty"));
}

TEST_CASE("bad files give an Error, never a crash") {
  const BinaryImage img = sample(3);
  const std::string good = temp_dir() + "/good.nrrd";
  write_image(good, img);
  std::ifstream in(good, std::ios::binary);
  std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  const std::string cut = temp_dir() + "/cut.nrrd";
  std::ofstream(cut, std::ios::binary) << bytes.substr(0, bytes.size() / 2);
  CHECK_THROWS_AS(read_foreground(cut, {}), Error);
  // ITK's NIfTI reader zero-fills a truncated file; we must refuse it.
  for (const char* ext : {".nii.gz", ".nii"}) {
    const std::string whole = temp_dir() + "/whole" + ext;
    write_image(whole, img);
    std::ifstream nin(whole, std::ios::binary);
    std::string nbytes((std::istreambuf_iterator<char>(nin)), std::istreambuf_iterator<char>());
    const std::string part = temp_dir() + "/part" + ext;
    std::ofstream(part, std::ios::binary) << nbytes.substr(0, nbytes.size() - 20);
    CHECK_THROWS_WITH(read_foreground(part, {}), Catch::Contains("truncated"));
  }
  const std::string junk = temp_dir() + "/junk.nrrd";
  std::ofstream(junk) << "this is not an image\n";
  CHECK_THROWS_AS(read_foreground(junk, {}), Error);
  CHECK_THROWS_AS(read_foreground(temp_dir() + "/missing.nrrd", {}), Error);
  CHECK_THROWS_AS(write_image(temp_dir() + "/x.jpg", img), UsageError);
  // A failed write leaves no file.
  CHECK(access((temp_dir() + "/x.jpg").c_str(), F_OK) != 0);
}

TEST_CASE("label images read narrow: the narrowest of 1, 2, 4 bytes their values fit, the same values") {
  const BinaryImage base = sample(3);
  // Values and the component type written: 1 byte for 0..255 whatever the
  // file's type, 2 for 0..65535, 4 beyond or negative.
  const struct {
    std::int32_t top, bottom;
    const char* component;
    int bytes;
  } cases[] = {{255, 0, "int", 1}, {200, 0, "unsigned_char", 1}, {256, 0, "short", 2}, {65535, 0, "unsigned_short", 2},
               {65536, 0, "int", 4}, {7, -1, "short", 4}, {1000, 0, "float", 2}};
  for (const auto& k : cases) {
    LabelImage img(base.geometry(), 0);
    std::mt19937 rng(3);
    for (std::size_t i = 0; i < img.data.size(); ++i)
      img.data[i] = base.data[i] ? std::int32_t(rng() % std::uint32_t(k.top)) : k.bottom;
    img.data[0] = k.top;
    const std::string path = temp_dir() + "/narrow.nrrd";
    write_image(path, img, k.component);
    INFO(k.component << " up to " << k.top);
    const NarrowLabelImage n = read_labels_narrow(path);
    REQUIRE(n.bytes == k.bytes);
    const LabelImage wide = read_labels(path);
    n.visit([&](const auto& narrow) {
      REQUIRE(narrow.same_grid(wide));
      REQUIRE(std::equal(narrow.data.begin(), narrow.data.end(), wide.data.begin(), wide.data.end()));
      return 0;
    });
  }
  const std::string path = temp_dir() + "/half.nrrd";
  FloatImage f(base.geometry(), 0.5f);
  write_image(path, f);
  CHECK_THROWS_WITH(read_labels_narrow(path), Catch::Contains("not a 32-bit integer"));
}
