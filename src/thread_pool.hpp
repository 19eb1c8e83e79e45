// thread_pool.hpp - the only place that starts threads: a pool whose idle workers sleep.
//
// parallel_for(pool, n, f) calls f(i) for i in [0, n) on the pool's threads, the calling thread
// among them, and returns when all calls are done. Iterations are handed out in chunks of about
// n / (16 threads) as threads free up: the clouds are in Z-order (spatial_order.hpp), so
// contiguous ranges can differ much in work (a region whose points have no neighbours is
// cheap), and a static split into halves left one thread waiting (docs/PERFORMANCE.md).
// Callers' results do not depend on which thread runs an iteration: each f(i) writes only its
// own outputs, and reductions are summed afterwards in a fixed order. f must not throw.
//
// Why not OpenMP: GCC's runtime lets idle threads spin before they sleep unless the process sets
// OMP_WAIT_POLICY=passive, a process-wide setting a library must not make; two busy processes
// on two cores then ran 2.5x slower. A worker here waits on a condition variable between
// loops; the caller, done with the chunks, waits the same way for the workers still in one (a
// worker that wakes after the last chunk was handed out stays out of that loop). No global state:
// each Registration owns its pool, whose workers live as long as it does.
#pragma once

#include <algorithm>
#include <atomic>
#include <condition_variable>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <mutex>
#include <thread>
#include <type_traits>
#include <vector>

#include "ppcr/abi.hpp"

namespace ppcr {
inline namespace PPCR_ABI_NAMESPACE {
namespace detail {

class ThreadPool {
 public:
  /// A pool of `threads` threads in all: the caller and threads - 1 workers (none for 1 or less).
  explicit ThreadPool(int threads = 1);
  ~ThreadPool();
  ThreadPool(const ThreadPool&) = delete;
  ThreadPool& operator=(const ThreadPool&) = delete;

  /// The threads that run the loops: the caller and the workers started.
  int threads() const { return 1 + static_cast<int>(workers_.size()); }

  /// f(i) for i in [0, n), on every thread of the pool. Not re-entrant: one loop at a time, from
  /// one calling thread. Logically const (the threads are an implementation detail), so that a
  /// const pool serves const code.
  template <class F>
  void parallel_for(std::ptrdiff_t n, F&& f) const {
    if (workers_.empty() || n <= 1) {
      for (std::ptrdiff_t i = 0; i < n; ++i) f(i);
      return;
    }
    using Body = std::remove_reference_t<F>;
    const Range range = [](void* body, std::ptrdiff_t begin, std::ptrdiff_t end) noexcept {
      for (std::ptrdiff_t i = begin; i < end; ++i) (*static_cast<Body*>(body))(i);
    };
    run_loop(range, const_cast<void*>(static_cast<const void*>(std::addressof(f))), n);
  }

 private:
  using Range = void (*)(void* body, std::ptrdiff_t begin, std::ptrdiff_t end) noexcept;
  struct Loop {
    Range range = nullptr;
    void* body = nullptr;
    std::ptrdiff_t n = 0;
    std::ptrdiff_t chunk = 1;
  };

  void run_loop(Range range, void* body, std::ptrdiff_t n) const;
  void start_workers(int count);
  void work(const Loop& loop) const noexcept;  // with workers, a throwing body terminates
  void worker() const;

  mutable std::mutex mutex_;
  mutable std::condition_variable wake_;  // workers: a new loop, or stop
  mutable std::condition_variable done_;  // the caller: the last worker left the loop
  std::vector<std::thread> workers_;
  mutable bool stop_ = false;
  mutable std::uint64_t generation_ = 0;  // loops started
  mutable bool open_ = false;             // the current loop takes workers
  mutable int joined_ = 0;                // workers in the current loop
  mutable Loop loop_;
  mutable std::atomic<std::ptrdiff_t> next_{0};  // the first iteration not yet handed out
};

/// f(i) for i in [0, n) on the pool's threads, or on the calling thread alone when pool is null.
template <class F>
void parallel_for(const ThreadPool* pool, std::ptrdiff_t n, F&& f) {
  if (pool != nullptr) {
    pool->parallel_for(n, f);
  } else {
    for (std::ptrdiff_t i = 0; i < n; ++i) f(i);
  }
}

/// The blocks of `block` items that [0, n) splits into (the last one may be shorter).
inline std::size_t block_count(std::size_t n, std::size_t block) { return (n + block - 1) / block; }

/// f(b, begin, end) for each block [begin, end) = [b * block, min(n, (b + 1) * block)) of [0, n),
/// as parallel_for over the block_count(n, block) blocks.
template <class F>
void parallel_for_blocks(const ThreadPool* pool, std::size_t n, std::size_t block, F&& f) {
  parallel_for(pool, static_cast<std::ptrdiff_t>(block_count(n, block)), [&](std::ptrdiff_t b) {
    const std::size_t begin = static_cast<std::size_t>(b) * block;
    f(b, begin, std::min(n, begin + block));
  });
}

}  // namespace detail
}  // namespace PPCR_ABI_NAMESPACE
}  // namespace ppcr
