#include "util/atomic_file.hpp"
#include "util/error.hpp"

#include <catch2/catch.hpp>
#include <cstdio>
#include <fstream>
#include <string>
#include <sys/stat.h>
#include <unistd.h>

using namespace imgmesh;

static std::string make_dir() {
  char templ[] = "/tmp/imgmesh-test-XXXXXX";
  REQUIRE(mkdtemp(templ) != nullptr);
  return templ;
}
TEST_CASE("AtomicOutput leaves nothing behind unless committed") {
  const std::string dir = make_dir();
  const std::string target = dir + "/out.txt";
  {
    AtomicOutput out(target);
    out.stream() << "partial";
    CHECK(out.path() != target);
    CHECK(extension_of(out.path()) == ".txt");
  }
  CHECK(access(target.c_str(), F_OK) != 0);
  {
    AtomicOutput out(target);
    out.stream() << "whole";
    out.commit();
  }
  std::ifstream in(target);
  std::string s;
  in >> s;
  CHECK(s == "whole");
  std::remove(target.c_str());
  rmdir(dir.c_str());
}

TEST_CASE("AtomicOutput gives the output the permissions of the umask, not mkstemp's 0600") {
  const std::string dir = make_dir();
  const std::string target = dir + "/out.txt";
  const mode_t old = umask(022);
  {
    AtomicOutput out(target);
    out.stream() << "x";
    out.commit();
  }
  umask(old);
  struct stat st {};
  REQUIRE(stat(target.c_str(), &st) == 0);
  CHECK((st.st_mode & 0777) == 0644);
  std::remove(target.c_str());
  rmdir(dir.c_str());
}

TEST_CASE("AtomicOutput fails clearly on a missing folder") {
  CHECK_THROWS_AS(AtomicOutput("/nonexistent-folder/x.txt"), Error);
}

TEST_CASE("extension_of knows compound extensions") {
  CHECK(extension_of("a/b.NII.gz") == ".nii.gz");
  CHECK(extension_of("scan.nrrd") == ".nrrd");
  CHECK(extension_of("dir.d/noext") == "");
  CHECK(extension_of(".hidden") == "");
  CHECK(replace_extension("a/x.1.ele", ".node") == "a/x.1.node");
}
