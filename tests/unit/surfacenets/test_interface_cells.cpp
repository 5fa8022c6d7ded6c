// The interface certificate's lattice shortcut (interface_cells.cpp): on
// surface-nets meshes, smoothed or not, the certificate with the nesting
// and voxel sides from the lattice is the one the rays give (every figure,
// each label's nesting depths; cavities, a rotated grid); net_cells
// refuses each mesh that is not a surface-nets mesh with its vertices
// strictly in their cells, and the certificate then falls back to rays; a
// mesh moved off its cells with voxel centres on the wrong side fails on
// them.
#include "surfacenets/interface_certificate.hpp"

#include "surfacenets/interface_certificate_detail.hpp"
#include "surfacenets/label_maps.hpp"
#include "surfacenets/soup.hpp"
#include "surfacenets/surface_nets.hpp"

#include <catch2/catch.hpp>

#include <algorithm>
#include <string>

using namespace imgmesh;
using namespace imgmesh::test;

namespace {

using Cert = InterfaceCertificate;

Cert certify(const Soup& s, const LabelImage& img, bool lattice) {
  InterfaceCertificateOptions o;
  o.lattice = lattice;
  return certify_interface_mesh(s.points, s.triangles, s.pairs, img, o);
}

// The lattice's certificate is the rays': every figure, every depth.
void check_same_as_rays(const Soup& s, const LabelImage& img, bool on_lattice) {
  const Cert lattice = certify(s, img, true), rays = certify(s, img, false);
  CHECK(lattice.on_lattice == on_lattice);
  CHECK(!rays.on_lattice);
  CHECK(lattice.to_json().dump() == rays.to_json().dump());
  REQUIRE(lattice.labels.size() == rays.labels.size());
  for (std::size_t i = 0; i < rays.labels.size(); ++i) {
    INFO("label " << rays.labels[i].label);
    CHECK(lattice.labels[i].surface.depth == rays.labels[i].surface.depth);
    CHECK(lattice.labels[i].sides_checked == rays.labels[i].sides_checked);
  }
}

void check_map(const LabelImage& img) {
  const InterfaceComplex k = interface_complex(img);
  InterfaceMesh m = interface_mesh(img, k);
  check_same_as_rays(soup_of(m), img, true);
  smooth_interface_mesh(m);
  check_same_as_rays(soup_of(m), img, true);
}

surfacenets_detail::NetCells cells_of(const Soup& s, const LabelImage& img) {
  return surfacenets_detail::net_cells(s.points, s.triangles, s.pairs, img, interface_complex(img));
}

} // namespace

// (test_interface_certificate.cpp compares the two on every map it certifies.)
TEST_CASE("interface cells: the lattice's nesting and sides are the rays'", "[surfacenets]") {
  SECTION("nested shells (cavities: depths 1), then with an offset origin on a rotated grid") {
    LabelImage img = nested_shells();
    check_map(img);
    const Cert c = certify(soup_of(interface_mesh(img, interface_complex(img))), img, true);
    std::vector<int> depths;
    for (const auto& l : c.labels) depths.insert(depths.end(), l.surface.depth.begin(), l.surface.depth.end());
    CHECK(std::count(depths.begin(), depths.end(), 1) >= 2);
    img.spacing = {0.5, 1.5, 2.0};
    img.origin = {300, -2, 7};
    img.direction = {0, 0, 1, 1, 0, 0, 0, 1, 0};
    check_map(img);
  }
  SECTION("smoothed with no margin: vertices on their cells' sides, rays") {
    const LabelImage img = three_labels();
    InterfaceMesh m = interface_mesh(img, interface_complex(img));
    SmoothingOptions o;
    o.margin = 0;
    o.rounds = 20;
    smooth_interface_mesh(m, o);
    check_same_as_rays(soup_of(m), img, false);
  }
}

