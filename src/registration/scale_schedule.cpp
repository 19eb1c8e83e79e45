// scale_schedule.cpp - the schedule documented in scale_schedule.hpp.
#include "registration/scale_schedule.hpp"

#include <algorithm>
#include <cmath>

namespace ppcr {
inline namespace PPCR_ABI_NAMESPACE {
namespace detail {

ScaleSchedule::ScaleSchedule(const WeightOptions& options, double radius)
    : options_(options), radius_(radius) {
  switch (options.scale_mode) {
    case ScaleMode::kRaw:
      scale_sq_ = 1.0;
      break;
    case ScaleMode::kFixed:
      scale_sq_ = options.scale * options.scale;
      break;
    case ScaleMode::kEM: {
      const double s0 = options.scale > 0.0 ? options.scale : 0.5 * radius;
      scale_sq_ = s0 * s0;
      coarse_ = settling_ = true;
      break;
    }
  }
}

void ScaleSchedule::update(double cost_drop, double rms_motion, double em_scale_sq) {
  if (options_.scale_mode != ScaleMode::kEM) return;
  if (coarse_) {
    // Phase 1: hold s until the pose has settled at this scale. (NaN drops count as settled.)
    const bool slow = options_.em_coarse_max_motion <= 0.0 ||
                      rms_motion < options_.em_coarse_max_motion * radius_;
    const bool low = slow && !(cost_drop >= options_.em_coarse_drop);
    const bool still = rms_motion < options_.em_coarse_motion * std::sqrt(scale_sq_);
    low_drop_count_ = low ? low_drop_count_ + 1 : 0;
    if (low_drop_count_ <= options_.em_coarse_patience && !still) return;
    coarse_ = false;  // settled: the EM updates start with this iteration's estimate
  }
  // Phase 2: EM estimate, shrinking by at most em_min_shrink per iteration, floored.
  const double limit_sq = options_.em_min_shrink * scale_sq_;
  const double floor_sq = options_.em_min_scale * options_.em_min_scale;
  double next = std::max({em_scale_sq, limit_sq, floor_sq});
  settling_ = em_scale_sq < limit_sq && limit_sq > floor_sq;
  if (std::isfinite(next) && next > 0.0) scale_sq_ = next;
}

}  // namespace detail
}  // namespace PPCR_ABI_NAMESPACE
}  // namespace ppcr
