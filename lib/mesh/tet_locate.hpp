// Where a label image's voxel centres lie in a tetrahedral mesh with a
// region per label (meshinfo's certificate of a multi-region mesh against a
// label map, seg2tet's "every voxel centre in a tetrahedron of its own
// label" for any mesh). Exact orientation tests (CGAL's filtered
// predicates, in tet_locate.cpp only): a centre on a face, edge or vertex is
// in every tetrahedron there.
#pragma once
#include "image/grid.hpp"
#include "mesh/tet_mesh.hpp"
#include "util/json.hpp"

#include <array>
#include <cstddef>
#include <cstdint>
#include <string>

namespace imgmesh {

struct VoxelCentreLocation {
  std::size_t checked = 0;          // every voxel of the image
  std::size_t outside = 0;          // of a label but 0, in no tetrahedron
  std::size_t in_other = 0;         // in a tetrahedron of another region (label 0: of a region but 0); not in outside
  std::size_t wrong() const { return outside + in_other; }
  // The first wrong one in the image's order: its voxel, label, and the
  // region of a tetrahedron of another region it lies in (-1: none).
  std::array<std::size_t, 3> first{0, 0, 0};
  std::int32_t first_label = 0;
  long long first_region = -1;
  std::string failure() const;  // "" when none is wrong
  Json to_json() const;
};

// Every voxel centre of `labels` (world coordinates: labels.world) against
// the tetrahedra of `mesh`, region = label: a centre of label L > 0 must lie
// in a tetrahedron of region L and in none of another; a centre of label 0
// in none, or only in region 0's. Tetrahedra not positively oriented
// contain nothing (tet_conformity counts them).
VoxelCentreLocation locate_voxel_centres(const TetMesh& mesh, const LabelImage& labels);

} // namespace imgmesh
