// write_implicit, apart from the rest of the file format: it writes through
// ITK (image/io.hpp), which the tools that only read f do not link.
#include "implicit/implicit_file.hpp"
#include "image/io.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace imgmesh {

void write_implicit(const std::string& path, const PartitionOfUnity& f, const ScanFrame& frame, float clamp) {
  char buf[128];
  std::snprintf(buf, sizeof buf, "%.17g %.17g %.17g", f.d()[0], f.d()[1], f.d()[2]);
  std::map<std::string, std::string> keys{{"imgmesh_kind", kImplicitKind}, {"imgmesh_version", kImplicitVersion}, {"imgmesh_d", buf}};
  if (frame.present()) keys.merge(frame.keys());
  FloatImage g = f.samples().to_image();
  if (std::isfinite(clamp)) {
    for (float& v : g.data) v = std::max(-clamp, std::min(v, clamp));
    std::snprintf(buf, sizeof buf, "%.9g", double(clamp));  // a float to the last bit
    keys["imgmesh_clamp"] = buf;
  }
  write_image(path, g, keys);
}

} // namespace imgmesh
