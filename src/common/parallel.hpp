// parallel.hpp - the core's one parallel loop, on OpenMP (optional at build: PPCR_USE_OPENMP).
//
// parallel_for(parallel, n, f) calls f(i) for i in [0, n) and returns when every call is done:
// on parallel->threads() OpenMP threads, or on the calling thread alone for a null `parallel`,
// one thread, or a build without OpenMP (which then links no thread library). Iterations are
// handed out in chunks of about n / (16 threads) as threads free up (schedule(dynamic)): the
// clouds are in Z-order (spatial_order.hpp), so contiguous ranges can differ much in work (a
// region whose points have no neighbours is cheap), and a static split into halves leaves one
// thread waiting. Callers' results do not depend on which thread runs an iteration: each f(i)
// writes only its own outputs, and reductions are summed afterwards in a fixed order, so the
// result is identical for any thread count (tests/reliability/test_determinism.cpp). f must not
// throw.
//
// Idle threads: GCC's OpenMP runtime lets a thread that has finished a loop spin for a while
// before it sleeps, taking a core that another busy process could use. A process stops that with
// OMP_WAIT_POLICY=passive in its environment, which the runtime reads when it loads; ppcr's tools
// set it for themselves (tools/common/openmp_environment.hpp). The library, which must not make
// process-wide settings, leaves it to the application (docs/PERFORMANCE.md).
#pragma once

#include <algorithm>
#include <cstddef>

#include "ppcr/abi.hpp"

namespace ppcr {
inline namespace PPCR_ABI_NAMESPACE {
namespace detail {

/// How many threads the parallel loops of one Registration use: num_threads, or 1 in a build
/// without OpenMP. A value: no thread lives between loops but those of the OpenMP runtime.
class Parallel {
 public:
  explicit Parallel(int threads = 1) : threads_(std::max(1, threads)) {}

  /// The threads that run a loop, the caller among them.
  int threads() const {
#if defined(PPCR_USE_OPENMP)
    return threads_;
#else
    return 1;
#endif
  }

 private:
  int threads_;
};

/// f(i) for i in [0, n) on the threads of `parallel`, or on the calling thread alone when
/// `parallel` is null or has one thread.
template <class F>
void parallel_for(const Parallel* parallel, std::ptrdiff_t n, F&& f) {
  const int threads = parallel != nullptr ? parallel->threads() : 1;
  if (threads > 1 && n > 1) {
#if defined(PPCR_USE_OPENMP)
    const std::ptrdiff_t chunk = std::max<std::ptrdiff_t>(1, n / (16 * std::ptrdiff_t{threads}));
#pragma omp parallel for num_threads(threads) schedule(dynamic, chunk)
    for (std::ptrdiff_t i = 0; i < n; ++i) f(i);
    return;
#endif
  }
  for (std::ptrdiff_t i = 0; i < n; ++i) f(i);
}

/// The blocks of `block` items that [0, n) splits into (the last one may be shorter).
inline std::size_t block_count(std::size_t n, std::size_t block) { return (n + block - 1) / block; }

/// f(b, begin, end) for each block [begin, end) = [b * block, min(n, (b + 1) * block)) of [0, n),
/// as parallel_for over the block_count(n, block) blocks.
template <class F>
void parallel_for_blocks(const Parallel* parallel, std::size_t n, std::size_t block, F&& f) {
  parallel_for(parallel, static_cast<std::ptrdiff_t>(block_count(n, block)), [&](std::ptrdiff_t b) {
    const std::size_t begin = static_cast<std::size_t>(b) * block;
    f(b, begin, std::min(n, begin + block));
  });
}

}  // namespace detail
}  // namespace PPCR_ABI_NAMESPACE
}  // namespace ppcr
