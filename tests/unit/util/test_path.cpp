#include "util/path.hpp"

#include <catch2/catch.hpp>

using namespace imgmesh;

TEST_CASE("extension_of knows compound extensions") {
  CHECK(extension_of("a/b.NII.gz") == ".nii.gz");
  CHECK(extension_of("scan.nrrd") == ".nrrd");
  CHECK(extension_of("dir.d/noext") == "");
  CHECK(extension_of(".hidden") == "");
  CHECK(replace_extension("a/x.1.ele", ".node") == "a/x.1.node");
}
