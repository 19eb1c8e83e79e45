// avx_power.hpp - PowerDyadic's q^e (e_step_kernel.hpp) in four AVX lanes, for the kernels
// compiled for AVX by a target attribute (four_lanes.cpp, four_points.cpp). Include it only
// where PPCR_AVX_KERNELS is 1 (GCC or Clang for x86-64), and call it only from a function of such
// a file marked PPCR_AVX: no copy is emitted for callers without AVX.
//
// Each lane runs PowerDyadic::operator()'s operations in its order: square roots and products,
// each correctly rounded (IEEE 754) whatever the vector width, none contracted into a fused
// multiply-add (-ffp-contract=off); test_weights and test_normal_equations hold the lanes to the
// bits of the template.
#pragma once

#if (defined(__GNUC__) || defined(__clang__)) && defined(__x86_64__)
#define PPCR_AVX_KERNELS 1
#include <immintrin.h>

#include "ppcr/abi.hpp"

#define PPCR_AVX __attribute__((target("avx")))

namespace ppcr {
inline namespace PPCR_ABI_NAMESPACE {
namespace detail {

/// q^e lane by lane, e = whole + eighths / 8 (PowerDyadic).
PPCR_AVX inline __m256d dyadic_power(__m256d q, int whole, int eighths) {
  __m256d p = _mm256_set1_pd(1.0);
  if (eighths != 0) {
    const __m256d r2 = _mm256_sqrt_pd(q);  // q^(1/2)
    if (eighths & 4) p = r2;
    if (eighths & 3) {
      const __m256d r4 = _mm256_sqrt_pd(r2);  // q^(1/4)
      if (eighths & 2) p = _mm256_mul_pd(p, r4);
      if (eighths & 1) p = _mm256_mul_pd(p, _mm256_sqrt_pd(r4));  // q^(1/8)
    }
  }
  __m256d base = q;
  for (int n = whole; n > 0; n >>= 1) {
    if (n & 1) p = _mm256_mul_pd(p, base);
    base = _mm256_mul_pd(base, base);
  }
  return p;
}

}  // namespace detail
}  // namespace PPCR_ABI_NAMESPACE
}  // namespace ppcr

#else
#define PPCR_AVX_KERNELS 0
#endif
