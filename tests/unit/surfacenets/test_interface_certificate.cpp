// The multi-label certificate (interface_certificate.hpp): it holds on the
// surface-nets meshes of hand-built and random well-composed maps, before
// and after smoothing, with each label's volume its voxels' before
// smoothing, and is the same with its lattice shortcut as with rays; and each wrong mesh is refused, naming the check and the pair
// or label that fails.
#include "surfacenets/interface_certificate.hpp"

#include "image/narrow_labels.hpp"
#include "mesh/embedding.hpp"
#include "surfacenets/label_maps.hpp"
#include "surfacenets/soup.hpp"
#include "surfacenets/surface_nets.hpp"
#include "util/error.hpp"
#include "wellcomposed/well_composed_partition.hpp"

#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <map>
#include <set>
#include <string>

using namespace imgmesh;
using namespace imgmesh::test;

namespace {

using Cert = InterfaceCertificate;

Cert certify(const Soup& s, const LabelImage& img) { return certify_interface_mesh(s.points, s.triangles, s.pairs, img); }

// Holds; the counts are K(X)'s; unsmoothed, every label encloses exactly
// its voxels' volume (label 0: the foreground's).
void check_holds(const Soup& s, const LabelImage& img, const InterfaceComplex& k, bool unsmoothed) {
  const Cert c = certify(s, img);
  INFO(c.summary());
  REQUIRE(c.failure() == "");
  CHECK(c.ok());
  // The nesting and voxel sides from the lattice (interface_cells.cpp): the rays' certificate.
  CHECK(c.on_lattice);
  InterfaceCertificateOptions rays;
  rays.lattice = false;
  const Cert r = certify_interface_mesh(s.points, s.triangles, s.pairs, img, rays);
  CHECK(r.to_json().dump() == c.to_json().dump());
  REQUIRE(r.labels.size() == c.labels.size());
  for (std::size_t i = 0; i < c.labels.size(); ++i) CHECK(r.labels[i].surface.depth == c.labels[i].surface.depth);
  std::set<std::array<std::int32_t, 2>> pairs;
  for (const auto& p : k.patches) pairs.insert({p.behind, p.front});
  std::size_t patches = 0;
  for (const auto& in : c.interfaces) patches += in.patches.size();
  CHECK(c.interfaces.size() == pairs.size());
  CHECK(patches == k.patches.size());
  std::size_t labelled = 0;
  for (const auto& lb : k.labels) labelled += lb.faces > 0;
  CHECK(c.labels.size() == labelled);
  for (const auto& l : c.labels) {
    CHECK(l.sides_checked);
    CHECK(l.area > 0);
    if (unsmoothed) CHECK(std::abs(l.volume - l.voxel_volume) < 1e-9 * (1 + l.voxel_volume));
    else CHECK(l.volume > 0);
  }
}

// The certificate holds on the unsmoothed and the smoothed mesh.
void check_case(const LabelImage& img) {
  const InterfaceComplex k = interface_complex(img);
  REQUIRE(k.failed_guarantee().empty());
  InterfaceMesh m = interface_mesh(img, k);
  check_holds(soup_of(m), img, k, true);
  smooth_interface_mesh(m);
  check_holds(soup_of(m), img, k, false);
}

} // namespace

TEST_CASE("interface certificate: holds on hand-built maps, before and after smoothing", "[surfacenets]") {
  SECTION("nested shells") { check_case(nested_shells()); }
  SECTION("three labels along triple curves") { check_case(three_labels()); }
  SECTION("a label on the grid's side and a one-voxel label") { check_case(side_and_one_voxel()); }
  SECTION("anisotropic spacing and a reflecting direction") {
    LabelImage img = three_labels();
    img.spacing = {0.5, 1.5, 2.0};
    img.origin = {3, -2, 7};
    img.direction = {0, 1, 0, 1, 0, 0, 0, 0, 1};
    check_case(img);
  }
  SECTION("four labels around one curve") { check_case(four_labels_around_an_edge()); }
  SECTION("the pinched block: one vertex, two fans, as K(X) counts it") {
    const LabelImage img = pinched_block();
    const InterfaceComplex k = interface_complex(img);
    REQUIRE(k.pinched_vertices() == 1);
    check_case(img);
    const Cert c = certify(soup_of(interface_mesh(img, k)), img);
    for (const auto& in : c.interfaces)
      for (const auto& p : in.patches) CHECK(p.pinched_vertices == (in.name() == "3|0" ? 1u : 0u));
  }
}

