// scale_schedule.hpp - the E-step scale s across outer iterations: raw, fixed, or the
// coarse-to-fine EM schedule (ScaleMode::kEM):
//  1. coarse: s = scale (or radius / 2 when scale is 0) until the pose has settled at that
//     scale: the relative cost drop of more than em_coarse_patience consecutive outer iterations
//     was below em_coarse_drop (an iteration counts only when it moved the source by less than
//     em_coarse_max_motion x radius, RMS), or one iteration moved the source by less than
//     em_coarse_motion x s (RMS). A wide kernel has a wide basin: this is what lets PPCR leave
//     the local minima a small scale creates.
//  2. refine: after every outer iteration s^2 <- max(EM estimate, em_min_shrink x s^2,
//     em_min_scale^2), the EM estimate being sum_kj w_kj r_kj / (3 x matched source points) at
//     the final pose (the M-step of the scale).
// While the scale is coarse or still shrinking at the em_min_shrink limit, it is "settling": the
// adaptive termination criteria do not count (termination.hpp), and the registration registers
// the coarse level (associator.hpp) until the first iteration that is not settling.
#pragma once

#include "ppcr/abi.hpp"
#include "ppcr/options.hpp"

namespace ppcr {
inline namespace PPCR_ABI_NAMESPACE {

/// The schedule's settings. The defaults of the fields with an option are the option's
/// (ExpertOptions, options.hpp: each default is defined there once); resolve_options.cpp fills them
/// from the options. em_coarse_motion and em_coarse_max_motion have no option: defined here.
struct WeightOptions {
  ScaleMode scale_mode = ExpertOptions{}.scale_mode;
  // kFixed: s; kEM: the coarse s (0 = radius / 2). Cloud units.
  double scale = ExpertOptions{}.scale;
  // Coarse phase: a relative cost drop below em_coarse_drop for more than em_coarse_patience
  // consecutive iterations is settled...
  double em_coarse_drop = ExpertOptions{}.em_coarse_drop;
  int em_coarse_patience = ExpertOptions{}.em_coarse_patience;
  // ...or one iteration moving the source by less than this fraction of s (RMS).
  double em_coarse_motion = 1e-3;
  // A low counts only when the source moved by less than this fraction of the radius (RMS);
  // 0 = always.
  double em_coarse_max_motion = 0.02;
  // Refine: s^2 shrinks by at most this factor per iteration, down to em_min_scale (cloud units,
  // 0 = none).
  double em_min_shrink = ExpertOptions{}.em_min_shrink;
  double em_min_scale = ExpertOptions{}.em_min_scale;
};

namespace detail {

class ScaleSchedule {
 public:
  /// radius: the association radius (the coarse scale defaults to radius / 2).
  ScaleSchedule(const WeightOptions& options, double radius);

  /// s^2 for the next outer iteration, cloud units^2.
  double scale_sq() const { return scale_sq_; }

  /// True while the scale is coarse or still shrinking at the em_min_shrink limit.
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
