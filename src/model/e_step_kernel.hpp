// e_step_kernel.hpp - the E-step of one source point (paper eq. 2-4) in ratio form.
//
// With z_k = r_k / s^2 and z_min the smallest of a point's z_k:
//  Student-t: the posterior ratios need no logarithm,
//     q_k = (nu + z_min) / (nu + z_k)  in (0, 1],     p_k / p_max = q_k^e,  e = (nu + d) / 2,
//   and the expected precision is (nu + d) / (nu + z_k) = q_k (nu + d) / (nu + z_min), so
//     w_k = pi_k (nu + d) / (nu + z_k) = u_k * c,   u_k = q_k^(e + 1),
//     c = (nu + d) / ((nu + z_min) * sum_m q_m^e).
//  Gaussian: u_k = exp(-(z_k - z_min) / 2), c = 1 / sum_m u_m.
// The closest neighbour has p_k / p_max = 1, so the sum is >= 1: this is the log-sum-exp trick
// in ratio form, and the posteriors never all underflow. Callers accumulate with the unnormalised
// u_k and multiply the point's sums by c once.
//
// Overflow: a neighbour whose z_k is +inf while z_min is finite gets q_k = 0 (Gaussian: u_k = 0),
// so weight 0. When every z_k of a point overflows (z_min = +inf, e.g. r = 1e300 and s = 1e-5),
// the ratios above would be inf / inf; one test of z_min per point sends such a point to the
// *_overflow kernels (e_step.cpp), which form the ratios from the r_k instead (the factor 1 / s^2
// cancels): Student-t q_k = r_min / r_k and c = 0, since every weight is below (nu + d) / DBL_MAX;
// Gaussian u_k = exp(-(r_k - r_min) / (2 s^2)), c = 1 / sum, so its posteriors still sum to 1.
// The per-pair work of finite points is unchanged.
//
// The power q^e is chosen once per pass: e = 4 (nu = 5, the default) as two squarings, any
// multiple of 1/8 up to 32 (nu a multiple of 0.25) by squaring and at most three square roots,
// otherwise exp(e log q) with log q formed stably (PowerGeneral), exact as nu -> infinity. The
// roots' kernel takes two neighbours per step in two lanes, and four per step where the CPU has AVX
// (four_lanes.hpp), to the same bits (tests/core/test_weights.cpp).
#pragma once

#include <Eigen/Core>
#include <cmath>
#include <cstddef>
#include <limits>

#include "model/e_step.hpp"
#include "model/four_lanes.hpp"
#include "ppcr/abi.hpp"

