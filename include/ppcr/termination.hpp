// termination.hpp - when the outer loop stops (the paper's subject).
//
// The monitor is fed one IterationReport per outer iteration and answers "continue" (kNone) or a
// StopReason. It never sees the clouds: the MSE w.r.t. the previous iteration (paper eq. 5) is
// computed in O(1) from the source cloud's mean and covariance (see metrics.hpp).
//
// When each criterion fires, with t = 1, 2, ... the outer iteration just finished:
//  - kFixedIterations: at t == fixed_iterations.
//  - kCostDrop (eq. 7): drop_t = (initial_cost_t - final_cost_t) / initial_cost_t. A counter of
//    consecutive iterations with drop_t < cost_drop_threshold is reset by any iteration at or
//    above it; fires when the counter exceeds cost_drop_patience, i.e. at the end of the
//    (patience + 1)-th consecutive low iteration. Earliest: t = patience + 1.
//    The authors' code differs: its counter is already 1 before the first iteration (it is
//    tested once with the initial drop of 0), and is compared before being incremented, so it
//    stops after patience + 1 low iterations from the start, but after patience + 2 consecutive
//    low iterations once an iteration at or above the threshold has reset it.
//    With cost_drop_max_motion > 0 (our addition), a low iteration must also have moved the
//    source by less than cost_drop_max_motion * motion_reference (RMS): the cost drop alone can
//    be tiny while the pose still slides along a valley, which is how the paper's rule stops
//    early on some lidar problems.
//  - kMsePrev (eq. 5-6): MSE_t = mean_i |T_t x_i - T_{t-1} x_i|^2 (T_0 the initial guess). A
//    counter of consecutive iterations with MSE_t < MSE_{t-1} / mse_ratio_threshold (t >= 2) or
//    MSE_t == 0; fires when it exceeds mse_patience. Earliest: t = patience + 2 (patience + 1
//    if the pose does not move at all).
//  - kSuccessfulSteps: a counter of consecutive iterations whose LM made at most
//    successful_steps_threshold accepted steps; fires when it exceeds successful_steps_patience.
//  - Always: kMaxIterations at t == max_iterations (a hard cap whatever the criteria);
//    kZeroCost when an iteration's initial cost is zero (every association exact: nothing to
//    minimise) and kNumericalFailure when it is not finite, both checked before any ratio is
//    formed, so no NaN drop ever reaches a criterion.
//  - While a report says scale_settling (the coarse-to-fine EM scale is not settled yet), the
//    cost-drop, MSE and successful-steps counters are held at zero; fixed and cap still apply.
//  - A report that says lists_reused (the iteration re-solved the previous iteration's
//    associations: RegistrationOptions::reassociate_motion) neither counts nor resets those three
//    counters (while the scale settles they stay at zero, as above): its inner problem is the one
//    just solved, so its cost drop and motion are ~0 by construction and say nothing about
//    convergence. wants_fresh_lists() asks the solver to re-associate before the next iteration
//    when such a report would have counted (scale settled, and low by an enabled criterion's
//    rule) or while an enabled criterion's streak runs (its counter > 0). So every count comes
//    from an iteration on fresh associations, and a streak's iterations follow one another as
//    without reuse; fixed and cap still count every t. (MSE_t is still measured from the pose of
//    the iteration before, reused or not; the MSE ratio's reference MSE_{t-1} holds with the
//    counters.)
// With several criteria enabled the loop stops when any fires; the first in the order above wins.
#pragma once

#include <Eigen/Geometry>
#include <cstdint>

#include "ppcr/abi.hpp"
#include "ppcr/lm.hpp"

