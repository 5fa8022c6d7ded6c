#include "image/nrrd_float.hpp"

#include "util/error.hpp"

#include <zlib.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <sstream>
#include <vector>

namespace imgmesh {
namespace {

// Header text quoted in an error: at most 60 characters, each printable
// (the header may be binary data), on one line.
std::string quoted(const std::string& text) {
  std::string shown = text.substr(0, 60);
  for (char& c : shown)
    if (!std::isprint((unsigned char)c)) c = '?';
  return "'" + shown + "'";
}

// Three numbers of a "(x,y,z)" vector, or an Error naming the field.
Vec3 vector_of(const std::string& text, const std::string& field, const std::string& path) {
  std::string t = text;
  for (char& c : t)
    if (c == '(' || c == ')' || c == ',') c = ' ';
  std::istringstream in(t);
  Vec3 v;
  std::string extra;
  if (!(in >> v[0] >> v[1] >> v[2]) || (in >> extra) || !std::isfinite(v[0]) || !std::isfinite(v[1]) || !std::isfinite(v[2]))
    throw Error("cannot read the image: bad " + field + " vector " + quoted(text) + " (want three finite numbers)", path);
  return v;
}

// The space directions field: three "(x,y,z)" vectors.
std::array<Vec3, 3> directions_of(const std::string& text, const std::string& path) {
  std::array<Vec3, 3> d;
  std::size_t at = 0;
  for (Vec3& v : d) {
    const std::size_t open = text.find('(', at), close = text.find(')', open == std::string::npos ? at : open);
    if (open == std::string::npos || close == std::string::npos)
      throw Error("cannot read the image: bad space directions " + quoted(text) + " (want three vectors)", path);
    v = vector_of(text.substr(open, close - open + 1), "space directions", path);
    at = close + 1;
  }
  if (text.find_first_not_of(" \t", at) != std::string::npos)
    throw Error("cannot read the image: bad space directions " + quoted(text) + " (want three vectors)", path);
  return d;
}

} // namespace

NrrdHeader read_nrrd_header(std::istream& data, const std::string& path) {
  std::string line;
  if (!std::getline(data, line) || line.size() < 8 || line.compare(0, 7, "NRRD000") != 0 || !std::isdigit((unsigned char)line[7]))
    throw Error("not a NRRD file (the implicit function file is wc2implicit's NRRD)", path);
  NrrdHeader h;
  for (;;) {
    if (!std::getline(data, line)) throw Error("cannot read the image: the NRRD header has no end (no blank line)", path);
    if (!line.empty() && line.back() == '\r') line.pop_back();
    if (line.empty()) break;
    if (line[0] == '#') continue;
    const std::size_t key = line.find(":="), field = line.find(": ");
    if (key != std::string::npos && (field == std::string::npos || key < field)) {
      h.keys[line.substr(0, key)] = line.substr(key + 2);
    } else if (field != std::string::npos) {
      std::string name = line.substr(0, field);
      for (char& c : name) c = char(std::tolower((unsigned char)c));
      h.fields[name] = line.substr(field + 2);
    } else {
      throw Error("cannot read the image: bad NRRD header line " + quoted(line) + " (a field, a key:=value or the blank line that ends the header expected)", path);
    }
  }
  return h;
}

// zlib's state and 64 KiB of packed input.
struct NrrdFloatStream::Inflater {
  z_stream zs{};
  std::vector<char> packed = std::vector<char>(std::size_t(1) << 16);
  bool ended = false;
  ~Inflater() { inflateEnd(&zs); }
};

NrrdFloatStream::NrrdFloatStream(const NrrdHeader& h, std::istream& data, const std::string& path)
    : data_(data), path_(path) {
  auto field = [&](const char* name) {
    const auto it = h.fields.find(name);
    return it == h.fields.end() ? std::string() : it->second;
  };
  for (const char* detached : {"data file", "datafile", "line skip", "lineskip", "byte skip", "byteskip"})
    if (h.fields.count(detached))
      throw Error(std::string("cannot read the image: '") + detached + "' is not supported in an implicit function file", path);
  if (field("type") != "float")
    throw Error("cannot read the image: samples of type " + quoted(field("type")) + " (an implicit function file holds float)", path);
  if (field("dimension") != "3")
    throw Error("cannot read the image: dimension " + quoted(field("dimension")) + " (an implicit function file is 3D)", path);
  Geometry& g = grid_;
  {
    std::istringstream in(field("sizes"));
    long long s[3];
    std::string extra;
    if (!(in >> s[0] >> s[1] >> s[2]) || (in >> extra))
      throw Error("cannot read the image: bad sizes " + quoted(field("sizes")) + " (want three)", path);
    std::size_t count = 1;
    for (int a = 0; a < 3; ++a) {
      if (s[a] <= 0) throw Error("cannot read the image: size is zero or negative", path);
      if (count > (std::size_t(1) << 40) / std::size_t(s[a])) throw Error("image too large", path);
      g.size[a] = std::size_t(s[a]);
      count *= g.size[a];
    }
  }
  // Geometry as ITK's NRRD reader (NrrdIO's nrrdSpacingCalculate): spacing
  // the norm of each space direction, its column that times 1/spacing; an
  // RAS space flips x and y into LPS.
  const std::string space = field("space");
  if (!field("space directions").empty()) {
    const std::array<Vec3, 3> d = directions_of(field("space directions"), path);
    const bool ras = space == "right-anterior-superior" || space == "RAS";
    if (!ras && space != "left-posterior-superior" && space != "LPS")
      throw Error("cannot read the image: space " + quoted(space) + " (left-posterior-superior or right-anterior-superior expected)", path);
    for (int a = 0; a < 3; ++a) {
      Vec3 v = d[a];
      if (ras) v[0] = -v[0], v[1] = -v[1];
      double nn = 0;
      for (double x : v) nn += x * x;
      g.spacing[a] = std::sqrt(nn);
      for (int r = 0; r < 3; ++r) g.direction[r * 3 + a] = v[r] * (1.0 / g.spacing[a]);
    }
    if (!field("space origin").empty()) {
      g.origin = vector_of(field("space origin"), "space origin", path);
      if (ras) g.origin[0] = -g.origin[0], g.origin[1] = -g.origin[1];
    }
  } else if (!field("space origin").empty() || !field("axis mins").empty() || !field("axes mins").empty()) {
    // A grid placed without space directions: refused rather than read at
    // the default origin (wc2implicit writes space directions and origin).
    throw Error("cannot read the image: an origin without space directions (an implicit function file places its grid by space directions and space origin)", path);
  } else if (!field("spacings").empty()) {
    std::istringstream in(field("spacings"));
    std::string extra;
    if (!(in >> g.spacing[0] >> g.spacing[1] >> g.spacing[2]) || (in >> extra))
      throw Error("cannot read the image: bad spacings " + quoted(field("spacings")), path);
  }
  for (double s : g.spacing)
    if (!(s > 0) || !std::isfinite(s)) throw Error("spacing must be positive and finite", path);

  const std::string endian = field("endian");
  std::uint16_t probe = 1;
  const bool little = *reinterpret_cast<unsigned char*>(&probe) == 1;
  if (endian != "little" && endian != "big")
    throw Error("cannot read the image: endian " + quoted(endian) + " (float samples need little or big, as NRRD says)", path);
  swap_ = (endian == "little") != little;

  total_ = g.count() * sizeof(float);
  const std::string encoding = field("encoding");
  const bool gzip = encoding == "gzip" || encoding == "gz";
  if (encoding != "raw" && !gzip)
    throw Error("cannot read the image: encoding " + quoted(encoding) + " (an implicit function file is raw or gzip)", path);
  // What is left after the header bounds what the header may declare, when
  // the input can tell (a file; not a pipe), before anything is allocated
  // (deflate packs at most 1032 bytes into one).
  const std::streampos start = data.tellg();
  if (start >= 0 && data.seekg(0, std::ios::end)) {
    const std::streampos end = data.tellg();
    data.seekg(start);
    const std::size_t left = end < start ? 0 : std::size_t(end - start);
    constexpr std::size_t deflate = 1032, slack = 4096;
    if (gzip ? total_ > (left + slack) * deflate : total_ > left)
      throw Error("cannot read the image: the header declares " + std::to_string(total_) + " bytes of samples, more than the " +
                      std::to_string(left) + (gzip ? " compressed bytes" : " bytes") + " after it can hold",
                  path);
  }
  data.clear();
  if (gzip) {
    gzip_ = std::make_unique<Inflater>();
    if (inflateInit2(&gzip_->zs, 32 + MAX_WBITS) != Z_OK) throw Error("cannot read the image: zlib cannot start", path);
  }
}

NrrdFloatStream::~NrrdFloatStream() = default;

void NrrdFloatStream::read(float* out, std::size_t n) {
  const std::size_t bytes = n * sizeof(float);
  if (bytes > total_ - done_) throw Error("internal: more samples asked for than the header declares", path_);
  if (!gzip_) {
    data_.read(reinterpret_cast<char*>(out), std::streamsize(bytes));
    if (std::size_t(data_.gcount()) != bytes) throw Error("cannot read the image: truncated data", path_);
  } else {
    z_stream& zs = gzip_->zs;
    std::size_t got = 0;
    while (got < bytes) {
      if (gzip_->ended) break;
      if (zs.avail_in == 0) {
        data_.read(gzip_->packed.data(), std::streamsize(gzip_->packed.size()));
        zs.next_in = reinterpret_cast<Bytef*>(gzip_->packed.data());
        zs.avail_in = uInt(data_.gcount());
        if (zs.avail_in == 0) break;  // the input ended
      }
      const std::size_t room = std::min<std::size_t>(bytes - got, 1u << 30);
      zs.next_out = reinterpret_cast<Bytef*>(out) + got;
      zs.avail_out = uInt(room);
      const int rc = inflate(&zs, Z_NO_FLUSH);
      got += room - zs.avail_out;
      if (rc == Z_STREAM_END) gzip_->ended = true;
      else if (rc != Z_OK && rc != Z_BUF_ERROR)
        throw Error("cannot read the image: corrupt gzip data" + (zs.msg ? " (" + std::string(zs.msg) + ")" : std::string()), path_);
    }
    if (got != bytes)
      throw Error("cannot read the image: truncated gzip data (expected " + std::to_string(total_) + " bytes but received " +
                      std::to_string(done_ + got) + ")",
                  path_);
  }
  done_ += bytes;
  if (swap_)
    for (std::size_t i = 0; i < n; ++i) {
      unsigned char b[4];
      std::memcpy(b, &out[i], 4);
      std::swap(b[0], b[3]);
      std::swap(b[1], b[2]);
      std::memcpy(&out[i], b, 4);
    }
}

FloatImage read_nrrd_float_samples(const NrrdHeader& header, std::istream& data, const std::string& path) {
  NrrdFloatStream in(header, data, path);
  FloatImage g(in.geometry());
  in.read(g.data.data(), g.data.size());
  return g;
}

} // namespace imgmesh
