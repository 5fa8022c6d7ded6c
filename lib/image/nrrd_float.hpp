// A float NRRD as wc2implicit writes it (ITK's NRRD writer), read without
// ITK: the tools that read only the implicit function file (implicit2mesh)
// then load no ITK library (about 7 MB of resident pages a process).
// Geometry as ITK's reader makes it (spacing the norm of each space
// direction, direction the column times 1/spacing), so meshes do not change.
#pragma once
#include "image/grid.hpp"

#include <cstddef>
#include <istream>
#include <map>
#include <memory>
#include <string>

namespace imgmesh {

// A NRRD header: its fields ("name: value", names lower case) and key/value
// pairs ("key:=value"); `data` is left at the first byte after the blank line.
struct NrrdHeader {
  std::map<std::string, std::string> fields, keys;
};

// Reads the header from `data` (path names the file in errors). Throws
// Error when it is not a NRRD header.
NrrdHeader read_nrrd_header(std::istream& data, const std::string& path);

// The samples after the header, streamed: 3D, type float, raw or gzip
// encoding, little or big endian, no detached data. The header is checked
// on construction (and, when `data` can seek, the bytes it declares against
// those left, before anything is allocated); read() then gives the samples
// in the file's order (x fastest, then y, then z) in native byte order,
// holding no more of them than the caller asks for (gzip: 64 KiB of packed
// input). Throws Error (one line, naming path) on anything else, on
// truncated or corrupt data.
class NrrdFloatStream {
public:
  NrrdFloatStream(const NrrdHeader& header, std::istream& data, const std::string& path);
  ~NrrdFloatStream();
  NrrdFloatStream(const NrrdFloatStream&) = delete;
  NrrdFloatStream& operator=(const NrrdFloatStream&) = delete;
  // The grid as ITK's reader makes it.
  const Geometry& geometry() const { return grid_; }
  // The next n samples.
  void read(float* out, std::size_t n);

private:
  struct Inflater;
  Geometry grid_;
  std::istream& data_;
  std::string path_;
  bool swap_ = false;
  std::size_t total_ = 0, done_ = 0;  // bytes declared, given so far
  std::unique_ptr<Inflater> gzip_;    // null: raw
};

// The samples whole (tests: the same as ITK's reader).
FloatImage read_nrrd_float_samples(const NrrdHeader& header, std::istream& data, const std::string& path);

} // namespace imgmesh
