// The exact predicates (lib/quad/predicates.cpp): strict convexity and
// orientation, right where floating point is not.
#include "quad/predicates.hpp"

#include "quad/quality.hpp"

#include <catch2/catch.hpp>

#include <cmath>

using namespace imgmesh;

TEST_CASE("strict convexity is exact and rejects every bad shape", "[quality]") {
  CHECK(is_strictly_convex({0, 0}, {1, 0}, {1, 1}, {0, 1}));
  CHECK_FALSE(is_strictly_convex({0, 0}, {0, 1}, {1, 1}, {1, 0}));     // clockwise
  CHECK_FALSE(is_strictly_convex({0, 0}, {1, 1}, {1, 0}, {0, 1}));     // bow-tie
  CHECK_FALSE(is_strictly_convex({0, 0}, {2, 0}, {0.5, 0.5}, {0, 2})); // dart (reflex at c)
  CHECK_FALSE(is_strictly_convex({0, 0}, {1, 0}, {2, 0}, {1, 1}));     // straight angle at b
  CHECK_FALSE(is_strictly_convex({0, 0}, {0, 0}, {1, 1}, {0, 1}));     // repeated vertex
  CHECK(scaled_jacobian({0, 0}, {2, 0}, {0.5, 0.5}, {0, 2}) < 0);
  // Points one ulp off the line y = x: the exact predicate gets the side right.
  const Point2 pa{0, 0}, pc{1, 1};
  CHECK(orientation(pa, pc, {0.1, std::nextafter(0.1, 1.0)}) == 1);
  CHECK(orientation(pa, pc, {0.1, std::nextafter(0.1, 0.0)}) == -1);
  CHECK(orientation(pa, pc, {0.1, 0.1}) == 0);
  CHECK(orientation(pc, pa, {0.1, std::nextafter(0.1, 1.0)}) == -1);
  // Far from the origin, where products lose the last bits.
  const double big = 1e15;
  CHECK(orientation({big, big}, {big + 2, big + 2}, {big + 1, big + 1}) == 0);
  CHECK(orientation({big, big}, {big + 2, big + 2}, {big + 1, std::nextafter(big + 1, 2 * big)}) == 1);
  CHECK(orientation({0, 0}, {1, 1}, {2, 2}) == 0);
  CHECK(orientation({0, 0}, {1, 0}, {0, 1}) == 1);
}