namespace ppcr {
inline namespace PPCR_ABI_NAMESPACE {

enum Criterion : std::uint32_t {
  kCriterionFixed = 1u << 0,
  kCriterionCostDrop = 1u << 1,
  kCriterionMsePrev = 1u << 2,
  kCriterionSuccessfulSteps = 1u << 3,
};

struct TerminationCriteria {
  std::uint32_t criteria = kCriterionCostDrop;  // bitwise OR of Criterion; stop when any fires
  int max_iterations = 100;            // hard cap on outer iterations, always active (>= 1)
  int fixed_iterations = 100;          // kCriterionFixed: stop at this iteration
  double cost_drop_threshold = 0.01;   // kCriterionCostDrop: relative drop (fraction, paper 1 %)
  int cost_drop_patience = 10;         // kCriterionCostDrop: consecutive low iterations tolerated
                                       // (paper 10; 20 in its Table 5)
  double cost_drop_max_motion = 0.02;  // kCriterionCostDrop: if > 0, an iteration counts as low
                                       // only when it also moved the source by less than this
                                       // fraction of the radius (RMS, sqrt of MSE_t); 0 = the
                                       // paper's rule (cost drop alone)
  double mse_ratio_threshold = 2.0;    // kCriterionMsePrev: low when MSE_t < MSE_{t-1} / this
  int mse_patience = 3;                // kCriterionMsePrev: consecutive low iterations tolerated
  int successful_steps_threshold = 1;  // kCriterionSuccessfulSteps: low when steps <= this
  int successful_steps_patience = 3;   // kCriterionSuccessfulSteps: consecutive lows tolerated
};

enum class StopReason {
  kNone,               // not stopped (still running)
  kFixedIterations,    // kCriterionFixed fired
  kCostDrop,           // kCriterionCostDrop fired
  kMsePrev,            // kCriterionMsePrev fired
  kSuccessfulSteps,    // kCriterionSuccessfulSteps fired
  kMaxIterations,      // the hard cap was reached before any criterion fired
  kZeroCost,           // an inner problem started with zero or non-finite cost
  kNoCorrespondences,  // an outer iteration found no source point with a neighbour in the radius
  kNumericalFailure,   // the LM solve failed (non-finite values)
  kInvalidInput,       // registration refused its input (see RegistrationResult::status)
  kCancelled,          // RegistrationOptions::on_iteration returned false
};

const char* to_string(StopReason reason);

/// True for the reasons that mean "a termination criterion decided" (fixed, cost drop, MSE,
/// successful steps); false for the hard cap, failures and refused input.
bool is_criterion_stop(StopReason reason);

/// What the solver hands the monitor after each outer iteration.
struct IterationReport {
  int iteration = 0;                                                  // 1-based outer iteration
  LMSummary lm;                                                       // the inner problem's summary
  Eigen::Isometry3d T_target_source = Eigen::Isometry3d::Identity();  // pose after the iteration
  double motion_reference = 1.0;  // length cost_drop_max_motion is relative to (the radius)
  bool scale_settling = false;    // the E-step scale is still coarse or shrinking (weights.hpp):
                                  // adaptive criteria neither count nor fire this iteration
  bool lists_reused = false;      // the iteration reused the last associations (no new ones):
                                  // adaptive counters hold (neither count nor reset; above)
};

}  // namespace PPCR_ABI_NAMESPACE
}  // namespace ppcr

#include "ppcr/metrics.hpp"

namespace ppcr {
inline namespace PPCR_ABI_NAMESPACE {

/// The termination monitor: one per registration, fed once per outer iteration.
class TerminationMonitor {
 public:
  /// source: moments of the source cloud being registered (for the MSE w.r.t. the previous
  /// iteration); T_initial: the pose before the first iteration.
  TerminationMonitor(const TerminationCriteria& criteria, const CloudMoments& source,
                     const Eigen::Isometry3d& T_initial);

  /// Takes the report of the outer iteration just finished; returns kNone to continue.
  StopReason update(const IterationReport& report);

  /// Values computed by the last update(): relative cost drop (NaN if the initial cost was zero
  /// or not finite) and MSE w.r.t. the previous pose.
  double last_cost_drop() const { return last_cost_drop_; }
  double last_mse_prev() const { return last_mse_prev_; }
  /// True when an enabled criterion's counter is above zero, or the last report had lists_reused
  /// and would have advanced one: the next iteration should associate afresh (file comment).
  bool wants_fresh_lists() const { return wants_fresh_lists_; }

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
  bool wants_fresh_lists_ = false;
};

}  // namespace PPCR_ABI_NAMESPACE
}  // namespace ppcr
