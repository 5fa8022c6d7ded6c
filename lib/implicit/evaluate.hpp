// implicit-eval's two modes: f (and grad f) at points given as text, and f
// at N random points of the domain as a benchmark (thesis Table 6.1).
#pragma once
#include "implicit/partition_of_unity.hpp"
#include "util/json.hpp"

#include <array>
#include <cstddef>
#include <cstdint>
#include <iosfwd>
#include <string>

namespace imgmesh {

struct PointEvaluation {
  std::array<std::size_t, 3> size{0, 0, 0};  // of f's grid
  Vec3 d{0, 0, 0};
  std::size_t points = 0, outside = 0;
  double seconds = 0;  // reading, evaluating and writing
  Json to_json() const;
  std::string failed_guarantee() const { return ""; }
};

// Reads 'x y z' lines (world coordinates; '#' starts a comment, commas and
// tabs separate like blanks, blank lines are skipped) and writes one line
// each: f, or 'f gx gy gz' with gradient, in %.17g. A point outside the
// domain is an Error, or nan with allow_outside. Errors name `source`.
PointEvaluation evaluate_points(const PartitionOfUnity& f, std::istream& in, std::ostream& out, bool gradient,
                                bool allow_outside, const std::string& source);

struct RandomEvaluation {
  std::array<std::size_t, 3> size{0, 0, 0};
  Vec3 d{0, 0, 0};
  std::uint64_t evaluations = 0, seed = 0;
  bool gradient = false;
  unsigned threads = 1;
  double seconds = 0, cpu_seconds = 0;
  double checksum = 0, gradient_checksum = 0;  // sums of f, of the gradients' components
  Json to_json() const;
  std::string failed_guarantee() const { return ""; }
};

// Point i is a function of (seed, i) only, and blocks are summed in order, so
// the checksums do not depend on the number of threads.
RandomEvaluation evaluate_random(const PartitionOfUnity& f, std::uint64_t n, std::uint64_t seed, bool gradient,
                                 unsigned threads);

} // namespace imgmesh
