// weights.cpp - E-step of one source point (paper eq. 2-4), in log space.
#include "ppcr/weights.hpp"

#include <cmath>

namespace ppcr {

double compute_weights(WeightModel model, double dof, double inv_scale_sq, const double* r_sq,
                       std::size_t n, double* w) {
  constexpr double kDim = 3.0;
  // Pass 1: log p_k (kept in w) and their maximum.
  double max_log_p = -HUGE_VAL;
  if (model == WeightModel::kStudentT) {
    const double exponent = -0.5 * (dof + kDim);
    const double inv_dof = 1.0 / dof;
    for (std::size_t k = 0; k < n; ++k) {
      w[k] = exponent * std::log1p(r_sq[k] * inv_scale_sq * inv_dof);  // eq. 3
      if (w[k] > max_log_p) max_log_p = w[k];
    }
  } else {
    for (std::size_t k = 0; k < n; ++k) {
      w[k] = -0.5 * r_sq[k] * inv_scale_sq;  // eq. 2
      if (w[k] > max_log_p) max_log_p = w[k];
    }
  }
  // Pass 2: posterior pi_k = exp(log p_k - logsumexp); the max term contributes exp(0) = 1, so
  // the sum is >= 1 and no posterior is lost to underflow at the top.
  double sum = 0.0;
  for (std::size_t k = 0; k < n; ++k) {
    w[k] = std::exp(w[k] - max_log_p);
    sum += w[k];
  }
  const double inv_sum = 1.0 / sum;
  if (model == WeightModel::kStudentT) {
    for (std::size_t k = 0; k < n; ++k) {
      // eq. 4: posterior times the expected precision (nu + d) / (nu + z_k).
      w[k] *= inv_sum * (dof + kDim) / (dof + r_sq[k] * inv_scale_sq);
    }
  } else {
    for (std::size_t k = 0; k < n; ++k) w[k] *= inv_sum;
  }
  return max_log_p + std::log(sum);
}

}  // namespace ppcr