TEST_CASE("interface cells: what is not a surface-nets mesh in its cells is refused, and rays decide", "[surfacenets]") {
  const LabelImage img = three_labels();
  const InterfaceComplex k = interface_complex(img);
  InterfaceMesh m = interface_mesh(img, k);
  smooth_interface_mesh(m);
  const Soup s0 = soup_of(m);
  REQUIRE(cells_of(s0, img).holds);
  // Quad 0 (K(X)'s first face) and the corner of its first vertex.
  const std::size_t f = 0;
  const auto q = m.quads[f];
  auto refused = [&](const Soup& s, const std::string& start) {
    const auto c = cells_of(s, img);
    INFO(c.why);
    CHECK(!c.holds);
    CHECK(c.why.find(start) != std::string::npos);
    check_same_as_rays(s, img, false);
  };
  SECTION("a vertex on its cell's side") {
    Soup s = s0;
    const auto c = m.corner(std::size_t(q[0]));
    s.points[std::size_t(q[0])] = img.world(double(c[0]) - 1, double(c[1]) - 0.5, double(c[2]) - 0.5);
    refused(s, "not strictly inside");
  }
  SECTION("a vertex in its neighbour's cell") {
    Soup s = s0;
    const auto c = m.corner(std::size_t(q[0]));
    s.points[std::size_t(q[0])] = img.world(double(c[0]) + 0.5, double(c[1]) - 0.5, double(c[2]) - 0.5);
    refused(s, "shares its cell");
  }
  SECTION("two vertices in one cell") {
    Soup s = s0;
    s.points.push_back(s.points[std::size_t(q[0])]);
    for (int& v : s.triangles[2 * f])
      if (v == q[0]) v = int(s.points.size() - 1);
    refused(s, "shares its cell");
  }
  SECTION("a triangle flipped") {
    Soup s = s0;
    std::swap(s.triangles[1][1], s.triangles[1][2]);
    refused(s, "not oriented as its face");
  }
  SECTION("a pair given the other way round") {
    Soup s = s0;
    std::swap(s.pairs[1][0], s.pairs[1][1]);
    refused(s, "not oriented as its face");
  }
  SECTION("a triangle with another pair") {
    Soup s = s0;
    s.pairs[1] = {s.pairs[1][0] + 1, s.pairs[1][1]};
    refused(s, "another pair than its face");
  }
  SECTION("a quad's triangles leaving out two neighbouring corners") {
    Soup s = s0;
    s.triangles[2 * f] = {q[0], q[1], q[2]};
    s.triangles[2 * f + 1] = {q[1], q[2], q[3]};
    refused(s, "not split in two along a diagonal");
  }
  SECTION("a triangle dropped") {
    Soup s = s0;
    s.triangles.pop_back();
    s.pairs.pop_back();
    refused(s, "not two triangles a face");
  }
  SECTION("a triangle across two faces") {
    Soup s = s0;
    // Quad 0's third corner replaced by a corner of a quad that is not its neighbour.
    const auto far = m.quads[m.quads.size() / 2];
    s.triangles[2 * f] = {q[0], q[1], far[2]};
    refused(s, "triangle 0 is not on a voxel face");
  }
}

TEST_CASE("interface cells: a label moved off its cells leaves voxel centres on the wrong side, counted", "[surfacenets]") {
  // The one-voxel label 2 inside label 1, its cube moved 0.6 voxels along
  // x: still closed, outward, placed and crossing nothing, but label 2's
  // centre is now outside it and label 1's next centre inside it.
  const LabelImage img = side_and_one_voxel();
  const InterfaceComplex k = interface_complex(img);
  const InterfaceMesh m = interface_mesh(img, k);
  Soup s = soup_of(m);
  std::vector<bool> moved(s.points.size(), false);
  for (std::size_t t = 0; t < s.triangles.size(); ++t)
    if (s.pairs[t] == std::array<std::int32_t, 2>{2, 1})
      for (int v : s.triangles[t]) moved[std::size_t(v)] = true;
  for (std::size_t v = 0; v < s.points.size(); ++v)
    if (moved[v]) {
      const Vec3 i = img.continuous_index(s.points[v]);
      s.points[v] = img.world(i[0] + 0.6, i[1], i[2]);
    }
  for (bool lattice : {true, false}) {
    const Cert c = certify(s, img, lattice);
    INFO(c.failure());
    CHECK(!c.on_lattice);
    CHECK(c.first_failed() == Cert::kSides);
    CHECK(c.failure().rfind("label 1: voxel sides: 2 of ", 0) == 0);
    for (const auto& l : c.labels)
      if (l.label == 2) CHECK(l.sides.foreground_outside == 1);
  }
}
