// termination.cpp - the termination monitor (paper Sec. 3.2; when each criterion fires is
// documented in termination.hpp).
#include "registration/termination.hpp"

#include <cmath>
#include <limits>

namespace ppcr {
inline namespace PPCR_ABI_NAMESPACE {

const char* to_string(StopReason reason) {
  switch (reason) {
    case StopReason::kNone:
      return "none";
    case StopReason::kFixedIterations:
      return "fixed_iterations";
    case StopReason::kCostDrop:
      return "cost_drop";
    case StopReason::kMsePrev:
      return "mse_prev";
    case StopReason::kSuccessfulSteps:
      return "successful_steps";
    case StopReason::kMaxIterations:
      return "max_iterations";
    case StopReason::kZeroCost:
      return "zero_cost";
    case StopReason::kNoCorrespondences:
      return "no_correspondences";
    case StopReason::kNumericalFailure:
      return "numerical_failure";
    case StopReason::kInvalidInput:
      return "invalid_input";
    case StopReason::kCancelled:
      return "cancelled";
  }
  return "unknown";
}

bool is_criterion_stop(StopReason reason) {
  switch (reason) {
    case StopReason::kFixedIterations:
    case StopReason::kCostDrop:
    case StopReason::kMsePrev:
    case StopReason::kSuccessfulSteps:
    case StopReason::kZeroCost:  // every association already exact: nothing left to do
      return true;
    default:
      return false;
  }
}

TerminationMonitor::TerminationMonitor(const TerminationCriteria& criteria,
                                       const CloudMoments& source,
                                       const Eigen::Isometry3d& T_initial)
    : criteria_(criteria), source_(source), T_previous_(T_initial) {}

StopReason TerminationMonitor::update(const IterationReport& report) {
  const int t = report.iteration;
  const double initial = report.lm.initial_cost;
  const double final_cost = report.lm.final_cost;

  // MSE w.r.t. the previous pose (eq. 5), O(1) from the source moments.
  last_mse_prev_ = mse_between(source_, report.T_target_source, T_previous_);
  T_previous_ = report.T_target_source;

  // Zero or non-finite initial cost: no ratio can be formed. Checked first.
  if (!std::isfinite(initial) || !std::isfinite(final_cost)) {
    last_cost_drop_ = std::numeric_limits<double>::quiet_NaN();
    return StopReason::kNumericalFailure;
  }
  if (initial <= 0.0) {
    last_cost_drop_ = std::numeric_limits<double>::quiet_NaN();
    return StopReason::kZeroCost;
  }
  last_cost_drop_ = (initial - final_cost) / initial;  // eq. 7

  // Update every counter, whichever criteria are enabled; hold them at zero while the E-step
  // scale is settling.
  const bool counting = !report.scale_settling;
  const bool still =
      criteria_.cost_drop_max_motion <= 0.0 ||
      std::sqrt(last_mse_prev_) < criteria_.cost_drop_max_motion * report.motion_reference;
  const bool drop_low = counting && still && last_cost_drop_ < criteria_.cost_drop_threshold;
  const bool mse_low =
      counting && (last_mse_prev_ == 0.0 ||
                   (t >= 2 && last_mse_prev_ < previous_mse_ / criteria_.mse_ratio_threshold));
  const bool steps_low =
      counting && report.lm.successful_steps <= criteria_.successful_steps_threshold;
  previous_mse_ = last_mse_prev_;
  low_cost_drop_count_ = drop_low ? low_cost_drop_count_ + 1 : 0;
  low_mse_count_ = mse_low ? low_mse_count_ + 1 : 0;
  low_steps_count_ = steps_low ? low_steps_count_ + 1 : 0;

  const std::uint32_t c = criteria_.criteria;
  if ((c & kCriterionFixed) && t >= criteria_.fixed_iterations) return StopReason::kFixedIterations;
  if ((c & kCriterionCostDrop) && low_cost_drop_count_ > criteria_.cost_drop_patience) {
    return StopReason::kCostDrop;
  }
  if ((c & kCriterionMsePrev) && low_mse_count_ > criteria_.mse_patience) {
    return StopReason::kMsePrev;
  }
  if ((c & kCriterionSuccessfulSteps) && low_steps_count_ > criteria_.successful_steps_patience) {
    return StopReason::kSuccessfulSteps;
  }
  if (t >= criteria_.max_iterations) return StopReason::kMaxIterations;
  return StopReason::kNone;
}

}  // namespace PPCR_ABI_NAMESPACE
}  // namespace ppcr
