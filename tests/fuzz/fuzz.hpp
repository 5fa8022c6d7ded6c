// Shared by the fuzz targets: the readers take file names (ITK and OpenMesh
// pick the reader by extension), so each input is written to a scratch file
// first. A target may throw imgmesh::Error (the one-line refusal every tool
// prints); anything else escaping a reader is a finding, as is every crash,
// leak or sanitizer report.
#pragma once
#include "util/error.hpp"

#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <string>
#include <unistd.h>

namespace fuzz {

// A per-process scratch folder (fuzzing jobs run in parallel).
inline const std::string& scratch() {
  static const std::string dir = [] {
    const char* t = std::getenv("TMPDIR");
    std::string d = std::string(t && *t ? t : "/tmp") + "/imgmesh-fuzz-" + std::to_string(getpid());
    std::string cmd = "mkdir -p '" + d + "'";
    if (std::system(cmd.c_str()) != 0) std::abort();
    return d;
  }();
  return dir;
}

// Writes data to scratch()/name and returns the path.
inline std::string write_file(const std::string& name, const std::uint8_t* data, std::size_t size) {
  const std::string path = scratch() + "/" + name;
  FILE* f = std::fopen(path.c_str(), "wb");
  if (!f) std::abort();
  if (size && std::fwrite(data, 1, size, f) != size) std::abort();
  std::fclose(f);
  return path;
}

// Runs f(); an imgmesh::Error is the expected refusal, any other exception a
// finding (the tool would print a message that names no file).
template <class F> void refuse_or_pass(F&& f) {
  try {
    f();
  } catch (const imgmesh::Error&) {
  } catch (const std::exception& e) {
    std::fprintf(stderr, "fuzz: exception that is not an imgmesh::Error: %s\n", e.what());
    std::abort();
  }
}

} // namespace fuzz
