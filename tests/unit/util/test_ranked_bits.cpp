// RankedBits (ranked_bits.hpp): on random sets of integers, of sizes about
// the 64-bit words' boundaries, every rank, the count and the listing are
// those of the set counted one by one.
#include "util/ranked_bits.hpp"

#include <catch2/catch.hpp>

#include <cstdint>
#include <random>
#include <set>
#include <vector>

using namespace imgmesh;

TEST_CASE("RankedBits: ranks, count and listing of random sets", "[util]") {
  std::mt19937_64 rng(39);
  for (std::uint64_t n : {1, 2, 63, 64, 65, 127, 128, 129, 1000}) {
    for (double density : {0.0, 0.05, 0.5, 1.0}) {
      INFO("n " << n << ", density " << density);
      std::set<std::uint64_t> members;
      RankedBits bits(n);
      std::bernoulli_distribution in(density);
      for (std::uint64_t i = 0; i < n; ++i)
        if (in(rng)) members.insert(i), bits.set(i);
      bits.set(n - 1);  // the last word's last member
      members.insert(n - 1);
      bits.rank();
      CHECK(bits.count() == members.size());
      std::uint64_t below = 0;
      for (std::uint64_t i = 0; i < n; ++i) {
        REQUIRE(bits(i) == below);
        below += members.count(i);
      }
      std::vector<std::uint64_t> listed{7};  // appended after what is there
      bits.list(listed);
      CHECK(listed == [&] {
        std::vector<std::uint64_t> v{7};
        v.insert(v.end(), members.begin(), members.end());
        return v;
      }());
    }
  }
}
