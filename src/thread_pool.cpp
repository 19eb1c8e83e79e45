// thread_pool.cpp - see thread_pool.hpp.
#include "thread_pool.hpp"

#include <algorithm>

namespace ppcr {
inline namespace PPCR_ABI_NAMESPACE {
namespace detail {

ThreadPool::ThreadPool(int threads) { start_workers(threads - 1); }

ThreadPool::~ThreadPool() {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    stop_ = true;
  }
  wake_.notify_all();
  for (std::thread& t : workers_) t.join();
}

// A worker the system refuses leaves the pool smaller (the core never throws): the loops are
// then run by fewer threads, with the same results.
void ThreadPool::start_workers(int count) {
  try {
    workers_.reserve(static_cast<std::size_t>(std::max(0, count)));
    for (int i = 0; i < count; ++i) workers_.emplace_back([this] { worker(); });
  } catch (...) {  // std::system_error, std::bad_alloc
  }
}

void ThreadPool::run_loop(Range range, void* body, std::ptrdiff_t n) const {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    loop_ = Loop{range, body, n, std::max<std::ptrdiff_t>(1, n / (16 * std::ptrdiff_t{threads()}))};
    next_.store(0, std::memory_order_relaxed);
    open_ = true;
    ++generation_;
  }
  wake_.notify_all();
  work(loop_);  // loop_ changes only in run_loop, on this thread
  // Every chunk is handed out: close the loop, so that a worker not yet in it stays out (it
  // would find nothing to do, and the caller need not wait for it to wake), and wait for those
  // in it, which may still run a chunk (the body lives in the caller's frame, and the next loop
  // resets next_).
  std::unique_lock<std::mutex> lock(mutex_);
  open_ = false;
  done_.wait(lock, [this] { return joined_ == 0; });
}

void ThreadPool::work(const Loop& loop) const noexcept {
  for (;;) {
    const std::ptrdiff_t begin = next_.fetch_add(loop.chunk, std::memory_order_relaxed);
    if (begin >= loop.n) return;
    loop.range(loop.body, begin, std::min(loop.n, begin + loop.chunk));
  }
}

void ThreadPool::worker() const {
  std::uint64_t seen = 0;
  for (;;) {
    Loop loop;
    {
      std::unique_lock<std::mutex> lock(mutex_);
      wake_.wait(lock, [&] { return stop_ || (open_ && generation_ != seen); });
      if (stop_) return;
      seen = generation_;
      loop = loop_;
      ++joined_;
    }
    work(loop);
    bool last = false;
    {
      std::lock_guard<std::mutex> lock(mutex_);
      last = --joined_ == 0 && !open_;
    }
    // After the unlock, so that the caller does not wake to a held mutex (it tests joined_ under
    // the mutex, so it cannot miss this). The pool outlives this: its destructor joins the
    // workers.
    if (last) done_.notify_one();
  }
}

}  // namespace detail
}  // namespace PPCR_ABI_NAMESPACE
}  // namespace ppcr
