// e_step.cpp - the public one-point E-step (the kernels are in e_step_kernel.hpp).
#include "model/e_step.hpp"

#include <cmath>

#include "model/e_step_kernel.hpp"

namespace ppcr {
inline namespace PPCR_ABI_NAMESPACE {
namespace detail {

// Every z_k = r_k / s^2 is +inf, so z_k >> nu and the ratios of the z_k are those of the r_k.
// r_k > r_min is false for r_k = r_min, and for every k when all r_k are +inf (r_min = +inf):
// such neighbours are equally close and get the ratio 1 (Student-t) or u = 1 (Gaussian).

PointWeights student_t_weights_overflow(double dof, double exponent, double inv_scale_sq,
                                        const double* r_sq, double r_min, std::size_t n,
                                        double* u) {
  // q_k = (nu + z_min) / (nu + z_k) = r_min / r_k to rounding: nu is negligible beside z.
  double sum = 0.0;
  for (std::size_t k = 0; k < n; ++k) {
    const double q = r_sq[k] > r_min ? r_min / r_sq[k] : 1.0;
    const double p = std::pow(q, exponent);
    sum += p;
    u[k] = p * q;
  }
  PointWeights out;
  // w_k = pi_k (nu + d) / (nu + z_k) <= (nu + d) / z_min < (nu + d) / DBL_MAX: the point's weights
  // are zero to within that, and are returned as zero (finite u_k times c = 0).
  out.c = 0.0;
  // log1p(z_min / nu) = log(r_min) + log(1 / s^2) - log(nu) to rounding; -inf if r_min = +inf.
  out.log_sum_exp =
      -exponent * (std::log(r_min) + std::log(inv_scale_sq) - std::log(dof)) + std::log(sum);
  return out;
}

PointWeights gaussian_weights_overflow(double inv_scale_sq, const double* r_sq, double r_min,
                                       std::size_t n, double* u) {
  // u_k = exp(-(z_k - z_min) / 2) with z_k - z_min = (r_k - r_min) / s^2, which may be finite.
  double sum = 0.0;
  for (std::size_t k = 0; k < n; ++k) {
    u[k] = r_sq[k] > r_min ? std::exp(-0.5 * ((r_sq[k] - r_min) * inv_scale_sq)) : 1.0;
    sum += u[k];
  }
  PointWeights out;
  out.c = 1.0 / sum;
  out.log_sum_exp = -(0.5 * r_min) * inv_scale_sq + std::log(sum);  // -inf unless z_min / 2 fits
  return out;
}

}  // namespace detail

double compute_weights(WeightModel model, double dof, double inv_scale_sq, const double* r_sq,
                       std::size_t n, double* w) {
  double log_sum_exp = 0.0;
  detail::with_weight_kernel<true>(model, dof, inv_scale_sq, [&](const auto& kernel) {
    const detail::PointWeights pw = kernel(r_sq, detail::smallest(r_sq, n), n, w);
    for (std::size_t k = 0; k < n; ++k) w[k] *= pw.c;
    log_sum_exp = pw.log_sum_exp;
  });
  return log_sum_exp;
}

}  // namespace PPCR_ABI_NAMESPACE
}  // namespace ppcr
