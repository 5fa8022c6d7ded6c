#include "util/atomic_file.hpp"
#include "util/path.hpp"
#include "util/error.hpp"

#include "scratch_dir.hpp"

#include <catch2/catch.hpp>
#include <cstdio>
#include <filesystem>
#include <iterator>
#include <fstream>
#include <string>
#include <sys/stat.h>
#include <unistd.h>

using namespace imgmesh;

static std::string make_dir() {  // a folder of its own in the scratch folder
  std::string templ = test::scratch_dir() + "/d-XXXXXX";
  REQUIRE(mkdtemp(templ.data()) != nullptr);
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

static std::string slurp(const std::string& path) {
  std::ifstream in(path);
  return std::string(std::istreambuf_iterator<char>(in), {});
}
static int entries(const std::string& dir) {
  int n = 0;
  for (const auto& e : std::filesystem::directory_iterator(dir)) n += !e.path().empty();
  return n;
}

TEST_CASE("OutputGroup lands its files together or not at all") {
  const std::string dir = make_dir();
  const std::string a = dir + "/m.ele", b = dir + "/m.node";
  { std::ofstream(a) << "old ele"; }
  SECTION("all in place, the earlier file replaced") {
    {
      OutputGroup group;
      AtomicOutput oa(a), ob(b);
      oa.stream() << "new ele";
      ob.stream() << "new node";
      oa.commit();
      ob.commit();
      group.commit();
    }
    CHECK(slurp(a) == "new ele");
    CHECK(slurp(b) == "new node");
    CHECK(entries(dir) == 2);
    std::remove(b.c_str());
  }
  SECTION("a later file failing to move takes the earlier one back") {
    {
      OutputGroup group;
      AtomicOutput oa(a), ob(b);
      oa.stream() << "new ele";
      ob.stream() << "new node";
      oa.commit();
      ob.commit();
      std::remove(ob.path().c_str());  // its rename fails after a's succeeded
      CHECK_THROWS_AS(group.commit(), Error);
    }
    CHECK(slurp(a) == "old ele");
    CHECK(access(b.c_str(), F_OK) != 0);
    CHECK(entries(dir) == 1);  // no temporary file, no backup left
  }
  SECTION("a target that is a folder fails before anything moves") {
    REQUIRE(mkdir(b.c_str(), 0755) == 0);
    {
      OutputGroup group;
      AtomicOutput oa(a), ob(b);
      oa.stream() << "new ele";
      ob.stream() << "new node";
      oa.commit();
      ob.commit();
      CHECK_THROWS_AS(group.commit(), Error);
    }
    CHECK(slurp(a) == "old ele");
    CHECK(entries(dir) == 2);
    rmdir(b.c_str());
  }
  std::remove(a.c_str());
  rmdir(dir.c_str());
}

TEST_CASE("AtomicOutput fails clearly on a missing folder") {
  CHECK_THROWS_AS(AtomicOutput("/nonexistent-folder/x.txt"), Error);
}
