// The persistent pool behind parallel_for: every index once, whatever the
// number of threads; uneven work spread over the threads; exceptions and
// nested loops.
#include "implicit/parallel.hpp"

#include <catch2/catch.hpp>

#include <atomic>
#include <chrono>
#include <set>
#include <stdexcept>
#include <thread>

using imgmesh::implicit_detail::parallel_for;

TEST_CASE("parallel_for visits every index once, in order within a chunk", "[parallel]") {
  for (unsigned threads : {1u, 2u, 3u, 7u}) {
    for (long n : {0L, 1L, 5L, 1000L, 100003L}) {
      std::vector<int> seen(std::size_t(n), 0);
      std::atomic<long> chunks{0};
      parallel_for(n, threads, [&](long a, long b, unsigned t) {
        CHECK(t < threads);
        CHECK(a <= b);
        for (long k = a; k < b; ++k) ++seen[std::size_t(k)];
        ++chunks;
      });
      for (long k = 0; k < n; ++k) REQUIRE(seen[std::size_t(k)] == 1);
      if (threads > 1 && n >= 1000) CHECK(chunks.load() > long(threads));  // dynamic: many chunks
    }
  }
}

TEST_CASE("parallel_for balances uneven work over its threads", "[parallel]") {
  // The first index is slow: with a static split the first thread would
  // also get half the rest; here the others take them meanwhile.
  std::vector<unsigned> by(64, 99);
  parallel_for(64, 2, [&](long a, long b, unsigned t) {
    for (long k = a; k < b; ++k) {
      if (k == 0) std::this_thread::sleep_for(std::chrono::milliseconds(200));
      by[std::size_t(k)] = t;
    }
  });
  long other = 0;
  for (unsigned t : by) other += t != by[0];
  CHECK(other >= 48);
}

TEST_CASE("parallel_for rethrows a body's exception and stays usable", "[parallel]") {
  CHECK_THROWS_AS(parallel_for(1000, 3, [](long a, long b, unsigned) {
                    for (long k = a; k < b; ++k)
                      if (k == 777) throw std::runtime_error("boom");
                  }),
                  std::runtime_error);
  std::atomic<long> sum{0};
  parallel_for(1000, 3, [&](long a, long b, unsigned) {
    for (long k = a; k < b; ++k) sum += k;
  });
  CHECK(sum.load() == 999L * 1000 / 2);
}

TEST_CASE("a parallel_for inside a parallel_for runs", "[parallel]") {
  std::atomic<long> count{0};
  parallel_for(8, 2, [&](long a, long b, unsigned) {
    for (long k = a; k < b; ++k)
      parallel_for(100, 2, [&](long c, long d, unsigned) { count += d - c; });
  });
  CHECK(count.load() == 800);
}
