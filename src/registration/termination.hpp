// termination.hpp - when the outer loop stops (the paper's subject, Sec. 3.2).
//
// The monitor is fed one IterationReport per outer iteration and answers "continue" (kNone) or a
// StopReason. It never sees the clouds: the MSE w.r.t. the previous iteration (eq. 5) comes in
// O(1) from the source cloud's mean and covariance (metrics.hpp).
//
// When each criterion fires, with t = 1, 2, ... the outer iteration just finished:
//  - kFixedIterations: at t == fixed_iterations.
//  - kCostDrop (eq. 7): drop_t = (initial_cost_t - final_cost_t) / initial_cost_t. A counter of
//    consecutive iterations with drop_t < cost_drop_threshold is reset by any iteration at or
//    above it; fires when the counter exceeds cost_drop_patience. With cost_drop_max_motion > 0,
//    a low iteration must also have moved the source by less than cost_drop_max_motion x
//    motion_reference (RMS): the cost drop alone can be tiny while the pose still slides along a
//    valley.
//  - kMsePrev (eq. 5-6): MSE_t = mean_i |T_t x_i - T_{t-1} x_i|^2 (T_0 the initial guess). A
//    counter of consecutive iterations with MSE_t < MSE_{t-1} / mse_ratio_threshold (t >= 2) or
//    MSE_t == 0; fires when it exceeds mse_patience.
//  - kSuccessfulSteps: a counter of consecutive iterations whose LM made at most
//    successful_steps_threshold accepted steps; fires when it exceeds successful_steps_patience.
//  - Always: kMaxIterations at t == max_iterations; kZeroCost when an iteration's initial cost is
//    zero and kNumericalFailure when it is not finite, both checked before any ratio is formed.
//  - While a report says scale_settling (the EM scale is coarse or still shrinking), the
//    cost-drop, MSE and successful-steps counters are held at zero; fixed and the cap still apply.
// With several criteria enabled the loop stops when any fires; the first in the order above wins.
#pragma once

#include <Eigen/Geometry>
#include <cstdint>

#include "ppcr/abi.hpp"
#include "ppcr/metrics.hpp"
#include "ppcr/options.hpp"
#include "ppcr/result.hpp"
#include "solver/lm_options.hpp"

namespace ppcr {
inline namespace PPCR_ABI_NAMESPACE {

/// The criteria's settings, with the options' defaults (options.hpp, where each is defined once);
/// resolve_options.cpp fills them from the options.
struct TerminationCriteria {
  std::uint32_t criteria = RegistrationOptions{}.criteria;  // bitwise OR of Criterion
  int max_iterations = RegistrationOptions{}.max_iterations;
  int fixed_iterations = ExpertOptions{}.fixed_iterations;
  double cost_drop_threshold = ExpertOptions{}.cost_drop_threshold;
  int cost_drop_patience = ExpertOptions{}.cost_drop_patience;
  double cost_drop_max_motion = ExpertOptions{}.cost_drop_max_motion;
  double mse_ratio_threshold = ExpertOptions{}.mse_ratio_threshold;
  int mse_patience = ExpertOptions{}.mse_patience;
  int successful_steps_threshold = ExpertOptions{}.successful_steps_threshold;
  int successful_steps_patience = ExpertOptions{}.successful_steps_patience;
};

/// What the solver hands the monitor after each outer iteration.
struct IterationReport {
  int iteration = 0;                                                  // 1-based outer iteration
  LMSummary lm;                                                       // the inner problem's summary
  Eigen::Isometry3d T_target_source = Eigen::Isometry3d::Identity();  // pose after the iteration
  double motion_reference = 1.0;  // length cost_drop_max_motion is relative to (the radius)
  bool scale_settling = false;    // the E-step scale is still coarse or shrinking
};

/// The termination monitor: one per registration, fed once per outer iteration.
class TerminationMonitor {
 public:
  /// source: moments of the source cloud being registered; T_initial: the pose before the first
  /// iteration.
  TerminationMonitor(const TerminationCriteria& criteria, const CloudMoments& source,
                     const Eigen::Isometry3d& T_initial);

  /// Takes the report of the outer iteration just finished; returns kNone to continue.
  StopReason update(const IterationReport& report);

  /// Values computed by the last update(): relative cost drop (NaN if the initial cost was zero
  /// or not finite) and MSE w.r.t. the previous pose.
  double last_cost_drop() const { return last_cost_drop_; }
  double last_mse_prev() const { return last_mse_prev_; }

 private:
  TerminationCriteria criteria_;
  CloudMoments source_;
  Eigen::Isometry3d T_previous_;
  double previous_mse_ = 0.0;
  double last_cost_drop_ = 0.0;
  double last_mse_prev_ = 0.0;
  int low_cost_drop_count_ = 0;
  int low_mse_count_ = 0;
  int low_steps_count_ = 0;
};

}  // namespace PPCR_ABI_NAMESPACE
}  // namespace ppcr
