// Shared by lib/implicit and lib/surface: a minimal static split of index ranges over
// std::thread (deterministic: each range is processed in order).
#pragma once
#include <algorithm>
#include <thread>
#include <vector>

namespace imgmesh::implicit_detail {

inline unsigned resolve_threads(unsigned threads) {
  if (threads == 0) threads = std::max(1u, std::thread::hardware_concurrency());
  return std::min(threads, 256u);
}

// body(begin, end, thread_index) over [0, count) split in `threads` ranges.
template <class F> void parallel_for(long count, unsigned threads, F&& body) {
  threads = resolve_threads(threads);
  if (threads <= 1 || count < 2) {
    body(0L, count, 0u);
    return;
  }
  std::vector<std::thread> pool;
  const long chunk = (count + long(threads) - 1) / long(threads);
  for (unsigned t = 0; t < threads; ++t) {
    const long a = long(t) * chunk, b = std::min(count, a + chunk);
    if (a >= b) break;
    pool.emplace_back([&body, a, b, t] { body(a, b, t); });
  }
  for (auto& th : pool) th.join();
}

} // namespace imgmesh::implicit_detail
