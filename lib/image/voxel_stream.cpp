#include "image/voxel_stream.hpp"

#include "image/nrrd_float.hpp"
#include "util/error.hpp"

#include <zlib.h>

#include <algorithm>
#include <cerrno>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <map>
#include <sstream>
#include <vector>

namespace imgmesh {
namespace {

// The product of the numbers of `text` (n of them when n > 0), 0 when one
// is not a positive whole number or the product passes 2^40.
std::size_t product(const std::string& text, std::size_t n = 0) {
  std::istringstream in(text);
  std::size_t p = 1, k = 0;
  for (long long v; in >> v; ++k) {
    if (v <= 0 || p > (std::size_t(1) << 40) / std::size_t(v)) return 0;
    p *= std::size_t(v);
  }
  if (!in.eof() || k == 0 || (n && k != n)) return 0;
  return p;
}

std::optional<VoxelLayout> nrrd_layout(const std::string& file) {
  std::ifstream in(file, std::ios::binary);
  NrrdHeader h;
  try {
    h = read_nrrd_header(in, file);
  } catch (const Error&) {
    return std::nullopt;
  }
  auto field = [&](const char* name) {
    const auto it = h.fields.find(name);
    return it == h.fields.end() ? std::string() : it->second;
  };
  for (const char* other : {"data file", "datafile", "line skip", "lineskip", "byte skip", "byteskip"})
    if (h.fields.count(other)) return std::nullopt;
  static const std::map<std::string, int> types = {
      {"signed char", 1}, {"int8", 1}, {"int8_t", 1}, {"uchar", 1}, {"unsigned char", 1}, {"uint8", 1},
      {"uint8_t", 1}, {"short", 2}, {"short int", 2}, {"signed short", 2}, {"signed short int", 2},
      {"int16", 2}, {"int16_t", 2}, {"ushort", 2}, {"unsigned short", 2}, {"unsigned short int", 2},
      {"uint16", 2}, {"uint16_t", 2}, {"int", 4}, {"signed int", 4}, {"int32", 4}, {"int32_t", 4},
      {"uint", 4}, {"unsigned int", 4}, {"uint32", 4}, {"uint32_t", 4}};
  const auto type = types.find(field("type"));
  const std::string encoding = field("encoding"), endian = field("endian");
  VoxelLayout l;
  l.deflate = encoding == "gzip" || encoding == "gz";
  if (type == types.end() || (encoding != "raw" && !l.deflate)) return std::nullopt;
  l.bytes = type->second;
  if (l.bytes > 1 && endian != "little" && endian != "big") return std::nullopt;
  l.big_endian = l.bytes > 1 && endian == "big";
  const std::streampos at = in.tellg();
  if (!in || at < 0) return std::nullopt;
  l.offset = std::size_t(at);
  l.values = product(field("sizes"));
  if (!l.values) return std::nullopt;
  return l;
}

// NIfTI-1 in one file ("n+1"), its integer types, no scaling (ITK reads
// scaled data as float).
std::optional<VoxelLayout> nifti_layout(const std::string& file, bool gzip) {
  unsigned char h[348];
  gzFile gz = gzopen(file.c_str(), "rb");  // reads plain files too
  if (!gz) return std::nullopt;
  const int got = gzread(gz, h, sizeof h);
  gzclose(gz);
  if (got != int(sizeof h) || std::memcmp(h + 344, "n+1", 4) != 0) return std::nullopt;
  bool big;  // by sizeof_hdr, 348
  if (h[0] == 92 && h[1] == 1 && h[2] == 0 && h[3] == 0) big = false;
  else if (h[3] == 92 && h[2] == 1 && h[1] == 0 && h[0] == 0) big = true;
  else return std::nullopt;
  const std::uint16_t probe = 1;
  const bool swap = big == (*reinterpret_cast<const unsigned char*>(&probe) == 1);
  auto raw = [&](int at, int n, void* out) {
    unsigned char b[4];
    for (int i = 0; i < n; ++i) b[i] = h[at + (swap ? n - 1 - i : i)];
    std::memcpy(out, b, std::size_t(n));
  };
  auto i16 = [&](int at) {
    std::int16_t v;
    raw(at, 2, &v);
    return v;
  };
  auto f32 = [&](int at) {
    float v;
    raw(at, 4, &v);
    return v;
  };
  const int dims = i16(40);
  if (dims < 1 || dims > 7) return std::nullopt;
  VoxelLayout l;
  l.values = 1;
  for (int a = 1; a <= dims; ++a) {
    const int d = i16(40 + 2 * a);
    if (d <= 0) return std::nullopt;
    l.values *= std::size_t(d);
  }
  static const std::map<int, int> types = {{2, 1}, {256, 1}, {4, 2}, {512, 2}, {8, 4}, {768, 4}};
  const auto type = types.find(i16(70));
  if (type == types.end() || i16(72) != 8 * type->second) return std::nullopt;
  const float slope = f32(112), inter = f32(116), vox = f32(108);
  if (!(slope == 0 || slope == 1) || inter != 0) return std::nullopt;
  if (!(vox >= 352 && vox < 1e9f) || vox != float(std::size_t(vox))) return std::nullopt;
  l.bytes = type->second;
  l.big_endian = big;
  l.deflate = gzip;
  (gzip ? l.skip : l.offset) = std::size_t(vox);
  return l;
}

// MetaImage with ElementDataFile LOCAL (the last header line), binary
// data of one channel, no HeaderSize.
std::optional<VoxelLayout> metaimage_layout(const std::string& file) {
  std::ifstream in(file, std::ios::binary);
  std::map<std::string, std::string> f;
  std::string line;
  for (int n = 0; n < 200 && std::getline(in, line); ++n) {
    const std::size_t eq = line.find('=');
    if (eq == std::string::npos) return std::nullopt;
    auto trim = [](std::string s) {
      const std::size_t a = s.find_first_not_of(" \t\r"), b = s.find_last_not_of(" \t\r");
      return a == std::string::npos ? std::string() : s.substr(a, b - a + 1);
    };
    const std::string key = trim(line.substr(0, eq));
    f[key] = trim(line.substr(eq + 1));
    if (key == "ElementDataFile") break;
  }
  const std::streampos at = in.tellg();
  auto yes = [&](const char* key) {
    const auto it = f.find(key);
    return it != f.end() && !it->second.empty() && (it->second[0] == 'T' || it->second[0] == 't' || it->second[0] == '1');
  };
  static const std::map<std::string, int> types = {{"MET_UCHAR", 1}, {"MET_CHAR", 1}, {"MET_USHORT", 2},
                                                   {"MET_SHORT", 2}, {"MET_UINT", 4},  {"MET_INT", 4}};
  const auto type = types.find(f["ElementType"]);
  if (!in || at < 0 || f["ElementDataFile"] != "LOCAL" || type == types.end() || f.count("HeaderSize") ||
      (f.count("BinaryData") && !yes("BinaryData")) ||
      (f.count("ElementNumberOfChannels") && f["ElementNumberOfChannels"] != "1"))
    return std::nullopt;
  VoxelLayout l;
  l.bytes = type->second;
  l.big_endian = yes("BinaryDataByteOrderMSB") || yes("ElementByteOrderMSB");
  l.deflate = yes("CompressedData");
  l.offset = std::size_t(at);
  l.values = product(f["DimSize"], std::size_t(std::atoi(f["NDims"].c_str())));
  if (!l.values) return std::nullopt;
  return l;
}

} // namespace

std::optional<VoxelLayout> plain_voxel_layout(const std::string& file) {
  char head[16] = {};
  {
    std::ifstream in(file, std::ios::binary);
    in.read(head, sizeof head);
    if (in.gcount() < 4) return std::nullopt;
  }
  if (std::memcmp(head, "NRRD000", 7) == 0) return nrrd_layout(file);
  if ((unsigned char)head[0] == 0x1f && (unsigned char)head[1] == 0x8b) return nifti_layout(file, true);
  if (std::memcmp(head, "ObjectType", 10) == 0 || std::memcmp(head, "NDims", 5) == 0) return metaimage_layout(file);
  return nifti_layout(file, false);
}

// The file and, for compressed data, zlib's state and a buffer of input.
struct VoxelStream::Source {
  std::FILE* file = nullptr;
  z_stream zs{};
  bool inflating = false, ended = false;
  std::vector<unsigned char> packed;
  ~Source() {
    if (inflating) inflateEnd(&zs);
    if (file) std::fclose(file);
  }
  // The next `bytes` bytes of data into out; false when the data ends first.
  bool fill(unsigned char* out, std::size_t bytes, const std::string& path) {
    if (!inflating) return std::fread(out, 1, bytes, file) == bytes;
    std::size_t got = 0;
    while (got < bytes && !ended) {
      if (zs.avail_in == 0) {
        zs.next_in = packed.data();
        zs.avail_in = uInt(std::fread(packed.data(), 1, packed.size(), file));
        if (zs.avail_in == 0) return false;
      }
      const std::size_t room = std::min<std::size_t>(bytes - got, std::size_t(1) << 30);
      zs.next_out = out + got;
      zs.avail_out = uInt(room);
      const int rc = inflate(&zs, Z_NO_FLUSH);
      got += room - zs.avail_out;
      if (rc == Z_STREAM_END) ended = true;
      else if (rc != Z_OK && rc != Z_BUF_ERROR)
        throw Error("cannot read the image: corrupt compressed data" + (zs.msg ? " (" + std::string(zs.msg) + ")" : std::string()),
                    path);
    }
    return got == bytes;
  }
  // After the last byte: the stream's end and its check (gzip's CRC,
  // zlib's Adler-32) read, so that corrupt data is not taken as voxels;
  // false when the input ends first (data beyond the voxels is let be).
  bool finish(const std::string& path) {
    unsigned char extra;
    return ended || fill(&extra, 1, path) || ended;
  }
};

VoxelStream::VoxelStream(const std::string& file, const VoxelLayout& layout, std::size_t values, const std::string& path)
    : in_(std::make_unique<Source>()), layout_(layout), path_(path), total_(values * std::size_t(layout.bytes)) {
  in_->file = std::fopen(file.c_str(), "rb");
  if (!in_->file || std::fseek(in_->file, long(layout.offset), SEEK_SET) != 0)
    throw Error("cannot open: " + std::string(std::strerror(errno)), path);
  if (!layout.deflate) return;
  if (inflateInit2(&in_->zs, 32 + MAX_WBITS) != Z_OK) throw Error("cannot read the image: zlib cannot start", path);
  in_->inflating = true;
  in_->packed.resize(std::size_t(1) << 18);
  std::vector<unsigned char> header(layout.skip);  // a NIfTI header and its extensions
  if (!in_->fill(header.data(), header.size(), path))
    throw Error("cannot read the image: truncated compressed data (it ends in the header)", path);
}

VoxelStream::~VoxelStream() = default;

void VoxelStream::read(void* out, std::size_t n) {
  const std::size_t bytes = n * std::size_t(layout_.bytes);
  if (bytes > total_ - done_) throw Error("internal: more voxels asked for than the header declares", path_);
  unsigned char* p = static_cast<unsigned char*>(out);
  if (!in_->fill(p, bytes, path_))
    throw Error(std::string("cannot read the image: truncated ") + (layout_.deflate ? "compressed " : "") +
                    "data (the header declares " + std::to_string(total_) + " bytes of voxels)",
                path_);
  done_ += bytes;
  if (layout_.deflate && done_ == total_ && !in_->finish(path_))
    throw Error("cannot read the image: truncated compressed data (it ends before its check)", path_);
  const std::uint16_t probe = 1;
  const bool little = *reinterpret_cast<const unsigned char*>(&probe) == 1;
  if (layout_.big_endian == !little || layout_.bytes == 1) return;
  for (std::size_t i = 0; i < bytes; i += std::size_t(layout_.bytes))
    std::reverse(p + i, p + i + layout_.bytes);
}

} // namespace imgmesh
