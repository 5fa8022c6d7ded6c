// A set of integers in [0, n) as one bit each, and each member's rank (how
// many members are below it) in constant time: an eighth of a byte an
// integer plus a count every 64. For numbering the corners a set of faces
// touches in ascending order (surface nets, voxel boundaries) without
// sorting four ids a face.
#pragma once
#include <cstddef>
#include <cstdint>
#include <vector>

namespace imgmesh {

class RankedBits {
public:
  explicit RankedBits(std::uint64_t n) : bits_((n + 63) / 64, 0), before_(bits_.size() + 1, 0) {}
  void set(std::uint64_t i) { bits_[i >> 6] |= std::uint64_t(1) << (i & 63); }
  // After the last set: the counts before each word.
  void rank() {
    for (std::size_t w = 0; w < bits_.size(); ++w) before_[w + 1] = before_[w] + std::uint64_t(__builtin_popcountll(bits_[w]));
  }
  // After rank(): the members, and the members below i.
  std::uint64_t count() const { return before_.back(); }
  std::uint64_t operator()(std::uint64_t i) const {
    return before_[i >> 6] + std::uint64_t(__builtin_popcountll(bits_[i >> 6] & ((std::uint64_t(1) << (i & 63)) - 1)));
  }
  // The members, ascending, appended to out.
  void list(std::vector<std::uint64_t>& out) const {
    out.reserve(out.size() + count());
    for (std::size_t w = 0; w < bits_.size(); ++w)
      for (std::uint64_t b = bits_[w]; b; b &= b - 1) out.push_back(64 * w + std::uint64_t(__builtin_ctzll(b)));
  }

private:
  std::vector<std::uint64_t> bits_, before_;
};

} // namespace imgmesh
