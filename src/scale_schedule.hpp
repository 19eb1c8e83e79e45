// scale_schedule.hpp - the E-step scale s across outer iterations (raw, fixed, or the
// coarse-to-fine EM schedule documented in ppcr/weights.hpp).
#pragma once

#include "ppcr/abi.hpp"
#include "ppcr/weights.hpp"

namespace ppcr {
inline namespace PPCR_ABI_NAMESPACE {
namespace detail {

class ScaleSchedule {
 public:
  /// radius: the association radius (the coarse scale defaults to radius / 2).
  ScaleSchedule(const WeightOptions& options, double radius);

  /// s^2 for the next outer iteration, cloud units^2.
  double scale_sq() const { return scale_sq_; }

  /// True while the scale is coarse or still shrinking at the em_min_shrink limit: the
  /// adaptive termination criteria should not count this iteration.
  bool settling() const { return settling_; }

  /// True during the coarse phase of the EM schedule.
  bool coarse() const { return coarse_; }

  /// After an outer iteration: its relative cost drop, the RMS motion of the source it caused
  /// (sqrt of the MSE w.r.t. the previous pose), the EM estimate of s^2 at its final pose, and
  /// whether it reused the last associations (RegistrationOptions::reassociate_motion). A
  /// coarse-phase iteration on reused lists re-solved the problem just solved: its drop and
  /// motion are ~0 by construction, so it neither counts toward the end of the coarse phase nor
  /// resets the count, and ends nothing; if it would have, wants_fresh_lists() asks for fresh
  /// associations, whose iteration then decides (as termination.hpp does for the criteria).
  void update(double cost_drop, double rms_motion, double em_scale_sq, bool lists_reused = false);
  /// True in the coarse phase while a streak of low drops runs, or when the last update() reused
  /// lists and would have counted toward (or ended) the coarse phase: the next iteration should
  /// associate afresh.
  bool wants_fresh_lists() const { return wants_fresh_lists_; }

 private:
  WeightOptions options_;
  double radius_ = 1.0;
  double scale_sq_ = 1.0;
  bool coarse_ = false;
  bool settling_ = false;
  int low_drop_count_ = 0;
  bool wants_fresh_lists_ = false;
};

}  // namespace detail
}  // namespace PPCR_ABI_NAMESPACE
}  // namespace ppcr