TEST_CASE("interface certificate: a random map of 200 labels", "[surfacenets]") {
  std::mt19937_64 rng(200);
  const PartitionResult r = make_well_composed_partition(voronoi_map(rng, 16, 200));
  REQUIRE(r.failed_guarantee().empty());
  std::set<std::int32_t> labels(r.image.data.begin(), r.image.data.end());
  REQUIRE(labels.size() > 150);
  check_case(r.image);
  // Labels certified by several threads: the same certificate.
  const InterfaceComplex k = interface_complex(r.image);
  InterfaceMesh m = interface_mesh(r.image, k);
  smooth_interface_mesh(m);
  const Soup s = soup_of(m);
  InterfaceCertificateOptions three;
  three.threads = 3;
  const InterfaceCertificate one = certify_interface_mesh(s.points, s.triangles, s.pairs, r.image, k);
  CHECK(one.ok());
  CHECK(certify_interface_mesh(s.points, s.triangles, s.pairs, r.image, k, three).to_json().dump() == one.to_json().dump());
  // The image held a byte a voxel (seg2mesh --fast): the same certificate.
  const NarrowLabelImage u8 = narrow_labels(r.image);
  REQUIRE(u8.bytes == 1);
  CHECK(certify_interface_mesh(s.points, s.triangles, s.pairs, u8, k, three).to_json().dump() == one.to_json().dump());
  // Labels past 255 (two bytes a voxel): the same as on the int32 image.
  LabelImage wide = r.image;
  for (std::int32_t& v : wide.data)
    if (v != 0) v += 1000;
  const InterfaceComplex kw = interface_complex(wide);
  InterfaceMesh mw = interface_mesh(wide, kw);
  smooth_interface_mesh(mw);
  const Soup sw = soup_of(mw);
  const InterfaceCertificate wide_cert = certify_interface_mesh(sw.points, sw.triangles, sw.pairs, wide, kw);
  CHECK(wide_cert.ok());
  const NarrowLabelImage u16 = narrow_labels(wide);
  REQUIRE(u16.bytes == 2);
  CHECK(certify_interface_mesh(sw.points, sw.triangles, sw.pairs, u16, kw).to_json().dump() == wide_cert.to_json().dump());
}

namespace {

// The mesh of the three-label map, and the triangles of one pair.
struct Fixture {
  LabelImage img = three_labels();
  InterfaceComplex k = interface_complex(img);
  InterfaceMesh m = interface_mesh(img, k);
  Soup s = soup_of(m);
  std::vector<std::size_t> of_pair(std::int32_t a, std::int32_t b) const {
    std::vector<std::size_t> ts;
    for (std::size_t t = 0; t < s.pairs.size(); ++t)
      if (s.pairs[t] == std::array<std::int32_t, 2>{a, b}) ts.push_back(t);
    return ts;
  }
};

void erase(Soup& s, std::vector<std::size_t> ts) {
  std::sort(ts.rbegin(), ts.rend());
  for (std::size_t t : ts) {
    s.triangles.erase(s.triangles.begin() + std::ptrdiff_t(t));
    s.pairs.erase(s.pairs.begin() + std::ptrdiff_t(t));
  }
}

// Triangles ts moved onto copies of the vertices `which` accepts.
template <class Which> void copy_vertices(Soup& s, const std::vector<std::size_t>& ts, Which which) {
  std::map<int, int> copy;
  for (std::size_t t : ts)
    for (int& v : s.triangles[t]) {
      if (!which(v)) continue;
      if (!copy.count(v)) copy[v] = int(s.points.size()), s.points.push_back(s.points[std::size_t(v)]);
      v = copy[v];
    }
}

void check_refused(const Soup& s, const LabelImage& img, int check, const std::string& start) {
  const Cert c = certify(s, img);
  INFO(c.failure());
  CHECK(c.first_failed() == check);
  CHECK(c.failure().rfind(start, 0) == 0);
  CHECK(c.summary().rfind("interface certificate fails: " + start, 0) == 0);
}

} // namespace

