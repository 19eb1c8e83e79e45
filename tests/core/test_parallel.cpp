// Tests of the parallel loop (parallel.hpp): every iteration exactly once, on more than one
// thread when OpenMP is built in, on the calling thread alone for one thread, through many loops
// in a row, and idle threads that use no CPU under OMP_WAIT_POLICY=passive (what the tools set).
#include <time.h>

#include <atomic>
#include <catch2/catch.hpp>
#include <chrono>
#include <cstdlib>
#include <mutex>
#include <set>
#include <string>
#include <thread>
#include <vector>

#include "common/parallel.hpp"

using ppcr::detail::Parallel;
using ppcr::detail::parallel_for;

namespace {

double process_cpu_seconds() {
  timespec t{};
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
  return static_cast<double>(t.tv_sec) + 1e-9 * static_cast<double>(t.tv_nsec);
}

bool built_with_openmp() { return Parallel(2).threads() == 2; }

}  // namespace

TEST_CASE("parallel_for calls every index exactly once", "[parallel]") {
  for (int threads : {1, 2, 3, 8}) {
    const Parallel parallel(threads);
    CHECK(parallel.threads() == (built_with_openmp() ? threads : 1));
    for (std::ptrdiff_t n : {0, 1, 2, 5, 17, 64, 1000, 100003}) {
      INFO("threads " << threads << ", n " << n);
      std::vector<std::atomic<int>> calls(static_cast<std::size_t>(n));
      for (std::atomic<int>& c : calls) c.store(0);
      parallel_for(&parallel, n, [&](std::ptrdiff_t i) { calls[static_cast<std::size_t>(i)]++; });
      int wrong = 0;
      for (const std::atomic<int>& c : calls) wrong += c.load() != 1;
      CHECK(wrong == 0);
    }
  }
}

TEST_CASE("one thread, or none given, runs the loop on the caller in order", "[parallel]") {
  const Parallel one(1);
  for (const Parallel* parallel : {static_cast<const Parallel*>(nullptr), &one}) {
    std::vector<std::ptrdiff_t> order;
    std::set<std::thread::id> ids;
    parallel_for(parallel, 1000, [&](std::ptrdiff_t i) {
      order.push_back(i);
      ids.insert(std::this_thread::get_id());
    });
    REQUIRE(order.size() == 1000u);
    for (std::size_t i = 0; i < order.size(); ++i)
      CHECK(order[i] == static_cast<std::ptrdiff_t>(i));
    CHECK(ids == std::set<std::thread::id>{std::this_thread::get_id()});
  }
}

TEST_CASE("two iterations of a loop run at once with 2 threads", "[parallel]") {
  if (!built_with_openmp()) {
    WARN("built without OpenMP (PPCR_USE_OPENMP off): every loop runs on the calling thread");
    return;
  }
  // Each iteration waits (up to 10 s) until the other has started: only two threads at once get
  // both through quickly.
  const Parallel parallel(2);
  std::atomic<int> entered{0};
  std::mutex m;
  std::set<std::thread::id> ids;
  std::atomic<bool> timed_out{false};
  parallel_for(&parallel, 2, [&](std::ptrdiff_t) {
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

TEST_CASE("many short loops in a row all complete", "[parallel]") {
  const Parallel parallel(2);
  std::vector<long> out(64);
  long total = 0;
  for (int loop = 0; loop < 20000; ++loop) {
    parallel_for(&parallel, 64,
                 [&](std::ptrdiff_t i) { out[static_cast<std::size_t>(i)] = loop + i; });
    total += out[63] - out[0];
  }
  CHECK(total == 20000L * 63);
}

TEST_CASE("idle threads sleep under OMP_WAIT_POLICY=passive: no CPU between loops", "[parallel]") {
  // ctest runs this executable with OMP_WAIT_POLICY=passive (tests/core/CMakeLists.txt), as the
  // tools run themselves. 50 tiny loops, each followed by 4 ms in which the caller sleeps (as a
  // caller's serial work or a busy process would leave the core): a thread that spun in those
  // gaps would add up to the 200 ms of wall time in CPU time. Sleeping threads add almost nothing.
  if (!built_with_openmp()) {
    WARN("built without OpenMP (PPCR_USE_OPENMP off): no thread to sleep");
    return;
  }
  const char* policy = std::getenv("OMP_WAIT_POLICY");
  REQUIRE(policy != nullptr);
  REQUIRE(std::string(policy) == "passive");
  const Parallel parallel(2);
  std::vector<double> out(256);
  const double cpu_before = process_cpu_seconds();
  for (int loop = 0; loop < 50; ++loop) {
    parallel_for(&parallel, 256,
                 [&](std::ptrdiff_t i) { out[static_cast<std::size_t>(i)] = 0.5 * i; });
    std::this_thread::sleep_for(std::chrono::milliseconds(4));
  }
  const double cpu = process_cpu_seconds() - cpu_before;
  INFO("CPU time over ~200 ms of loops and gaps: " << cpu * 1e3 << " ms");
  CHECK(cpu < 0.04);
}
