// The conforming surface complex (conforming/conforming_surface.hpp),
// certified by the interface certificate against K(X) on hand-built
// partitions: every interface meshed once, every label's surface of the
// right topology, no crossing, every voxel centre on its label's side,
// triangles within the ratio bound.
#include "conforming/conforming_surface.hpp"
#include "label_maps.hpp"
#include "surfacenets/interface_certificate.hpp"
#include "wellcomposed/interface_complex.hpp"

#include <catch2/catch.hpp>

#include <cmath>

using namespace imgmesh;
using namespace imgmesh::test;

namespace {

InterfaceCertificate mesh_and_certify(const LabelImage& x, ConformingSurface& m, const ConformingOptions& o = {}) {
  const LabelFunction f(x, 0.3 * std::min({x.spacing[0], x.spacing[1], x.spacing[2]}));
  const InterfaceComplex k = interface_complex(x);
  m = conforming_surface(f, x, k, o);
  InterfaceCertificateOptions co;
  co.lattice = false;
  return certify_interface_mesh(m.points, m.triangles, m.pairs, x, k, co);
}

} // namespace

TEST_CASE("conforming surfaces of hand-built partitions are certified", "[conforming]") {
  const std::pair<const char*, LabelImage> maps[] = {{"nested shells", nested_shells()},
                                                     {"three labels", three_labels()},
                                                     {"four labels around an edge", four_labels_around_an_edge()}};
  for (const auto& [name, x] : maps) {
    INFO(name);
    ConformingSurface m;
    const InterfaceCertificate c = mesh_and_certify(x, m);
    INFO(c.summary());
    INFO(m.to_json().dump());
    CHECK(!m.max_points_hit);
    CHECK(c.ok());
    CHECK(m.smallest_angle >= std::asin(1 / (2 * 1.2)) * 180 / M_PI - 1e-9);
  }
}
