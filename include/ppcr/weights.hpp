// weights.hpp - the E-step: posterior weights of the associations of one source point.
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

namespace ppcr {
inline namespace PPCR_ABI_NAMESPACE {

enum class WeightModel {
  kStudentT,  // paper eq. 3-4 (default)
  kGaussian,  // paper eq. 2
};

enum class ScaleMode {
  kRaw,    // s = 1 cloud unit: the paper's and the authors' code; weights depend on the units
  kFixed,  // s = WeightOptions::scale, given by the user
  kEM,     // coarse-to-fine: s held at a coarse value, then re-estimated by EM (default)
};

/// The E-step scale. kEM runs in two phases (src/scale_schedule.cpp):
///  1. coarse: s = scale (or radius / 2 when scale is 0) until the pose has settled at that
///     scale: the relative cost drop of more than em_coarse_patience consecutive outer iterations
///     was below em_coarse_drop, or one iteration moved the source by less than
///     em_coarse_motion * s (RMS). A wide kernel has a wide basin: this is what lets PPCR escape
///     the local minima a small scale creates (measured on the lidar pair: see README). An
///     iteration that reused the last associations (RegistrationOptions::reassociate_motion)
///     neither counts toward nor ends this phase (src/scale_schedule.hpp).
///  2. refine: after every outer iteration s^2 <- max(EM estimate, em_min_shrink * s^2,
///     em_min_scale^2), the EM estimate being sum_kj w_kj r_kj / (3 * matched source points) at
///     the final pose (the M-step of the Student-t / Gaussian scale).
/// While the scale is coarse or still shrinking at the em_min_shrink limit, the adaptive
/// termination criteria do not count (termination.hpp); fixed iterations and the cap do.
struct WeightOptions {
  WeightModel model = WeightModel::kStudentT;
  double dof = 5.0;  // Student-t degrees of freedom nu (> 0); the authors' default
  ScaleMode scale_mode = ScaleMode::kEM;
  double scale = 0.0;                  // kFixed: s, cloud units (> 0). kEM: coarse s, cloud units
                                       // (0 = radius / 2). Unused by kRaw.
  double em_coarse_drop = 0.01;        // kEM phase 1: relative cost drop counted as settled
  int em_coarse_patience = 10;         // kEM phase 1: settled after more than this many
                                       // consecutive iterations below em_coarse_drop
  double em_coarse_motion = 1e-3;      // kEM phase 1: or after an iteration moving the source by
                                       // less than this fraction of s (RMS)
  double em_coarse_max_motion = 0.02;  // kEM phase 1: if > 0, an iteration counts toward
                                       // em_coarse_patience only when it moved the source by
                                       // less than this fraction of the radius (RMS)
  double em_min_shrink = 0.25;         // kEM phase 2: s^2 shrinks by at most this factor per outer
                                       // iteration (0 < f <= 1). 0.25 (was 0.5): 18 % fewer
                                       // iterations on the bunny set, errors within 0.5 %
                                       // (docs/TERMINATION.md, section 9)
  double em_min_scale = 0.0;           // kEM phase 2: floor on s, cloud units (0 = none)
};

/// Computes the weights of one source point's n associations from their squared errors.
/// r_sq[k] = |e_k|^2 in cloud units^2, inv_scale_sq = 1 / s^2, finite and > 0 (the registration
/// clamps it to DBL_MAX). Writes w[0..n). n >= 1.
/// Returns logsumexp_k(log p_k): the log of the point's (unnormalised) mixture likelihood, with
/// the constants of the density dropped.
double compute_weights(WeightModel model, double dof, double inv_scale_sq, const double* r_sq,
                       std::size_t n, double* w);

}  // namespace PPCR_ABI_NAMESPACE
}  // namespace ppcr