TEST_CASE("interface certificate: wrong meshes refused, naming the check", "[surfacenets]") {
  Fixture f;
  REQUIRE(certify(f.s, f.img).ok());
  const auto p21 = f.of_pair(2, 1);
  REQUIRE(!p21.empty());
  SECTION("a duplicated interface (each label's copy, as separate surfaces write it)") {
    Soup s = f.s;
    for (std::size_t t : p21) s.triangles.push_back(s.triangles[t]), s.pairs.push_back(s.pairs[t]);
    std::vector<std::size_t> copies(p21.size());
    for (std::size_t i = 0; i < p21.size(); ++i) copies[i] = f.s.triangles.size() + i;
    copy_vertices(s, copies, [](int) { return true; });
    check_refused(s, f.img, Cert::kInterfaces, "interface 2|1: 2 patches, K(X) has 1");
  }
  SECTION("a duplicated interface on the same vertices") {
    Soup s = f.s;
    for (std::size_t t : p21) s.triangles.push_back(s.triangles[t]), s.pairs.push_back({1, 2});
    check_refused(s, f.img, Cert::kInterfaces, "interface 2|1: the patch of triangle");
  }
  SECTION("a dropped patch") {
    Soup s = f.s;
    erase(s, p21);
    check_refused(s, f.img, Cert::kInterfaces, "interface 2|1: 0 patches, K(X) has 1");
  }
  SECTION("a patch split in two") {
    Soup s = f.s;
    // Patch 2|1 is the plane x = 6 (corners), y 2..8, z 2..7: the half
    // above y = 5 on copies of its inner vertices at y = 5.
    std::vector<std::size_t> upper;
    for (std::size_t t : p21) {
      bool above = true;
      for (int v : s.triangles[t]) above = above && f.m.corner(std::size_t(v))[1] >= 5;
      if (above) upper.push_back(t);
    }
    copy_vertices(s, upper, [&](int v) {
      const auto c = f.m.corner(std::size_t(v));
      return c[1] == 5 && c[2] > 2 && c[2] < 7;
    });
    check_refused(s, f.img, Cert::kInterfaces, "interface 2|1: 2 patches, K(X) has 1");
    // A mesher refines where it fails: on every triangle of the stray
    // piece (where it parted from the rest lies on its border).
    const Cert c = certify(s, f.img);
    const auto places = c.failing_places(s.points, s.triangles, s.pairs, interface_complex(f.img), f.img);
    const auto in = std::find_if(c.interfaces.begin(), c.interfaces.end(), [](const Cert::Interface& i) { return i.name() == "2|1"; });
    REQUIRE(in != c.interfaces.end());
    REQUIRE(in->patches.size() == 2);
    const std::size_t stray_first = in->patches[in->patches[0].triangles >= in->patches[1].triangles ? 1 : 0].first_triangle;
    std::vector<std::size_t> lower;
    for (std::size_t t : p21)
      if (std::find(upper.begin(), upper.end(), t) == upper.end()) lower.push_back(t);
    const std::vector<std::size_t>& piece =
        std::find(upper.begin(), upper.end(), stray_first) != upper.end() ? upper : lower;
    REQUIRE(piece.size() > 1);
    for (std::size_t t : piece) {
      Vec3 m{0, 0, 0};
      for (int v : s.triangles[t])
        for (int a = 0; a < 3; ++a) m[a] += s.points[std::size_t(v)][a] / 3;
      CHECK(std::find(places.begin(), places.end(), m) != places.end());
    }
  }
  SECTION("two labels swapped on a patch") {
    Soup s = f.s;
    for (std::size_t t : p21) s.pairs[t] = {1, 2};
    check_refused(s, f.img, Cert::kLabels, "label 1: oriented: ");
  }
  SECTION("a patch given another label") {
    Soup s = f.s;
    for (std::size_t t : p21) s.pairs[t] = {2, 0};
    check_refused(s, f.img, Cert::kInterfaces, "interface 2|1: 0 patches, K(X) has 1");
  }
  SECTION("one triangle flipped") {
    Soup s = f.s;
    std::swap(s.triangles[p21[3]][1], s.triangles[p21[3]][2]);
    check_refused(s, f.img, Cert::kLabels, "label 1: oriented: ");
  }
  SECTION("a label the image does not have") {
    Soup s = f.s;
    for (std::size_t t : f.of_pair(3, 0)) s.pairs[t] = {7, 0};
    check_refused(s, f.img, Cert::kInterfaces, "interface 3|0: 0 patches, K(X) has 1");
  }
}

