// Shared by lib/implicit and lib/surface: parallel loops over index ranges on
// one persistent pool of threads (started once, not per pass), scheduled
// dynamically: threads take the next small chunk of [0, count) when done,
// so uneven work (FacetCycle's facets, HandleDetection's cells) balances.
// Deterministic as long as the body writes only to per-index slots or
// order-independent reductions (each chunk is processed in order).
#pragma once
#include <algorithm>
#include <atomic>
#include <condition_variable>
#include <exception>
#include <functional>
#include <mutex>
#include <thread>
#include <vector>

namespace imgmesh::implicit_detail {

inline unsigned resolve_threads(unsigned threads) {
  if (threads == 0) threads = std::max(1u, std::thread::hardware_concurrency());
  return std::min(threads, 256u);
}

class ThreadPool {
public:
  static ThreadPool& instance() {
    static ThreadPool pool;
    return pool;
  }
  ~ThreadPool() {
    {
      std::lock_guard<std::mutex> lock(m_);
      stop_ = true;
    }
    wake_.notify_all();
    for (auto& t : workers_) t.join();
  }

  // job(t) on t = 0 .. threads - 1 at once, t = 0 on the calling thread;
  // the first exception a job throws is rethrown once all have ended. A job
  // that calls run() again (nested) runs the inner one on its own thread.
  void run(unsigned threads, const std::function<void(unsigned)>& job) {
    if (threads <= 1 || inside_) {
      for (unsigned t = 0; t < threads; ++t) job(t);
      return;
    }
    std::lock_guard<std::mutex> one(run_);  // one parallel loop at a time
    {
      std::unique_lock<std::mutex> lock(m_);
      while (workers_.size() + 1 < threads) {
        const unsigned w = unsigned(workers_.size()) + 1;
        workers_.emplace_back([this, w] { work(w); });
      }
      job_ = &job;
      error_ = nullptr;
      active_ = threads;
      pending_ = threads - 1;
      ++generation_;
    }
    wake_.notify_all();
    inside_ = true;
    std::exception_ptr mine;
    try {
      job(0);
    } catch (...) {
      mine = std::current_exception();
    }
    inside_ = false;
    std::unique_lock<std::mutex> lock(m_);
    done_.wait(lock, [this] { return pending_ == 0; });
    job_ = nullptr;
    if (!mine) mine = error_;
    if (mine) std::rethrow_exception(mine);
  }

private:
  ThreadPool() = default;
  void work(unsigned w) {
    inside_ = true;
    unsigned long seen = 0;
    std::unique_lock<std::mutex> lock(m_);
    for (;;) {
      wake_.wait(lock, [&] { return stop_ || generation_ != seen; });
      if (stop_) return;
      seen = generation_;
      if (w >= active_) continue;
      const std::function<void(unsigned)>* job = job_;
      lock.unlock();
      std::exception_ptr e;
      try {
        (*job)(w);
      } catch (...) {
        e = std::current_exception();
      }
      lock.lock();
      if (e && !error_) error_ = e;
      if (--pending_ == 0) done_.notify_one();
    }
  }

  std::mutex run_, m_;
  std::condition_variable wake_, done_;
  std::vector<std::thread> workers_;
  const std::function<void(unsigned)>* job_ = nullptr;
  std::exception_ptr error_;
  unsigned active_ = 0, pending_ = 0;
  unsigned long generation_ = 0;
  bool stop_ = false;
  static inline thread_local bool inside_ = false;
};

// body(begin, end, thread_index) over [0, count) in chunks taken
// dynamically by `threads` threads; body runs once per chunk.
template <class F> void parallel_for(long count, unsigned threads, F&& body) {
  threads = resolve_threads(threads);
  if (threads <= 1 || count < 2) {
    body(0L, count, 0u);
    return;
  }
  threads = unsigned(std::min<long>(threads, count));
  const long chunk = std::max(1L, count / (long(threads) * 16));
  std::atomic<long> next{0};
  ThreadPool::instance().run(threads, [&](unsigned t) {
    for (long a; (a = next.fetch_add(chunk, std::memory_order_relaxed)) < count;)
      body(a, std::min(count, a + chunk), t);
  });
}

} // namespace imgmesh::implicit_detail
