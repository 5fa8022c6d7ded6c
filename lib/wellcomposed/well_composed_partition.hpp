// Well-composed partitions (issue 36): a label image in which every label's
// indicator {X = L}, and the background's {X = 0}, has no critical
// configuration C1 or C2 (thesis 4.2, 5.1), every voxel still carrying one
// label. Voxels outside the grid are background (label 0). The binary
// repair of well_composed.hpp is the case of two labels.
//
// count_label_critical_configurations(): per label, the C1/C2 counts of its
// indicator, in one pass over the 2x2x2 blocks (a block's configurations
// for L depend only on which of its voxels carry L).
// make_well_composed_partition(): the repair, see well_composed_partition.cpp
// for why it terminates and why no configuration is left. 2D images: the
// diagonal 2x2 pattern, counted as C1.
#pragma once
#include "image/grid.hpp"
#include "util/json.hpp"
#include "wellcomposed/well_composed.hpp"

#include <array>
#include <cstddef>
#include <cstdint>
#include <map>
#include <string>
#include <utility>
#include <vector>

namespace imgmesh {

struct LabelCriticalCounts {
  // The label values: labels[0] is the background 0 (present or not), then
  // the other values of the image in increasing order; counts[i] those of
  // the indicator of labels[i] (for 0, of the union of the others).
  std::vector<std::int32_t> labels;
  std::vector<CriticalCounts> counts;
  std::size_t total() const;
  std::size_t labels_with_configurations() const;
  Json to_json() const;  // {"c1", "c2", "labels_left": [values with any left], "per_label": {...}}
};

// Throws Error on an image that is not 2D/3D, too large, or of more than
// 65535 labels besides 0.
LabelCriticalCounts count_label_critical_configurations(const LabelImage& img);

struct PartitionOptions {
  // A label with fewer voxels than this in the input may vanish; every
  // other label of the input keeps at least one voxel (the repair prefers
  // choices that keep a label's last voxel and, if it must, raises that
  // label's priority once). 0 or 1: every label is kept.
  std::size_t min_voxels = 0;
  // Which label of a configuration grows: the background always yields;
  // Smaller: the label of fewer input voxels ranks higher (small structures
  // grow, never thin out); Larger: the reverse (a few % fewer changes on
  // noisy maps, small labels shrink).
  enum class Priority { Smaller, Larger };
  Priority priority = Priority::Smaller;
  // Prune: after the repair, every changed voxel goes back to its input
  // label when that creates no configuration (fewer changes).
  bool prune = true;
  // 3D: then, as far as single moves creating no C1/C2 reach, no voxel edge
  // with four labels around it and no patch of K(X) pinched at a corner
  // (configurations no smooth partition has: well_composed_partition.cpp),
  // so the conforming meshers can match K(X).
  bool generic = true;
  // Tests only: false pads but does not repair (img2wc's hidden --skip-repair);
  // max_steps stops the repair after that many relabellings.
  bool repair = true;
  std::size_t max_steps = std::size_t(-1);
};

struct PartitionResult {
  // Every label's indicator well-composed; grown by one background voxel on
  // each side where a label touched the border (origin moved; world
  // coordinates exact).
  LabelImage image;
  std::array<std::size_t, 3> padded_before{0, 0, 0}, padded_after{0, 0, 0};
  LabelCriticalCounts input, output;  // output: recounted on image, the guarantee checked
  std::size_t input_voxels = 0;
  // Voxels whose label differs between input and output (a voxel moved
  // twice counts once, from its input label to its output label), per
  // (from, to) pair of label values.
  std::size_t changed = 0;
  std::map<std::pair<std::int32_t, std::int32_t>, std::size_t> changes;
  std::size_t steps = 0;       // relabellings made by the repair (before pruning)
  std::size_t promotions = 0;  // labels raised to the top rank to keep their last voxel
  std::vector<std::int32_t> lost;  // labels of the input with no voxel left (none unless min_voxels)
  std::vector<std::int32_t> lost_protected;  // of those, labels of at least min_voxels voxels: a failed guarantee
  PartitionOptions options;

  Json to_json() const;
  std::string failed_guarantee() const;  // configurations left, or a kept label lost
};

// Throws Error on an image that is not 2D/3D, too large, or of more than
// 65535 labels besides 0. `in` by value: moved in, its storage becomes the
// output's when the grid does not grow.
PartitionResult make_well_composed_partition(LabelImage in, const PartitionOptions& opt = {});

// img2wc --labels --check: the counts of a label image. Configurations
// left are a failed guarantee (exit 3): the check is the partition's
// certificate.
struct PartitionCheck {
  int dimension = 3;
  std::size_t voxels = 0;
  LabelCriticalCounts counts;
  Json to_json() const;
  std::string failed_guarantee() const;
};
PartitionCheck check_well_composed_partition(const LabelImage& img);

} // namespace imgmesh
