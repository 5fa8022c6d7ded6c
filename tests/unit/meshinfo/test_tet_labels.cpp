// A multi-region tetrahedral mesh against a label map (meshinfo TETS
// --image LABELS): a small map's voxels as cubes of six tetrahedra each,
// region = label, certified; a flipped tetrahedron, a region that is no
// label, a label without a region, a voxel centre in another label's
// tetrahedron and a gap between two regions each refused, naming its check.
#include "meshinfo/meshinfo.hpp"
#include "meshinfo/tet_labels.hpp"

#include <catch2/catch.hpp>

#include <algorithm>
#include <map>

using namespace imgmesh;

namespace {

// 5 x 4 x 4 voxels, anisotropic: label 1 a 2x2x2 block, label 2 a 1x2x2
// block beside it, background around.
LabelImage two_blocks() {
  Geometry g;
  g.size = {5, 4, 4};
  g.spacing = {1.0, 1.5, 0.75};
  g.origin = {-3, 2, 1};
  LabelImage x(g, 0);
  for (std::size_t k = 1; k <= 2; ++k)
    for (std::size_t j = 1; j <= 2; ++j) {
      x(1, j, k) = x(2, j, k) = 1;
      x(3, j, k) = 2;
    }
  return x;
}

// Every voxel of a label as its cube of six tetrahedra around the diagonal
// from its lower corner (Kuhn's triangulation: conforming across cubes),
// region = label; corners shared between cubes unless apart(label).
TetMesh voxel_tets(const LabelImage& x, int apart = -1) {
  TetMesh m;
  std::map<std::array<long long, 4>, int> id;
  auto corner = [&](std::size_t i, std::size_t j, std::size_t k, int label) {
    const std::array<long long, 4> key{(long long)i, (long long)j, (long long)k, label == apart ? label : -1};
    auto [it, added] = id.try_emplace(key, int(m.points.size()));
    if (added) m.points.push_back(x.world(double(i) - 0.5, double(j) - 0.5, double(k) - 0.5));
    return it->second;
  };
  const int perms[6][3] = {{0, 1, 2}, {0, 2, 1}, {1, 0, 2}, {1, 2, 0}, {2, 0, 1}, {2, 1, 0}};
  for (std::size_t k = 0; k < x.size[2]; ++k)
    for (std::size_t j = 0; j < x.size[1]; ++j)
      for (std::size_t i = 0; i < x.size[0]; ++i) {
        const int label = x(i, j, k);
        if (label == 0) continue;
        for (const auto& p : perms) {
          std::array<std::size_t, 3> c{i, j, k};
          std::array<int, 4> t{};
          t[0] = corner(c[0], c[1], c[2], label);
          for (int s = 0; s < 3; ++s) {
            ++c[std::size_t(p[s])];
            t[std::size_t(s + 1)] = corner(c[0], c[1], c[2], label);
          }
          const auto& q = m.points;
          if (tet_orient(q[std::size_t(t[0])], q[std::size_t(t[1])], q[std::size_t(t[2])], q[std::size_t(t[3])]) < 0)
            std::swap(t[2], t[3]);
          m.tets.push_back(t);
          m.tet_region.push_back(label);
        }
      }
  return m;
}

int first_failed(const TetMesh& m, const LabelImage& x) { return certify_tet_labels(m, x).first_failed(); }

} // namespace

TEST_CASE("a map's voxels as tetrahedra, region = label: certified, a line per region", "[meshinfo][tet_labels]") {
  const LabelImage x = two_blocks();
  const TetMesh m = voxel_tets(x);
  const TetLabelCertificate c = certify_tet_labels(m, x);
  INFO(c.failure());
  CHECK(c.ok());
  CHECK(c.centres.checked == 80);
  CHECK(c.interfaces.interfaces.size() == 3);  // 1|0, 2|0, 2|1
  const MeshInfo info = label_tet_mesh_info(m, "m.msh", x, "x.nrrd");
  CHECK(info.failed_guarantee().empty());
  CHECK(info.report.at("certificate").at("verdict").string() == "ok");
  const Json& regions = info.report.at("tetrahedra").at("regions");
  REQUIRE(regions.items().size() == 2);
  const double voxel = 1.0 * 1.5 * 0.75;
  CHECK(regions.items()[0].at("tetrahedra").integer() == 8 * 6);
  CHECK(regions.items()[0].at("volume").number() == Approx(8 * voxel));
  CHECK(regions.items()[1].at("voxel_volume").number() == Approx(4 * voxel));
  CHECK(regions.items()[1].at("volume_ratio").number() == Approx(1));
  CHECK(format_report(info.report).find("region 2: 24 tetrahedra") != std::string::npos);
}