namespace ppcr {
inline namespace PPCR_ABI_NAMESPACE {
namespace detail {

/// Unnormalised weights of one point: u[k] and the factor c with w_k = c * u_k.
struct PointWeights {
  double c = 0.0;            // normaliser (see file comment)
  double log_sum_exp = 0.0;  // logsumexp_k log p_k, constants dropped
};

/// The powers below take a double; PowerDyadic also an Eigen::Array2d (two lanes, one SSE2 / NEON
/// operation each, kTwoLanes): a lane runs the scalar's operations in the scalar's order, a
/// square root or a division is correctly rounded in either form (IEEE 754), and no a * b + c is
/// contracted into a fused multiply-add (-ffp-contract=off, CMakeLists.txt), so both give the
/// same bits.
inline double square_root(double x) { return std::sqrt(x); }
inline Eigen::Array2d square_root(const Eigen::Array2d& x) { return x.sqrt(); }
inline double one_like(double) { return 1.0; }
inline Eigen::Array2d one_like(const Eigen::Array2d&) { return Eigen::Array2d::Ones(); }

/// q^e: the default nu = 5 (e = 4). Two multiplications: one lane (kTwoLanes below) is faster.
struct PowerFour {
  static constexpr bool kTwoLanes = false;
  static constexpr bool kFromLog = false;
  double operator()(double q) const {
    const double q2 = q * q;
    return q2 * q2;
  }
};
/// q^e for 8e an integer, e <= 32: q^floor(e) by squaring times q^(1/2), q^(1/4), q^(1/8) (a chain
/// of square roots) for the set bits of the fraction. Half-integers (any integer dof) need one
/// root; dof a multiple of 0.25 (e.g. 1.25, 1.5) at most three, instead of std::pow.
struct PowerDyadic {
  // Two lanes pay for the roots at dof 1.25 (docs/PERFORMANCE.md, BM_EStep); an integer e (odd
  // dof) gains on the E-step's division only.
  static constexpr bool kTwoLanes = true;
  static constexpr bool kFromLog = false;
  int whole;                // floor(e)
  int eighths;              // (e - floor(e)) * 8, in [0, 8)
  bool four_lanes = false;  // four_lane_dyadic() first (four_lanes.hpp): the same bits
  template <class T>
  T operator()(const T& q) const {
    T result = one_like(q);
    if (eighths != 0) {
      const T r2 = square_root(q);  // q^(1/2)
      if (eighths & 4) result = r2;
      if (eighths & 3) {
        const T r4 = square_root(r2);  // q^(1/4)
        if (eighths & 2) result *= r4;
        if (eighths & 1) result *= square_root(r4);  // q^(1/8)
      }
    }
    T base = q;
    for (int n = whole; n > 0; n >>= 1) {
      if (n & 1) result *= base;
      base *= base;
    }
    return result;
  }
};
/// q^e, any e, from log q (kFromLog): exp(e log q) with log q = log1p(d), d = (z_min - z_k) /
/// (nu + z_k) = q - 1 formed without rounding q. std::pow(q, e) would carry q's rounding error
/// (1 ulp, about 1e-16) times e into the result: at nu = 1e100 that is every weight. In this
/// form q^e tends to exp(-(z_k - z_min) / 2), the Gaussian's ratio, as nu grows, for any finite nu.
struct PowerGeneral {
  static constexpr bool kTwoLanes = false;
  static constexpr bool kFromLog = true;
  double e;
  double operator()(double log_q) const { return std::exp(e * log_q); }
};

/// e log1p(z / nu), the Student-t's -log p of one error up to constants, for z >= 0 finite. When
/// z / nu is below the smallest normal double (nu near the largest), the quotient would lose
/// bits or round to 0: then log1p(t) = t and e t = (z / 2)(1 + 3 / nu), the Gaussian's z / 2 as
/// nu grows.
inline double student_t_log_term(double dof, double exponent, double z) {
  const double t = z / dof;
  if (t >= std::numeric_limits<double>::min() || t == 0.0) return exponent * std::log1p(t);
  return 0.5 * z * (1.0 + 3.0 / dof);
}

/// The E-steps of a point whose every z_k = r_k * inv_scale_sq overflows to +inf (e_step.cpp;
/// see the file comment), r_min the smallest r_k. Write u[0..n), return c and the log-sum-exp.
PointWeights student_t_weights_overflow(double dof, double exponent, double inv_scale_sq,
                                        const double* r_sq, double r_min, std::size_t n, double* u);
PointWeights gaussian_weights_overflow(double inv_scale_sq, const double* r_sq, double r_min,
                                       std::size_t n, double* u);

/// The smallest of r_sq[0..n), n >= 1, as the kernels take it: r_sq[0], then each r_sq[k] that
/// compares less (a NaN in r_sq[0] is kept, later ones are skipped). A caller that produces the
/// r_sq one by one may fold the same comparison into its loop instead.
inline double smallest(const double* r_sq, std::size_t n) {
  double r_min = r_sq[0];
  for (std::size_t k = 1; k < n; ++k) r_min = r_sq[k] < r_min ? r_sq[k] : r_min;
  return r_min;
}

/// Student-t E-step of n >= 1 squared errors whose smallest is r_min (smallest()): writes
/// u[0..n), returns c and, if kLogSumExp, the log-sum-exp (two logarithms per point; the
/// normal-equation pass does not need it). z_min = r_min / s^2 is the smallest z_k: rounding is
/// monotone, so scaling the smallest r_k gives the smallest of the scaled ones (for
/// 0 < inv_scale_sq <= DBL_MAX; an infinite one would make 0 * inf = NaN).
template <bool kLogSumExp, class Power>
inline PointWeights student_t_weights(const Power& power, double dof, double exponent,
                                      double inv_scale_sq, const double* r_sq, double r_min,
                                      std::size_t n, double* u) {
  const double z_min = r_min * inv_scale_sq;
  if (z_min > std::numeric_limits<double>::max()) {  // every z_k is +inf
    return student_t_weights_overflow(dof, exponent, inv_scale_sq, r_sq, r_min, n, u);
  }
  const double nu_z_min = dof + z_min;
  double sum = 0.0;
  // With a power of square roots (Power::kTwoLanes), two neighbours per step: one instruction
  // serves two lanes for the division and the roots, the cost of this loop; the sum is kept in
  // the scalar order (four per step first where the CPU has AVX). Then the rest, or every
  // neighbour, one at a time.
  std::size_t k = 0;
  if constexpr (Power::kTwoLanes) {
    if (power.four_lanes && n >= 4) {
      k = four_lane_dyadic(power.whole, power.eighths, nu_z_min, dof, inv_scale_sq, r_sq, n, u,
                           &sum);
    }
    for (; k + 2 <= n; k += 2) {
      const Eigen::Array2d r2 = Eigen::Map<const Eigen::Array2d>(r_sq + k);
      const Eigen::Array2d q = nu_z_min / (dof + r2 * inv_scale_sq);
      const Eigen::Array2d p = power(q);
      sum += p[0];
      sum += p[1];
      Eigen::Map<Eigen::Array2d>(u + k) = p * q;
    }
  }
  for (; k < n; ++k) {
    const double z = r_sq[k] * inv_scale_sq;
    const double q = nu_z_min / (dof + z);
    double p = 0.0;
    if constexpr (Power::kFromLog) {
      // q = 0 (z_k = +inf): p = 0, where d would be -inf / inf.
      if (q > 0.0) p = power(std::log1p((z_min - z) / (dof + z)));
    } else {
      p = power(q);
    }
    sum += p;
    u[k] = p * q;
  }
  PointWeights out;
  // (nu + z_min) sum overflows for nu near the largest double: then divide in two steps.
  const double denominator = nu_z_min * sum;
  out.c = denominator <= std::numeric_limits<double>::max() ? (dof + 3.0) / denominator
                                                            : (dof + 3.0) / nu_z_min / sum;
  if (kLogSumExp) out.log_sum_exp = -student_t_log_term(dof, exponent, z_min) + std::log(sum);
  return out;
}

/// Gaussian E-step of n >= 1 squared errors whose smallest is r_min (smallest()): writes
/// u[0..n), returns c and, if kLogSumExp, the log-sum-exp.
template <bool kLogSumExp>
inline PointWeights gaussian_weights(double inv_scale_sq, const double* r_sq, double r_min,
                                     std::size_t n, double* u) {
  const double z_min = r_min * inv_scale_sq;
  if (z_min > std::numeric_limits<double>::max()) {  // every z_k is +inf
    return gaussian_weights_overflow(inv_scale_sq, r_sq, r_min, n, u);
  }
  double sum = 0.0;
  for (std::size_t k = 0; k < n; ++k) {
    u[k] = std::exp(-0.5 * (r_sq[k] * inv_scale_sq - z_min));
    sum += u[k];
  }
  PointWeights out;
  out.c = 1.0 / sum;
  if (kLogSumExp) out.log_sum_exp = -0.5 * z_min + std::log(sum);
  return out;
}

/// True when the Student-t exponent e = (dof + 3) / 2 has 8e an integer and e <= 32 (PowerDyadic;
/// e = 4 too, which PowerFour takes in the same bits): then *whole = floor(e) and *eighths =
/// 8 (e - floor(e)).
inline bool dyadic_exponent(double dof, int* whole, int* eighths) {
  const double exponent = 0.5 * (dof + 3.0);
  const double e8 = 8.0 * exponent;
  if (!(e8 == std::floor(e8) && exponent <= 32.0)) return false;
  *whole = static_cast<int>(std::floor(exponent));
  *eighths = static_cast<int>(e8) - 8 * *whole;
  return true;
}

/// Calls f(kernel) with kernel(r_sq, r_min, n, u) -> PointWeights specialised for the model and
/// dof, so that the choice is made once per pass, not once per point. Without kLogSumExp the kernel
/// leaves PointWeights::log_sum_exp at 0 (except on the overflow path).
template <bool kLogSumExp, class F>
void with_weight_kernel(WeightModel model, double dof, double inv_scale_sq, F&& f) {
  if (model == WeightModel::kGaussian) {
    f([=](const double* r_sq, double r_min, std::size_t n, double* u) {
      return gaussian_weights<kLogSumExp>(inv_scale_sq, r_sq, r_min, n, u);
    });
    return;
  }
  const double exponent = 0.5 * (dof + 3.0);
  int whole = 0, eighths = 0;
  if (exponent == 4.0) {
    f([=](const double* r_sq, double r_min, std::size_t n, double* u) {
      return student_t_weights<kLogSumExp>(PowerFour(), dof, exponent, inv_scale_sq, r_sq, r_min, n,
                                           u);
    });
  } else if (dyadic_exponent(dof, &whole, &eighths)) {
    const PowerDyadic power{whole, eighths, four_lanes_available()};
    f([=](const double* r_sq, double r_min, std::size_t n, double* u) {
      return student_t_weights<kLogSumExp>(power, dof, exponent, inv_scale_sq, r_sq, r_min, n, u);
    });
  } else {
    const PowerGeneral power{exponent};
    f([=](const double* r_sq, double r_min, std::size_t n, double* u) {
      return student_t_weights<kLogSumExp>(power, dof, exponent, inv_scale_sq, r_sq, r_min, n, u);
    });
  }
}

}  // namespace detail
}  // namespace PPCR_ABI_NAMESPACE
}  // namespace ppcr
