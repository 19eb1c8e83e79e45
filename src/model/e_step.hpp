// e_step.hpp - the E-step: posterior weights of the associations of one source point.
//
// For a source point x_j with neighbours y_1..y_n (n <= max_neighbours), squared errors
// r_k = |y_k - T x_j|^2 and a scale s (std. deviation, cloud units; s = 1 in the paper's raw mode)
// let z_k = r_k / s^2, d = 3. Then (paper eq. 2-4):
//   Student-t:  log p_k = -(nu + d)/2 * log(1 + z_k / nu)
//               pi_k    = exp(log p_k - logsumexp_k log p_k)       (posterior over the neighbours)
//               w_k     = pi_k * (nu + d) / (nu + z_k)             (eq. 4: times expected
//               precision)
//   Gaussian:   pi_k = softmax_k(-z_k / 2),  w_k = pi_k            (eq. 2; the limit nu -> inf)
// The log-sum-exp keeps the closest neighbour's posterior at least 1/n however large z is, so
// posteriors neither overflow nor all underflow to zero, and weights stay finite. If z_k overflows
// to +inf (a tiny s), that neighbour's weight is 0 when another z of the point is finite; when
// every z_k of the point overflows, the Student-t weights are all 0 (each is below
// (nu + d) / DBL_MAX) and the Gaussian weights are the posteriors of the exact z_k (formed from
// the r_k), so they still sum to 1.
#pragma once

#include <cstddef>

#include "ppcr/abi.hpp"
#include "ppcr/options.hpp"

namespace ppcr {
inline namespace PPCR_ABI_NAMESPACE {

/// Computes the weights of one source point's n associations from their squared errors.
/// r_sq[k] = |e_k|^2 in cloud units^2, inv_scale_sq = 1 / s^2, finite and > 0 (the registration
/// clamps it to DBL_MAX). Writes w[0..n). n >= 1.
/// Returns logsumexp_k(log p_k): the log of the point's (unnormalised) mixture likelihood, with
/// the constants of the density dropped.
double compute_weights(WeightModel model, double dof, double inv_scale_sq, const double* r_sq,
                       std::size_t n, double* w);

}  // namespace PPCR_ABI_NAMESPACE
}  // namespace ppcr
