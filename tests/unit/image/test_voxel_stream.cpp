// read_foreground_runs (VoxelStream: plain NRRD, NIfTI-1 and MetaImage
// voxels read without ITK's reader) against read_foreground (ITK's): the
// same voxels, box and geometry on every plain layout, and truncated or
// corrupt data refused with one line.
#include "image/io.hpp"
#include "image/voxel_stream.hpp"
#include "util/error.hpp"

#include "scratch_dir.hpp"

#include <catch2/catch.hpp>
#include <zlib.h>

#include <algorithm>
#include <cstdint>
#include <fstream>
#include <random>
#include <string>
#include <vector>

using namespace imgmesh;

namespace {

std::string dir() { return test::scratch_dir(); }

// Labels 0..6 in blobs and specks, some rows empty, label 300 once (16-bit
// files) and -2 (signed ones).
LabelImage labels() {
  Geometry g;
  g.size = {23, 17, 9};
  g.origin = {-12.5, 3.25, 7.0};
  g.spacing = {0.6, 0.7, 1.3};
  g.direction = {0, -1, 0, 1, 0, 0, 0, 0, 1};
  LabelImage img(g, 0);
  std::mt19937 rng(11);
  for (std::size_t z = 0; z < g.size[2]; ++z)
    for (std::size_t y = 0; y < g.size[1]; ++y)
      for (std::size_t x = 0; x < g.size[0]; ++x)
        if (y % 5 != 3) img(x, y, z) = rng() % 4 == 0 ? std::int32_t(rng() % 7) : std::int32_t((x / 6 + z / 3) % 4);
  return img;
}

std::string bytes_of(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
}

void put(const std::string& path, const std::string& bytes) { std::ofstream(path, std::ios::binary) << bytes; }

// The values as `bytes`-byte integers, big- or little-endian.
std::string packed(const LabelImage& img, int bytes, bool big) {
  std::string out;
  for (std::int32_t v : img.data)
    for (int i = 0; i < bytes; ++i) out += char((std::uint32_t(v) >> (8 * (big ? bytes - 1 - i : i))) & 0xff);
  return out;
}

std::string gzipped(const std::string& data) {
  z_stream z{};
  deflateInit2(&z, 6, Z_DEFLATED, 16 + MAX_WBITS, 8, Z_DEFAULT_STRATEGY);
  std::string out(deflateBound(&z, uLong(data.size())) + 64, '\0');
  z.next_in = reinterpret_cast<Bytef*>(const_cast<char*>(data.data()));
  z.avail_in = uInt(data.size());
  z.next_out = reinterpret_cast<Bytef*>(&out[0]);
  z.avail_out = uInt(out.size());
  deflate(&z, Z_FINISH);
  out.resize(z.total_out);
  deflateEnd(&z);
  return out;
}

// A NRRD written by hand: raw or gzip, either byte order, the sample's geometry.
std::string nrrd(const LabelImage& img, const char* type, int bytes, bool big, bool gzip) {
  const std::string header = std::string("NRRD0004\ntype: ") + type +
                             "\ndimension: 3\nspace: left-posterior-superior\nsizes: 23 17 9\n"
                             "space directions: (0,0.6,0) (-0.7,0,0) (0,0,1.3)\nkinds: domain domain domain\n"
                             "endian: " + (big ? "big" : "little") + "\nencoding: " + (gzip ? "gzip" : "raw") +
                             "\nspace origin: (-12.5,3.25,7)\n\n";
  const std::string data = packed(img, bytes, big);
  return header + (gzip ? gzipped(data) : data);
}

struct Case {
  std::string name;       // file name (its extension matters to ITK)
  std::string component;  // written by ITK in this type; empty: `bytes` is the file
  const LabelImage* image = nullptr;
  std::string bytes;
};

std::vector<Case> cases(const LabelImage& img) {
  static LabelImage wide, sign;
  wide = img;
  sign = img;
  wide.data[5] = 300;
  sign.data[7] = -2;
  const std::string mha = "ObjectType = Image\nNDims = 3\nBinaryData = True\nBinaryDataByteOrderMSB = False\n"
                          "Offset = -12.5 3.25 7\nTransformMatrix = 0 1 0 -1 0 0 0 0 1\nElementSpacing = 0.6 0.7 1.3\n"
                          "DimSize = 23 17 9\nElementType = MET_UCHAR\nElementDataFile = LOCAL\n";
  std::vector<Case> c = {
      {"itk.nii.gz", "unsigned_char", &img, ""}, {"itk16.nii.gz", "short", &sign, ""},
      {"itk.nii", "unsigned_short", &wide, ""},  {"itk.nrrd", "unsigned_char", &img, ""},
      {"itk32.nrrd", "int", &sign, ""},          {"itk.mha", "unsigned_char", &img, ""},
      {"itk16.mha", "short", &sign, ""},
      {"raw.nrrd", "", nullptr, nrrd(img, "uint8", 1, false, false)},
      {"raw16big.nrrd", "", nullptr, nrrd(wide, "uint16", 2, true, false)},
      {"gz16big.nrrd", "", nullptr, nrrd(sign, "int16", 2, true, true)},
      {"raw32.nrrd", "", nullptr, nrrd(sign, "int32", 4, false, false)},
      {"raw.mha", "", nullptr, mha + packed(img, 1, false)},
  };
  for (Case& k : c)
    if (k.image) {
      const std::string path = dir() + "/" + k.name;
      write_image(path, *k.image, k.component);
      k.bytes = bytes_of(path);
    }
  return c;
}

} // namespace

