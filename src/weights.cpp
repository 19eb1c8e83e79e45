// weights.cpp - the public one-point E-step (the kernels are in weight_kernel.hpp).
#include "ppcr/weights.hpp"

#include "weight_kernel.hpp"

namespace ppcr {

double compute_weights(WeightModel model, double dof, double inv_scale_sq, const double* r_sq,
                       std::size_t n, double* w) {
  double log_sum_exp = 0.0;
  detail::with_weight_kernel(model, dof, inv_scale_sq, [&](const auto& kernel) {
    const detail::PointWeights pw = kernel(r_sq, n, w);
    for (std::size_t k = 0; k < n; ++k) w[k] *= pw.c;
    log_sum_exp = pw.log_sum_exp;
  });
  return log_sum_exp;
}

}  // namespace ppcr
