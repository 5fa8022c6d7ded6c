// seg2mesh --fast (issue 39): every label's surface at once, the shared
// interfaces meshed once. The stages, each timed:
//   repair       the chosen labels kept (the rest background), the
//                partition made well-composed (img2wc --labels all's
//                make_well_composed_partition), in memory;
//   complex      its interface complex K(X);
//   mesh         surface nets on K(X): a vertex per corner, a quad per
//                face split in two, each triangle with its (behind, front)
//                labels (surfacenets/surface_nets.hpp);
//   smoothing    `smooth_rounds` rounds inside each corner's cell, then
//                untangled (0: the voxel faces);
//   certificate  the interface certificate (surfacenets/interface_certificate.hpp):
//                every interface's patches against K(X)'s, no two triangles
//                crossing, each label's closed surface against its voxels.
// Then one SurfaceMesh: every triangle once with its pair, or, `separate`,
// each label's closed surface alone (its own vertices, interfaces twice)
// with a label per triangle.
#pragma once
#include "image/grid.hpp"
#include "conforming/conforming_surface.hpp"
#include "image/slicer_segmentation.hpp"
#include "mesh/surface_io.hpp"
#include "mesh/tet_mesh.hpp"
#include "surfacenets/interface_certificate.hpp"
#include "util/json.hpp"

#include <array>
#include <cstdint>
#include <functional>
#include <string>
#include <utility>
#include <vector>

namespace imgmesh {

struct LabelSurfaceNetsOptions {
  std::vector<long long> labels;  // empty: every nonzero value present
  LabelNames names;               // the labels' names where the image gives them
  int smooth_rounds = 5;          // >= 0
  bool separate = false;
  // Issue 40 (experimental): the restricted Delaunay complex of the
  // labelling function (conforming/conforming_surface.hpp) instead of
  // surface nets; smooth_rounds unused.
  bool conforming = false;
  ConformingOptions conforming_options;  // tets.on (seg2tet): the labels' tetrahedra too
  unsigned threads = 1;           // for the crossing searches and the certificate (the same result whatever their number)
  std::function<void(const std::string&)> progress;
};

struct LabelSurfaceNetsResult {
  std::vector<std::int32_t> labels;  // the labels meshed, ascending (their figures: meshed_labels())
  SurfaceMesh mesh;              // interfaces set (or labels, separate); label_names
  std::size_t changed = 0;       // voxels the repair relabelled
  std::array<std::size_t, 3> grid{0, 0, 0};  // the repaired grid (grown by a voxel where labels touch the side)
  Json complex = Json::object(); // K(X)'s counts
  Json conforming;                   // the conforming mesher's counts, when it ran (else null)
  // seg2tet (conforming_options.tets.on): the tetrahedra of every meshed
  // label (region = label; the interfaces as triangles, each once, of the
  // higher label, oriented out of it) and their certificate beside the
  // interfaces': conforming, the triangles exactly the regions' boundary
  // (boundary_mismatch), every tetrahedron's radius-edge ratio within R,
  // every voxel centre in a tetrahedron of its own label (label 0: in none).
  bool tetrahedra = false;
  TetMesh tets;
  TetConformity tet_conformity;
  TetQualityReport tet_quality;
  std::string tet_boundary_mismatch;
  double cell_ratio = 0;
  bool cell_refinement_stopped = false;  // rounds or points exhausted
  std::size_t centres_checked = 0, centres_wrong = 0;
  // tets.outside: region 0 fills the image box B too (its label 0 voxel
  // centres among those checked): the tetrahedra's volume B's (box_filled,
  // 1e-9 relative), the box triangles on B's faces and of its area
  // (box_covered); region 0's volume against the background's voxels.
  bool outside = false, box_filled = false, box_covered = false;
  double box_volume = 0, background_voxel_volume = 0;
  long long box_points = 0, box_refused = 0;
  int smooth_rounds = 0;
  bool separate = false;
  // Seconds of each stage, in order: repair, complex, mesh, smoothing, certificate.
  std::vector<std::pair<std::string, double>> seconds;
  InterfaceCertificate certificate;
  // Per meshed label its figures and surface certificate (voxels after the
  // repair, triangles, area, enclosed volume, voxel volume, components),
  // as the interface certificate found them; label 0 left out.
  std::vector<const InterfaceCertificate::Label*> meshed_labels() const;
  Json to_json() const;
  std::string failed_guarantee() const;  // the certificate's first failure, naming its label or pair
};

// Throws Error on a 2D image, one without labels, an asked label absent, a
// partition the repair cannot make (more than 65535 labels), a negative
// smooth_rounds.
LabelSurfaceNetsResult mesh_label_surface_nets(LabelImage image, const LabelSurfaceNetsOptions& options);

} // namespace imgmesh
