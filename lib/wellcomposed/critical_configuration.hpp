// The local vocabulary of chapter 5: a 2x2x2 block N(r) as an 8-bit code, the
// critical configurations it holds, and the candidate sets B(r). Internal to
// the wellcomposed module (and its unit tests).
//
// Bit k of a block code is the colour (1 = foreground) of the point
// r + (k & 1, (k >> 1) & 1, (k >> 2) & 1). So bit 0 is r itself,
// N_x(r) = bits {0,2,4,6}, N_y(r) = {0,1,4,5}, N_z(r) = {0,1,2,3}.
#pragma once
#include <array>
#include <cstdint>

namespace imgmesh {
struct Geometry;
}

namespace imgmesh::wellcomposed_detail {

// CriticalConfiguration flags of one block: which of N_x(r), N_y(r), N_z(r)
// is an instance of (C1), and whether N(r) is an instance of (C2).
enum CriticalConfiguration : std::uint8_t {
  kC1x = 1,
  kC1y = 2,
  kC1z = 4,
  kC2 = 8,
};

// The flags above for a block code (table lookup).
std::uint8_t critical_configurations(std::uint8_t code);

// B(r) (section 5.2.4): the sets of background points of N(r) any one of which,
// made foreground, eliminates all instances of (C1) in N_x(r), N_y(r), N_z(r)
// or the instance of (C2) in N(r). Each set is a mask of block bits.
struct CandidateSets {
  std::uint8_t count = 0;
  std::array<std::uint8_t, 6> sets{};
};
const CandidateSets& candidate_sets(std::uint8_t code);

// Throws Error (naming `what`) unless g is a 2D or 3D grid small enough to
// index: each side 1 to 2^20 voxels, at most 2^40 voxels.
void check_size(const Geometry& g, const char* what);

} // namespace imgmesh::wellcomposed_detail
