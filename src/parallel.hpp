// parallel.hpp - the only place that knows about OpenMP.
//
// parallel_for(num_threads, n, f) calls f(i) for i in [0, n), split statically over num_threads
// threads (the num_threads clause is local to the region: no process-wide setting is touched).
// Without OpenMP it is a plain loop. f must not throw.
#pragma once

#include <cstddef>

namespace ppcr {
namespace detail {

template <class F>
void parallel_for(int num_threads, std::ptrdiff_t n, F&& f) {
#if defined(PPCR_HAVE_OPENMP)
  if (num_threads > 1 && n > 1) {
#pragma omp parallel for num_threads(num_threads) schedule(static)
    for (std::ptrdiff_t i = 0; i < n; ++i) f(i);
    return;
  }
#else
  (void)num_threads;
#endif
  for (std::ptrdiff_t i = 0; i < n; ++i) f(i);
}

}  // namespace detail
}  // namespace ppcr
