// parallel.hpp - the only place that knows about OpenMP.
//
// parallel_for(num_threads, n, f) calls f(i) for i in [0, n) on num_threads threads (the
// num_threads clause is local to the region: no process-wide setting is touched). Iterations
// are handed out in chunks of about n / (16 num_threads) as threads free up (OpenMP's dynamic
// schedule): the clouds are in Z-order (spatial_order.hpp), so contiguous ranges can differ
// much in work (a region whose points have no neighbours is cheap), and a static split into
// halves left one thread waiting (docs/PERFORMANCE.md). Callers' results do not depend on which
// thread runs an iteration: each f(i) writes only its own outputs, and reductions are summed
// afterwards in a fixed order. Without OpenMP it is a plain loop. f must not throw.
#pragma once

#include <algorithm>
#include <cstddef>

#include "ppcr/abi.hpp"

namespace ppcr {
inline namespace PPCR_ABI_NAMESPACE {
namespace detail {

template <class F>
void parallel_for(int num_threads, std::ptrdiff_t n, F&& f) {
#if defined(PPCR_HAVE_OPENMP)
  if (num_threads > 1 && n > 1) {
    const std::ptrdiff_t chunk =
        std::max<std::ptrdiff_t>(1, n / (16 * static_cast<std::ptrdiff_t>(num_threads)));
#pragma omp parallel for num_threads(num_threads) schedule(dynamic, chunk)
    for (std::ptrdiff_t i = 0; i < n; ++i) f(i);
    return;
  }
#else
  (void)num_threads;
#endif
  for (std::ptrdiff_t i = 0; i < n; ++i) f(i);
}

}  // namespace detail
}  // namespace PPCR_ABI_NAMESPACE
}  // namespace ppcr
