// A scratch folder in the test's working folder, made on first use and
// removed with everything in it when the test binary exits (so running a
// test by hand from the source tree leaves nothing behind).
#pragma once
#include <cstdlib>
#include <filesystem>
#include <string>
#include <unistd.h>

namespace imgmesh::test {

inline const std::string& scratch_dir() {
  struct Dir {
    std::string path;
    Dir() {
      char templ[] = "imgmesh-test-XXXXXX";
      if (!mkdtemp(templ)) std::abort();
      path = templ;
    }
    ~Dir() {
      std::error_code ec;
      std::filesystem::remove_all(path, ec);
    }
  };
  static const Dir dir;
  return dir.path;
}

} // namespace imgmesh::test
