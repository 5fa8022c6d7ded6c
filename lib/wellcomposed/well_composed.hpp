// Well-composed binary images (thesis chapter 5; Latecki's 2D analogue).
// A 3D binary image is well-composed when it has no critical configuration:
// C1, two foreground (or two background) voxels sharing only an edge in a
// 2x2x1 block N_x(r), N_y(r), N_z(r), the other two of the other colour; C2,
// two voxels sharing only a vertex in a 2x2x2 block N(r), the other six of the
// other colour. In 2D only the diagonal 2x2 pattern exists (counted as C1).
// make_well_composed() is the linear-time repair of chapter 5: a scan for
// critical configurations, the queue R, the candidate sets B(r), B1(r), B2(r),
// rules (1)-(3), and re-examination of the 4x4x4 grid G(r) only.
#pragma once
#include "image/grid.hpp"
#include "util/json.hpp"

#include <array>
#include <cstddef>
#include <cstdint>
#include <string>

namespace imgmesh {

struct CriticalCounts {
  std::size_t c1 = 0, c2 = 0;
  std::size_t total() const { return c1 + c2; }
};

// Count critical configurations of a 2D or 3D binary image (2D: the diagonal
// 2x2 pattern counts as c1; c2 = 0). Voxels outside the grid are background.
CriticalCounts count_critical_configurations(const BinaryImage& img);
bool is_well_composed(const BinaryImage& img);

enum class RepairMode { Add, Remove, Min };

struct WellComposedOptions {
  RepairMode mode = RepairMode::Add;
  std::uint64_t seed = 0;
  // Rules (2) and (3) draw only among the sets of B(r) that eliminate the
  // most critical configurations of G(r) per inserted point; gated first
  // passes take the points that serve several configurations first; a last
  // pass drops inserted points that became unnecessary. false: the thesis's
  // literal rules (draw among all of B1(r), resp. B2(r); one pass).
  bool greedy = true;
  // Tests only: false pads but does not repair, so that the final count
  // must find the critical configurations (img2wc's hidden --skip-repair).
  bool repair = true;
};

struct WellComposedResult {
  // Well-composed, grown by one voxel on each side where foreground touched
  // the border (origin moved; world coordinates exact).
  BinaryImage image;
  std::array<std::size_t, 3> padded_before{0, 0, 0}, padded_after{0, 0, 0};
  CriticalCounts input;      // #C1, #C2 of the input (Table 5.1)
  std::size_t changed = 0;   // |P|
  std::size_t created = 0;   // new critical configurations created during the repair (Table 5.1)
  RepairMode mode_used = RepairMode::Add;  // for Min: which one won
  WellComposedOptions options;             // as asked
  std::size_t input_voxels = 0;            // of the input grid
  CriticalCounts output;                   // counted on image: the guarantee, checked rather than assumed
  // The box of every voxel the repair set, in image's indices, those it
  // later took back too (a crop holding it with room around repairs as the
  // whole grid does); empty (lo > hi) when it set none.
  Index3 touched_lo{0, 0, 0}, touched_hi{-1, -1, -1};

  Json to_json() const;
  std::string failed_guarantee() const;  // when output has critical configurations left
};

// Throws Error on an image that is not 2D/3D or too large to index.
WellComposedResult make_well_composed(const BinaryImage& in, const WellComposedOptions& opt = {});

// img2wc --check: the counts of an image. Being not well-composed is its
// answer, not a failed guarantee.
struct WellComposedCheck {
  int dimension = 3;
  std::size_t voxels = 0;
  CriticalCounts counts;
  Json to_json() const;
  std::string failed_guarantee() const { return ""; }
};
WellComposedCheck check_well_composed(const BinaryImage& img);

} // namespace imgmesh