TEST_CASE("a tetrahedron flipped: refused on orientation", "[meshinfo][tet_labels]") {
  const LabelImage x = two_blocks();
  TetMesh m = voxel_tets(x);
  std::swap(m.tets[7][2], m.tets[7][3]);
  CHECK(first_failed(m, x) == TetLabelCertificate::kOrientation);
  const MeshInfo info = label_tet_mesh_info(m, "m.msh", x, "x.nrrd");
  CHECK(info.failed_guarantee().find("orientation: 1 of 72 tetrahedra") != std::string::npos);
}

TEST_CASE("a tetrahedron moved to a region that is no label: refused on regions", "[meshinfo][tet_labels]") {
  const LabelImage x = two_blocks();
  TetMesh m = voxel_tets(x);
  m.tet_region[3] = 7;
  const TetLabelCertificate c = certify_tet_labels(m, x);
  CHECK(c.first_failed() == TetLabelCertificate::kRegions);
  CHECK(c.failure() == "regions: region(s) 7 not a label of the map");
}

TEST_CASE("a label's region missing: refused on regions, naming the label", "[meshinfo][tet_labels]") {
  const LabelImage x = two_blocks();
  TetMesh m = voxel_tets(x);
  for (std::size_t t = m.tets.size(); t-- > 0;)
    if (m.tet_region[t] == 2) {
      m.tets.erase(m.tets.begin() + std::ptrdiff_t(t));
      m.tet_region.erase(m.tet_region.begin() + std::ptrdiff_t(t));
    }
  const TetLabelCertificate c = certify_tet_labels(m, x);
  CHECK(c.first_failed() == TetLabelCertificate::kRegions);
  CHECK(c.failure() == "regions: label(s) 2 with no region");
}

TEST_CASE("a voxel centre in a tetrahedron of another label: refused on voxel centres", "[meshinfo][tet_labels]") {
  const LabelImage x = two_blocks();
  TetMesh m = voxel_tets(x);
  // The first cube is voxel (1, 1, 1)'s; its centre lies on the diagonal
  // all six tetrahedra share.
  m.tet_region[2] = 2;
  const TetLabelCertificate c = certify_tet_labels(m, x);
  CHECK(c.first_failed() == TetLabelCertificate::kVoxelCentres);
  CHECK(c.centres.in_other == 1);
  CHECK(c.centres.first == std::array<std::size_t, 3>{1, 1, 1});
  CHECK(c.centres.first_region == 2);
  // That cube's six tetrahedra gone: its centre in none.
  m.tets.erase(m.tets.begin(), m.tets.begin() + 6);
  m.tet_region.erase(m.tet_region.begin(), m.tet_region.begin() + 6);
  const TetLabelCertificate gone = certify_tet_labels(m, x);
  CHECK(gone.first_failed() == TetLabelCertificate::kVoxelCentres);
  CHECK(gone.centres.outside == 1);
  CHECK(gone.centres.in_other == 0);
  CHECK(gone.centres.first_region == -1);
}

TEST_CASE("two regions apart (a gap where they should touch): refused on interfaces", "[meshinfo][tet_labels]") {
  const LabelImage x = two_blocks();
  TetMesh m = voxel_tets(x, 2);  // label 2's cubes on their own corners
  const Vec3 shift = x.world(0.2, 0, 0), o = x.world(0, 0, 0);
  std::vector<bool> moved(m.points.size(), false);
  for (std::size_t t = 0; t < m.tets.size(); ++t)
    if (m.tet_region[t] == 2)
      for (int v : m.tets[t])
        if (!moved[std::size_t(v)]) {
          moved[std::size_t(v)] = true;
          for (int i = 0; i < 3; ++i) m.points[std::size_t(v)][std::size_t(i)] += shift[std::size_t(i)] - o[std::size_t(i)];
        }
  const TetLabelCertificate c = certify_tet_labels(m, x);
  INFO(c.failure());
  CHECK(c.first_failed() == TetLabelCertificate::kInterfaces);
  CHECK(c.failure().rfind("interfaces: interface ", 0) == 0);
  const auto& i = c.interfaces.interfaces;
  const auto p21 = std::find_if(i.begin(), i.end(), [](const auto& f) { return f.name() == "2|1"; });
  REQUIRE(p21 != i.end());
  CHECK(p21->triangles == 0);  // K(X)'s 2|1 with nothing of the mesh on it
  CHECK(!p21->why.empty());
}
