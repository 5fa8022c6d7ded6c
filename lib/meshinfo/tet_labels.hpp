// A multi-region tetrahedral mesh of any origin (seg2tet's, CGAL Mesh_3's,
// a user's) certified against a label map (meshinfo TETS --image LABELS),
// region = label, the map repaired as seg2tet and seg2mesh repair it
// (make_well_composed_partition). The checks, in order; the verdict names
// the first that fails:
//
//   orientation    every tetrahedron positively oriented;
//   conformity     tet_conformity: no face in three tetrahedra, none
//                  traversed alike by two, no duplicate, no bad vertex id;
//   regions        the regions (0 aside: the background) are the map's
//                  labels, no label without a region, no region without a
//                  label;
//   voxel centres  every voxel centre in a tetrahedron of its own label, a
//                  background one in none or only in region 0's
//                  (mesh/tet_locate.hpp); it names the first wrong voxel;
//   interfaces     the faces between regions (region_interfaces: two
//                  regions, or one and nothing) as a surface with label
//                  pairs pass the interface certificate seg2mesh
//                  --conforming and seg2tet use (every pair's patches
//                  against K(X)'s, no two triangles crossing, each label's
//                  surface, voxel sides; surfacenets/interface_certificate.hpp).
// Every check runs (the interfaces only on a conforming mesh: else their
// surface is not defined).
#pragma once
#include "image/grid.hpp"
#include "mesh/tet_locate.hpp"
#include "mesh/tet_mesh.hpp"
#include "surfacenets/interface_certificate.hpp"
#include "util/json.hpp"

#include <array>
#include <cstdint>
#include <string>
#include <vector>

namespace imgmesh {

struct TetLabelCertificate {
  enum Check : int { kOrientation, kConformity, kRegions, kVoxelCentres, kInterfaces, kChecks };
  static const char* name(int check);  // "orientation", "conformity", "regions", "voxel centres", "interfaces"
  std::array<int, kChecks> state{};    // 1 held, 0 failed, -1 not run
  std::array<std::string, kChecks> why;
  TetConformity conformity;
  std::vector<std::int32_t> labels;                  // the repaired map's, 0 aside
  std::vector<long long> regions;                    // the mesh's, 0 aside
  std::vector<std::int32_t> labels_without_region;
  std::vector<long long> regions_without_label;
  VoxelCentreLocation centres;
  // The regions' interfaces as a surface (region_interfaces) and its certificate.
  std::vector<std::array<int, 3>> triangles;
  std::vector<std::array<std::int32_t, 2>> pairs;
  InterfaceCertificate interfaces;
  int first_failed() const;  // kChecks when every check holds
  bool ok() const { return first_failed() == kChecks; }
  std::string failure() const;  // "CHECK: why" of the first failed check; "" when ok
  Json to_json() const;
};

// `labels`: the repaired map (well-composed, as make_well_composed_partition
// leaves it), the mesh in its world coordinates.
TetLabelCertificate certify_tet_labels(const TetMesh& mesh, const LabelImage& labels,
                                       const InterfaceCertificateOptions& options = {});

} // namespace imgmesh