TEST_CASE("streamed label runs: the voxels, box and geometry of ITK's reader on every plain layout") {
  const LabelImage img = labels();
  for (const Case& k : cases(img)) {
    DYNAMIC_SECTION(k.name) {
      const std::string path = dir() + "/" + k.name;
      put(path, k.bytes);
      REQUIRE(plain_voxel_layout(path));
      for (const std::vector<long long>& want : {std::vector<long long>{2}, {1, 3}, {300}, {-2, 5}}) {
        Selection sel;
        sel.labels = want;
        BinaryImage itk;
        try {
          itk = read_foreground(path, sel);
        } catch (const Error&) {
          CHECK_THROWS_AS(read_foreground_runs(path, sel), Error);  // absent here: the same refusal
          continue;
        }
        const ForegroundRuns runs = read_foreground_runs(path, sel);
        INFO("labels " << want.front() << (want.size() > 1 ? "..." : ""));
        CHECK(runs.streamed());
        REQUIRE(runs.geometry().same_grid(itk.geometry()));
        CHECK(runs.image().data == itk.data);
        CHECK(runs.count() == std::size_t(std::count(itk.data.begin(), itk.data.end(), 1)));
        // The box, and rows asked for in parts.
        Index3 lo{1 << 20, 1 << 20, 1 << 20}, hi{-1, -1, -1};
        for (std::size_t z = 0; z < itk.size[2]; ++z)
          for (std::size_t y = 0; y < itk.size[1]; ++y) {
            std::vector<std::uint8_t> row(9);
            runs.row(y, z, 7, 9, row.data());
            CHECK(std::equal(row.begin(), row.end(), &itk(7, y, z)));
            for (std::size_t x = 0; x < itk.size[0]; ++x)
              if (itk(x, y, z))
                for (int a = 0; a < 3; ++a) {
                  const std::ptrdiff_t c = a == 0 ? std::ptrdiff_t(x) : a == 1 ? std::ptrdiff_t(y) : std::ptrdiff_t(z);
                  lo[a] = std::min(lo[a], c);
                  hi[a] = std::max(hi[a], c);
                }
          }
        CHECK(runs.lo() == lo);
        CHECK(runs.hi() == hi);
      }
    }
  }
}

TEST_CASE("streamed label runs: an absent label refused as ITK's reader refuses it; other layouts through ITK") {
  const LabelImage img = labels();
  const std::string path = dir() + "/absent.nrrd";
  put(path, nrrd(img, "uint8", 1, false, true));
  Selection sel;
  sel.labels = {2, 9};
  std::string itk;
  try {
    read_foreground(path, sel);
  } catch (const Error& e) {
    itk = e.what();
  }
  REQUIRE(itk.find("label 9 does not occur") != std::string::npos);
  CHECK_THROWS_WITH(read_foreground_runs(path, sel), itk);
  // ASCII data is not a plain layout: ITK reads it, the same voxels.
  std::string text = "NRRD0004\ntype: uint8\ndimension: 3\nsizes: 23 17 9\nencoding: ascii\n\n";
  for (std::int32_t v : img.data) text += std::to_string(v) + "\n";
  const std::string ascii = dir() + "/ascii.nrrd";
  put(ascii, text);
  CHECK_FALSE(plain_voxel_layout(ascii));
  sel.labels = {2};
  const ForegroundRuns runs = read_foreground_runs(ascii, sel);
  CHECK_FALSE(runs.streamed());
  CHECK(runs.image().data == read_foreground(ascii, sel).data);
}

TEST_CASE("streamed label runs: truncated or corrupt data refused with one line") {
  const LabelImage img = labels();
  Selection sel;
  sel.labels = {2};
  for (const Case& k : cases(img)) {
    DYNAMIC_SECTION(k.name) {
      // A few bytes short (fewer than the header: the size checks before
      // reading pass), then half the data gone.
      for (std::size_t cut : {std::size_t(7), k.bytes.size() / 2}) {
        const std::string path = dir() + "/cut-" + k.name;
        put(path, k.bytes.substr(0, k.bytes.size() - cut));
        std::string what, named;
        try {
          read_foreground_runs(path, sel);
        } catch (const Error& e) {
          what = e.what();
          named = e.path();
        }
        INFO("cut " << cut << ": " << what);
        CHECK(named == path);
        CHECK(what.find('\n') == std::string::npos);
        CHECK((what.find("truncated") != std::string::npos || what.find("can hold") != std::string::npos ||
               what.find("corrupt") != std::string::npos || what.find("holds fewer") != std::string::npos));
      }
    }
  }
  // Compressed data with a byte changed inside.
  std::string bad = nrrd(img, "uint8", 1, false, true);
  bad[bad.size() / 2] = char(bad[bad.size() / 2] ^ 0x5a);
  bad[bad.size() / 2 + 1] = char(bad[bad.size() / 2 + 1] ^ 0xa5);
  const std::string path = dir() + "/corrupt.nrrd";
  put(path, bad);
  CHECK_THROWS_AS(read_foreground_runs(path, sel), Error);
}
