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

FloatImage read_nrrd_float_samples(const NrrdHeader& h, std::istream& data, const std::string& path) {
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
  FloatImage g;
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
  const bool swap = (endian == "little") != little;

  const std::size_t bytes = g.count() * sizeof(float);
  const std::string encoding = field("encoding");
  // What is left after the header bounds what the header may declare, before
  // anything is allocated (deflate packs at most 1032 bytes into one).
  const std::streampos start = data.tellg();
  data.seekg(0, std::ios::end);
  const std::size_t left = start < 0 ? 0 : std::size_t(data.tellg() - start);
  data.seekg(start);
  auto too_large = [&](const char* what) {
    return Error("cannot read the image: the header declares " + std::to_string(bytes) + " bytes of samples, more than the " +
                     std::to_string(left) + what + " after it can hold",
                 path);
  };
  if (encoding == "raw") {
    if (bytes > left) throw too_large(" bytes");
    g.data.resize(g.count());
    data.read(reinterpret_cast<char*>(g.data.data()), std::streamsize(bytes));
    if (std::size_t(data.gcount()) != bytes) throw Error("cannot read the image: truncated data", path);
  } else if (encoding == "gzip" || encoding == "gz") {
    constexpr std::size_t deflate = 1032, slack = 4096;
    if (bytes > (left + slack) * deflate) throw too_large(" compressed bytes");
    std::string packed(left, '\0');
    data.read(packed.data(), std::streamsize(left));
    g.data.resize(g.count());
    z_stream zs{};
    if (inflateInit2(&zs, 32 + MAX_WBITS) != Z_OK) throw Error("cannot read the image: zlib cannot start", path);
    zs.next_in = reinterpret_cast<Bytef*>(packed.data());
    zs.avail_in = uInt(std::min<std::size_t>(packed.size(), 1u << 30));
    std::size_t in = 0, out = 0;
    int rc = Z_OK;
    while (rc == Z_OK && out < bytes) {
      const std::size_t room = std::min<std::size_t>(bytes - out, 1u << 30);
      zs.next_out = reinterpret_cast<Bytef*>(g.data.data()) + out;
      zs.avail_out = uInt(room);
      const uInt had = zs.avail_in;
      rc = inflate(&zs, Z_NO_FLUSH);
      out += room - zs.avail_out;
      in += had - zs.avail_in;
      if (zs.avail_in == 0 && in < packed.size()) {
        zs.next_in = reinterpret_cast<Bytef*>(packed.data()) + in;
        zs.avail_in = uInt(std::min<std::size_t>(packed.size() - in, 1u << 30));
      }
    }
    const std::string why = zs.msg ? zs.msg : "";
    inflateEnd(&zs);
    if (rc != Z_OK && rc != Z_STREAM_END && rc != Z_BUF_ERROR)
      throw Error("cannot read the image: corrupt gzip data" + (why.empty() ? std::string() : " (" + why + ")"), path);
    if (out != bytes)
      throw Error("cannot read the image: truncated gzip data (expected " + std::to_string(bytes) + " bytes but received " +
                      std::to_string(out) + ")",
                  path);
  } else {
    throw Error("cannot read the image: encoding " + quoted(encoding) + " (an implicit function file is raw or gzip)", path);
  }
  if (swap)
    for (float& v : g.data) {
      unsigned char b[4];
      std::memcpy(b, &v, 4);
      std::swap(b[0], b[3]);
      std::swap(b[1], b[2]);
      std::memcpy(&v, b, 4);
    }
  return g;
}

} // namespace imgmesh
