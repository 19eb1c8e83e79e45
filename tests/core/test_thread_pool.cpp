// Tests of the thread pool (thread_pool.hpp): every iteration exactly once, on more than one
// thread, through many loops in a row, and idle workers that use no CPU.
#include <time.h>

#include <atomic>
#include <catch2/catch.hpp>
#include <chrono>
#include <mutex>
#include <set>
#include <thread>
#include <vector>

#include "thread_pool.hpp"

using ppcr::detail::ThreadPool;

namespace {

double process_cpu_seconds() {
  timespec t{};
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
  return static_cast<double>(t.tv_sec) + 1e-9 * static_cast<double>(t.tv_nsec);
}

}  // namespace

TEST_CASE("parallel_for calls every index exactly once", "[thread_pool]") {
  for (int threads : {1, 2, 3, 8}) {
    const ThreadPool pool(threads);
    CHECK(pool.threads() == threads);
    for (std::ptrdiff_t n : {0, 1, 2, 5, 17, 64, 1000, 100003}) {
      INFO("threads " << threads << ", n " << n);
      std::vector<std::atomic<int>> calls(static_cast<std::size_t>(n));
      for (std::atomic<int>& c : calls) c.store(0);
      pool.parallel_for(n, [&](std::ptrdiff_t i) { calls[static_cast<std::size_t>(i)]++; });
      int wrong = 0;
      for (const std::atomic<int>& c : calls) wrong += c.load() != 1;
      CHECK(wrong == 0);
    }
  }
  // A null pool: the calling thread alone, in order.
  std::vector<std::ptrdiff_t> order;
  ppcr::detail::parallel_for(nullptr, 5, [&](std::ptrdiff_t i) { order.push_back(i); });
  CHECK(order == std::vector<std::ptrdiff_t>{0, 1, 2, 3, 4});
}

TEST_CASE("two iterations of a loop run at once on a pool of 2", "[thread_pool]") {
  // Each iteration waits (up to 10 s) until the other has started: only two threads at once
  // get both through quickly.
  const ThreadPool pool(2);
  std::atomic<int> entered{0};
  std::mutex m;
  std::set<std::thread::id> ids;
  std::atomic<bool> timed_out{false};
  pool.parallel_for(2, [&](std::ptrdiff_t) {
    {
      std::lock_guard<std::mutex> lock(m);
      ids.insert(std::this_thread::get_id());
    }
    entered++;
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(10);
    while (entered.load() < 2) {
      if (std::chrono::steady_clock::now() > deadline) {
        timed_out = true;
        break;
      }
      std::this_thread::yield();
    }
  });
  CHECK_FALSE(timed_out.load());
  CHECK(ids.size() == 2);
}

TEST_CASE("many short loops in a row, and pools made and dropped, all complete", "[thread_pool]") {
  // A lost wake-up would hang here (ctest's timeout), a race give a wrong sum.
  const ThreadPool pool(2);
  std::vector<long> out(64);
  long total = 0;
  for (int loop = 0; loop < 20000; ++loop) {
    pool.parallel_for(64, [&](std::ptrdiff_t i) { out[static_cast<std::size_t>(i)] = loop + i; });
    total += out[63] - out[0];
  }
  CHECK(total == 20000L * 63);
  for (int p = 0; p < 200; ++p) {
    const ThreadPool short_lived(3);
    std::atomic<int> calls{0};
    short_lived.parallel_for(10, [&](std::ptrdiff_t) { calls++; });
    REQUIRE(calls.load() == 10);
  }
}

TEST_CASE("idle workers sleep: no CPU between loops", "[thread_pool]") {
  // 50 tiny loops, each followed by 4 ms in which the caller sleeps (as a caller's serial work
  // or a busy process would leave the core): a worker that spun in those gaps would add up to
  // the 200 ms of wall time in CPU time. Sleeping workers add almost nothing.
  const ThreadPool pool(2);
  std::vector<double> out(256);
  const double cpu_before = process_cpu_seconds();
  for (int loop = 0; loop < 50; ++loop) {
    pool.parallel_for(256, [&](std::ptrdiff_t i) { out[static_cast<std::size_t>(i)] = 0.5 * i; });
    std::this_thread::sleep_for(std::chrono::milliseconds(4));
  }
  const double cpu = process_cpu_seconds() - cpu_before;
  INFO("CPU time over ~200 ms of loops and gaps: " << cpu * 1e3 << " ms");
  CHECK(cpu < 0.04);
}
