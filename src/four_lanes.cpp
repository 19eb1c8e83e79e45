// four_lanes.cpp - see four_lanes.hpp. Only this function is compiled for AVX (a target
// attribute, not a flag of the file), so that no inline function of a header is emitted with AVX
// instructions for callers on CPUs without it.
#include "four_lanes.hpp"

#if (defined(__GNUC__) || defined(__clang__)) && defined(__x86_64__)
#define PPCR_FOUR_LANES 1
#include <immintrin.h>
#else
#define PPCR_FOUR_LANES 0
#endif

namespace ppcr {
inline namespace PPCR_ABI_NAMESPACE {
namespace detail {

#if PPCR_FOUR_LANES

bool four_lanes_available() {
#if defined(__AVX__)
  return true;
#else
  return __builtin_cpu_supports("avx");
#endif
}

__attribute__((target("avx"))) std::size_t four_lane_dyadic(int whole, int eighths, double nu_z_min,
                                                            double dof, double inv_scale_sq,
                                                            const double* r_sq, std::size_t n,
                                                            double* u, double* sum) {
  const __m256d numerator = _mm256_set1_pd(nu_z_min);
  const __m256d nu = _mm256_set1_pd(dof);
  const __m256d inv = _mm256_set1_pd(inv_scale_sq);
  const __m256d one = _mm256_set1_pd(1.0);
  double s = *sum;
  std::size_t k = 0;
  for (; k + 4 <= n; k += 4) {
    const __m256d r = _mm256_loadu_pd(r_sq + k);
    const __m256d q = _mm256_div_pd(numerator, _mm256_add_pd(nu, _mm256_mul_pd(r, inv)));
    // PowerDyadic::operator() (weight_kernel.hpp), lane by lane: written again in intrinsics, as
    // its template would be compiled without AVX; test_weights holds the two to the same bits.
    __m256d p = one;
    if (eighths != 0) {
      const __m256d r2 = _mm256_sqrt_pd(q);
      if (eighths & 4) p = r2;
      if (eighths & 3) {
        const __m256d r4 = _mm256_sqrt_pd(r2);
        if (eighths & 2) p = _mm256_mul_pd(p, r4);
        if (eighths & 1) p = _mm256_mul_pd(p, _mm256_sqrt_pd(r4));
      }
    }
    __m256d base = q;
    for (int m = whole; m > 0; m >>= 1) {
      if (m & 1) p = _mm256_mul_pd(p, base);
      base = _mm256_mul_pd(base, base);
    }
    alignas(32) double lanes[4];
    _mm256_store_pd(lanes, p);
    s += lanes[0];
    s += lanes[1];
    s += lanes[2];
    s += lanes[3];
    _mm256_storeu_pd(u + k, _mm256_mul_pd(p, q));
  }
  *sum = s;
  return k;
}

#else

bool four_lanes_available() { return false; }

std::size_t four_lane_dyadic(int, int, double, double, double, const double*, std::size_t, double*,
                             double*) {
  return 0;
}

#endif

}  // namespace detail
}  // namespace PPCR_ABI_NAMESPACE
}  // namespace ppcr
