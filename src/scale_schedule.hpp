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
  /// (sqrt of the MSE w.r.t. the previous pose), and the EM estimate of s^2 at its final pose.
  void update(double cost_drop, double rms_motion, double em_scale_sq);

 private:
  WeightOptions options_;
  double radius_ = 1.0;
  double scale_sq_ = 1.0;
  bool coarse_ = false;
  bool settling_ = false;
  int low_drop_count_ = 0;
};

}  // namespace detail
}  // namespace PPCR_ABI_NAMESPACE
}  // namespace ppcr
