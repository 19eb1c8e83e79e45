// resolve_options.cpp - see resolve_options.hpp.
#include "registration/resolve_options.hpp"

#include <algorithm>
#include <cmath>

namespace ppcr {
inline namespace PPCR_ABI_NAMESPACE {
namespace detail {
namespace {
constexpr double kPlaneFineTolerance = 1e-2;
constexpr int kPlaneCoarseStride = 2;
constexpr std::size_t kMinCoarsePoints = 1000;
}  // namespace

RegistrationOptions in_internal_units(const RegistrationOptions& o, double unit) {
  RegistrationOptions n = o;
  n.on_iteration = nullptr;  // the caller keeps the user's
  n.radius = o.radius / unit;
  ExpertOptions& e = n.expert;
  if (e.scale_mode == ScaleMode::kRaw) {
    e.scale_mode = ScaleMode::kFixed;
    e.scale = 1.0 / unit;
  } else {
    e.scale = o.expert.scale / unit;
  }
  e.em_min_scale = o.expert.em_min_scale / unit;
  return n;
}

WeightParams weight_params(const RegistrationOptions& o) {
  WeightParams p;
  p.model = o.expert.weight_model;
  p.dof = o.dof;
  return p;
}

WeightOptions schedule_options(const RegistrationOptions& o, double target_surface_noise) {
  const ExpertOptions& e = o.expert;
  WeightOptions w;
  w.scale_mode = e.scale_mode;
  w.scale = e.scale;
  w.em_coarse_drop = e.em_coarse_drop;
  w.em_coarse_patience = e.em_coarse_patience;
  w.em_min_shrink = e.em_min_shrink;
  w.em_min_scale = e.em_min_scale;
  // The point model's surface noise is 0: no floor.
  const double noise_floor = e.noise_floor * target_surface_noise;
  if (std::isfinite(noise_floor)) w.em_min_scale = std::max(w.em_min_scale, noise_floor);
  return w;
}

TerminationCriteria termination_criteria(const RegistrationOptions& o) {
  const ExpertOptions& e = o.expert;
  TerminationCriteria c;
  c.criteria = o.criteria;
  c.max_iterations = o.max_iterations;
  c.fixed_iterations = e.fixed_iterations;
  c.cost_drop_threshold = e.cost_drop_threshold;
  c.cost_drop_patience = e.cost_drop_patience;
  c.cost_drop_max_motion = e.cost_drop_max_motion;
  c.mse_ratio_threshold = e.mse_ratio_threshold;
  c.mse_patience = e.mse_patience;
  c.successful_steps_threshold = e.successful_steps_threshold;
  c.successful_steps_patience = e.successful_steps_patience;
  return c;
}

LMOptions lm_options(const RegistrationOptions& o) {
  LMOptions lm;
  lm.max_iterations = o.expert.lm_max_iterations;
  lm.function_tolerance = o.expert.lm_function_tolerance;
  return lm;
}

double fine_function_tolerance(const RegistrationOptions& o) {
  const ExpertOptions& e = o.expert;
  if (e.scale_mode != ScaleMode::kEM) return 0.0;
  if (e.lm_fine_function_tolerance != ExpertOptions::kAutomatic) {
    return e.lm_fine_function_tolerance;
  }
  if (o.error_model != ErrorModel::kPlane || o.criteria != kCriterionCostDrop) return 0.0;
  const double loosened = std::min(kPlaneFineTolerance, e.cost_drop_threshold);
  return loosened > e.lm_function_tolerance ? loosened : 0.0;
}

std::size_t coarse_stride(const RegistrationOptions& o, std::size_t n) {
  if (o.expert.scale_mode != ScaleMode::kEM) return 1;
  int stride = o.expert.coarse_stride;
  if (stride == static_cast<int>(ExpertOptions::kAutomatic)) {
    stride = o.error_model == ErrorModel::kPlane ? kPlaneCoarseStride : 1;
  }
  return std::max<std::size_t>(1, std::min(static_cast<std::size_t>(stride), n / kMinCoarsePoints));
}

}  // namespace detail
}  // namespace PPCR_ABI_NAMESPACE
}  // namespace ppcr