TEST_CASE("interface certificate: where a large patch's holes merged, their curves are the places", "[surfacenets]") {
  // A plane of 2|1 (20 x 20 faces: too large to refine all over) with two
  // one-face holes, where single voxels of 3 touch 1, two faces apart.
  LabelImage img = label_grid(24, 24, 12);
  paint(img, {2, 2, 2}, {21, 21, 5}, 1);
  paint(img, {2, 2, 6}, {21, 21, 9}, 2);
  paint(img, {8, 11, 6}, {8, 11, 6}, 3);
  paint(img, {11, 11, 6}, {11, 11, 6}, 3);
  const InterfaceComplex k = interface_complex(img);
  REQUIRE(k.failed_guarantee().empty());
  Soup s = soup_of(interface_mesh(img, k));
  REQUIRE(certify(s, img).ok());
  // The strip of 2|1 between the holes cut: their two loops one.
  std::vector<std::size_t> strip;
  for (std::size_t t = 0; t < s.triangles.size(); ++t) {
    Vec3 m{0, 0, 0};
    for (int v : s.triangles[t])
      for (int a = 0; a < 3; ++a) m[a] += s.points[std::size_t(v)][a] / 3;
    if (s.pairs[t] == std::array<std::int32_t, 2>{2, 1} && m[0] > 8.5 && m[0] < 10.5 && m[1] > 10.5 && m[1] < 11.5)
      strip.push_back(t);
  }
  REQUIRE(strip.size() == 4);
  erase(s, strip);
  const Cert c = certify(s, img);
  REQUIRE(!c.ok());
  const auto places = c.failing_places(s.points, s.triangles, s.pairs, k, img);
  // The midpoints of both holes' four edges (world = voxel coordinates here).
  for (double x : {8.0, 11.0})
    for (const auto& d : {std::array<double, 2>{-0.5, 0}, {0.5, 0}, {0, -0.5}, {0, 0.5}}) {
      const Vec3 w{x + d[0], 11 + d[1], 5.5};
      INFO("x " << w[0] << " y " << w[1]);
      CHECK(std::any_of(places.begin(), places.end(), [&](const Vec3& p) {
        return std::abs(p[0] - w[0]) + std::abs(p[1] - w[1]) + std::abs(p[2] - w[2]) < 1e-9;
      }));
    }
}

TEST_CASE("interface certificate: a vertex moved out of its cell, a|b crossing c|d", "[surfacenets]") {
  const LabelImage img = four_labels_around_an_edge();
  const InterfaceComplex k = interface_complex(img);
  const InterfaceMesh m = interface_mesh(img, k);
  Soup s = soup_of(m);
  REQUIRE(certify(s, img).ok());
  // Corner (4, 5, 2), on the curve 4|1|0 at the bottom of patch 4|1,
  // moved 1.4, 0.7, -0.7 voxels (its cell reaches half a voxel each way):
  // a triangle of 4|1 crosses one of 3|0.
  const std::uint64_t corner = 4 + m.lattice[0] * (5 + m.lattice[1] * 2);
  const auto v = std::size_t(std::lower_bound(m.corners.begin(), m.corners.end(), corner) - m.corners.begin());
  REQUIRE(m.corners[v] == corner);
  s.points[v] = {s.points[v][0] + 1.4, s.points[v][1] + 0.7, s.points[v][2] - 0.7};
  const Cert c = certify(s, img);
  INFO(c.failure());
  CHECK(c.first_failed() == Cert::kIntersections);
  const auto a = s.pairs[c.intersections.first[0]], b = s.pairs[c.intersections.first[1]];
  CHECK(std::find(b.begin(), b.end(), a[0]) == b.end());
  CHECK(std::find(b.begin(), b.end(), a[1]) == b.end());
}

