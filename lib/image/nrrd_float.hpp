// A float NRRD as wc2implicit writes it (ITK's NRRD writer), read without
// ITK: the tools that read only the implicit function file (implicit2mesh)
// then load no ITK library (about 7 MB of resident pages a process).
// Geometry as ITK's reader makes it (spacing the norm of each space
// direction, direction the column times 1/spacing), so meshes do not change.
#pragma once
#include "image/grid.hpp"

#include <istream>
#include <map>
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

// The samples after the header: 3D, type float, raw or gzip encoding,
// little or big endian, no detached data. Throws Error (one line, naming
// path) on anything else, on truncated or corrupt data.
FloatImage read_nrrd_float_samples(const NrrdHeader& header, std::istream& data, const std::string& path);

} // namespace imgmesh
