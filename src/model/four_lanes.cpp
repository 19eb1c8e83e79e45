// four_lanes.cpp - see four_lanes.hpp. Only this function is compiled for AVX (a target
// attribute, not a flag of the file; with avx_power.hpp's power inlined into it), so that no inline
// function of a header is emitted with AVX instructions for callers on CPUs without it.
#include "model/four_lanes.hpp"

#include "model/avx_power.hpp"

namespace ppcr {
inline namespace PPCR_ABI_NAMESPACE {
namespace detail {

#if PPCR_AVX_KERNELS

bool four_lanes_available() {
#if defined(__AVX__)
  return true;
#else
  return __builtin_cpu_supports("avx");
#endif
}

PPCR_AVX std::size_t four_lane_dyadic(int whole, int eighths, double nu_z_min, double dof,
                                      double inv_scale_sq, const double* r_sq, std::size_t n,
                                      double* u, double* sum) {
  const __m256d numerator = _mm256_set1_pd(nu_z_min);
  const __m256d nu = _mm256_set1_pd(dof);
  const __m256d inv = _mm256_set1_pd(inv_scale_sq);
  double s = *sum;
  std::size_t k = 0;
  for (; k + 4 <= n; k += 4) {
    const __m256d r = _mm256_loadu_pd(r_sq + k);
    const __m256d q = _mm256_div_pd(numerator, _mm256_add_pd(nu, _mm256_mul_pd(r, inv)));
    const __m256d p = dyadic_power(q, whole, eighths);
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