TEST_CASE("interface certificate: the crossings added later, the same certificate", "[surfacenets]") {
  // The conforming mesher's rounds certify without the crossings; the one
  // certificate kept gets them after (label_surface_nets.cpp).
  const LabelImage img = four_labels_around_an_edge();
  const InterfaceComplex k = interface_complex(img);
  const InterfaceMesh m = interface_mesh(img, k);
  for (const double move : {0.0, 1.4}) {  // none; a|b crossing c|d (the test above)
    Soup s = soup_of(m);
    const std::uint64_t corner = 4 + m.lattice[0] * (5 + m.lattice[1] * 2);
    const auto v = std::size_t(std::lower_bound(m.corners.begin(), m.corners.end(), corner) - m.corners.begin());
    s.points[v] = {s.points[v][0] + move, s.points[v][1] + move / 2, s.points[v][2] - move / 2};
    const Cert full = certify(s, img);
    CHECK(full.ok() == (move == 0));
    InterfaceCertificateOptions without;
    without.check_crossings = false;
    Cert c = certify_interface_mesh(s.points, s.triangles, s.pairs, img, k, without);
    CHECK(c.state[Cert::kIntersections] == -1);
    CHECK_FALSE(c.ok());  // never holds unchecked
    CHECK(c.failing_places(s.points, s.triangles, s.pairs, k, img) == full.failing_places(s.points, s.triangles, s.pairs, k, img));
    add_crossings(c, s.points, s.triangles, s.pairs);
    CHECK(c.to_json().dump() == full.to_json().dump());
  }
}

TEST_CASE("interface certificate: a split pinch is refused", "[surfacenets]") {
  const LabelImage img = pinched_block();
  const InterfaceComplex k = interface_complex(img);
  const InterfaceMesh m = interface_mesh(img, k);
  Soup s = soup_of(m);
  // The centre corner (1, 1, 1) of the 3x3x3 lattice; the fan of patch 3|0
  // there in the plane z = 1 (the face between voxels (0,1,1) and (0,1,0))
  // moved onto a copy of it.
  const std::uint64_t centre = 1 + 3 * (1 + 3 * 1);
  const int v = int(std::lower_bound(m.corners.begin(), m.corners.end(), centre) - m.corners.begin());
  REQUIRE(m.corners[std::size_t(v)] == centre);
  std::vector<std::size_t> fan;
  for (std::size_t t = 0; t < s.triangles.size(); ++t) {
    if (s.pairs[t] != std::array<std::int32_t, 2>{3, 0}) continue;
    bool flat = true;  // all corners at z = 1
    for (int w : s.triangles[t]) flat = flat && m.corner(std::size_t(w))[2] == 1;
    if (flat) fan.push_back(t);
  }
  REQUIRE(!fan.empty());
  copy_vertices(s, fan, [v](int w) { return w == v; });
  check_refused(s, img, Cert::kInterfaces, "interface 3|0: the patch of triangle");
  const Cert c = certify(s, img);
  CHECK(c.failure().find("Euler characteristic") != std::string::npos);
}

TEST_CASE("interface certificate: bad input refused", "[surfacenets]") {
  Fixture f;
  Soup s = f.s;
  s.pairs.pop_back();
  CHECK_THROWS_AS(certify(s, f.img), Error);
  s = f.s;
  s.triangles[0][1] = s.triangles[0][0];
  CHECK_THROWS_AS(certify(s, f.img), Error);
  s = f.s;
  s.triangles[0][1] = int(s.points.size());
  CHECK_THROWS_AS(certify(s, f.img), Error);
  LabelImage bad = label_grid(4, 4, 4);
  bad(1, 1, 1) = 1;
  bad(2, 2, 1) = 1;  // a C1 of label 1
  CHECK_THROWS_AS(certify(Soup{}, bad), Error);
}
