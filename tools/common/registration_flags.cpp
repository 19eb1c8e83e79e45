// registration_flags.cpp - CLI flags -> RegistrationOptions.
#include "common/registration_flags.hpp"

#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <sstream>

namespace ppcr_tools {
namespace {

ppcr::Status bad(const std::string& flag, const std::string& value, const std::string& why) {
  return ppcr::Status(ppcr::StatusCode::kInvalidArgument, flag + " " + value + ": " + why);
}

std::string str(double v) {
  std::ostringstream s;
  s << v;
  return s.str();
}

// text as a finite number (the whole of it, in range), else false.
bool parse_finite(const std::string& text, double* v) {
  errno = 0;
  char* end = nullptr;
  *v = std::strtod(text.c_str(), &end);
  return !text.empty() && *end == '\0' && errno == 0 && std::isfinite(*v);
}

}  // namespace

void add_registration_flags(CLI::App& app, RegistrationFlags* f) {
  app.add_option("--radius", f->radius,
                 "association radius, cloud units (default " + str(f->radius) + ")");
  app.add_option("--max-neighbours", f->max_neighbours,
                 "target points associated with each source point (default " +
                     std::to_string(f->max_neighbours) + ")");
  app.add_option("--dof", f->dof, "Student-t degrees of freedom (default " + str(f->dof) + ")");
  app.add_flag("--gaussian", f->gaussian, "Gaussian weights (paper eq. 2) instead of Student-t");
  app.add_option("--scale", f->scale,
                 "E-step scale: em (coarse-to-fine EM, default), raw (the paper's unit "
                 "variance: depends on the data's units), or a fixed value in cloud units");
  app.add_option("--coarse-scale", f->coarse_scale,
                 "EM's coarse scale, cloud units (default 0 = radius / 2)");
  app.add_option("--min-scale", f->min_scale,
                 "EM scale: floor on the refined scale s, cloud units (default 0 = none)");
  app.add_option("--criterion", f->criterion,
                 "termination: cost-drop (default), mse-prev, successful-steps, fixed, or a "
                 "comma-separated combination (stops when any fires)");
  app.add_option(
      "--cost-drop-threshold", f->cost_drop_threshold,
      "relative cost drop counted as low (default " + str(f->cost_drop_threshold) + " = 1 %)");
  app.add_option("--patience", f->patience,
                 "consecutive low iterations tolerated by cost-drop (default " +
                     std::to_string(f->patience) + "; the paper also uses 20)");
  app.add_option("--max-iterations", f->max_iterations,
                 "hard cap on outer iterations; with --criterion fixed, the iterations run "
                 "(default " +
                     std::to_string(f->max_iterations) + ")");
  app.add_option("--mse-ratio", f->mse_ratio,
                 "mse-prev: low when MSE_t < MSE_{t-1} / this (default " + str(f->mse_ratio) + ")");
  app.add_option("--mse-patience", f->mse_patience,
                 "mse-prev: consecutive low iterations tolerated (default " +
                     std::to_string(f->mse_patience) + ")");
  app.add_option("--steps-threshold", f->steps_threshold,
                 "successful-steps: low when LM accepted at most this many steps (default " +
                     std::to_string(f->steps_threshold) + ")");
  app.add_option("--error-model", f->error_model,
                 "plane (Mahalanobis error along the target's local surface normal; default) or "
                 "point (point-to-point, the paper's)");
  app.add_option("--plane-epsilon", f->plane_epsilon,
                 "plane model: in-plane weight of Omega = n n^T + epsilon I (default " +
                     str(f->plane_epsilon) + ")");
  app.add_option("--normal-neighbours", f->normal_neighbours,
                 "plane model: target points per normal fit (default " +
                     std::to_string(f->normal_neighbours) + ")");
  app.add_flag("--source-normals", f->source_normals,
               "plane model: also fit source normals and use each pair's mean normal");
  app.add_option("--noise-floor", f->noise_floor,
                 "plane model with the EM scale: the scale never shrinks below this multiple of "
                 "the target's surface noise (median RMS out-of-plane spread of its normal fits; "
                 "default " +
                     str(f->noise_floor) + " = off)");
  app.add_option("--motion-guard", f->motion_guard,
                 "an iteration counts as settled (cost-drop criterion and EM coarse phase) only "
                 "if it moved the source by less than this fraction of the radius, RMS (default " +
                     str(f->motion_guard) + "; 0 = the paper's rule)");
  app.add_option("--coarse-patience", f->coarse_patience,
                 "EM scale: settled iterations ending the coarse phase (default " +
                     std::to_string(f->coarse_patience) + ")");
  app.add_option("--scale-shrink", f->scale_shrink,
                 "EM scale: s^2 shrinks by at most this factor per outer iteration, in (0, 1] "
                 "(default " +
                     str(f->scale_shrink) + ")");
  app.add_option("--neighbour-cache", f->neighbour_cache,
                 "extra candidates kept per source point for exact incremental association "
                 "(default " +
                     std::to_string(f->neighbour_cache) +
                     "; 0 = a k-d tree query per point and iteration; same result either way)");
  app.add_option("--coarse-stride", f->coarse_stride,
                 "EM scale: register every this-th source point during the coarse phase, every "
                 "point after it: auto (default: " +
                     std::to_string(ppcr::RegistrationOptions::kPlaneCoarseStride) +
                     " with the plane model, 1 with the point model) or an integer in [1, " +
                     std::to_string(ppcr::RegistrationOptions::kMaxCoarseStride) +
                     "] (1 = every point throughout, the paper); lowered to keep at least " +
                     std::to_string(ppcr::RegistrationOptions::kMinCoarsePoints) + " points");
  app.add_option("--lm-tolerance", f->lm_tolerance,
                 "inner LM: stop after a step lowering the cost by less than this fraction of it "
                 "(default " +
                     str(f->lm_tolerance) + ", the authors')");
  app.add_option("--lm-fine-tolerance", f->lm_fine_tolerance,
                 "EM scale: the inner LM's --lm-tolerance once the scale has left its coarse "
                 "phase: auto (default: " +
                     str(ppcr::LMOptions::kPlaneFineTolerance) +
                     " with the plane model and --criterion cost-drop, at most "
                     "--cost-drop-threshold; otherwise, or if that is not above --lm-tolerance, "
                     "off), or a number (0 = --lm-tolerance throughout; keep it <= "
                     "--cost-drop-threshold; docs/PERFORMANCE.md)");
  app.add_option("--reassociate-motion", f->reassociate_motion,
                 "re-associate only when a source point may have moved more than this fraction "
                 "of the radius since the last association (default " +
                     str(f->reassociate_motion) + "; 0 = every iteration, the paper)");
  app.add_option("--source-voxel", f->source_voxel,
                 "voxel-grid leaf for the source, cloud units (default 0 = off)");
  app.add_option("--target-voxel", f->target_voxel,
                 "voxel-grid leaf for the target, cloud units (default 0 = off)");
  app.add_option("--threads", f->threads, "threads (default 1; results do not depend on it)");
}

ppcr::Status to_options(const RegistrationFlags& f, ppcr::RegistrationOptions* o) {
  *o = ppcr::RegistrationOptions();
  o->radius = f.radius;
  o->max_neighbours = f.max_neighbours;
  o->weights.dof = f.dof;
  o->weights.model = f.gaussian ? ppcr::WeightModel::kGaussian : ppcr::WeightModel::kStudentT;
  if (f.scale == "em") {
    o->weights.scale_mode = ppcr::ScaleMode::kEM;
    o->weights.scale = f.coarse_scale;
    o->weights.em_min_scale = f.min_scale;
  } else if (f.scale == "raw") {
    o->weights.scale_mode = ppcr::ScaleMode::kRaw;
  } else {
    double s = 0.0;
    if (!(parse_finite(f.scale, &s) && s > 0.0)) {
      return bad("--scale", f.scale, "expected em, raw or a positive number");
    }
    o->weights.scale_mode = ppcr::ScaleMode::kFixed;
    o->weights.scale = s;
  }
  if (!(std::isfinite(f.coarse_scale) && f.coarse_scale >= 0.0)) {
    return bad("--coarse-scale", str(f.coarse_scale), "expected a number >= 0");
  }
  if (!(std::isfinite(f.min_scale) && f.min_scale >= 0.0)) {
    return bad("--min-scale", str(f.min_scale), "expected a number >= 0");
  }
  if (f.min_scale > 0.0 && f.scale != "em") {
    return bad("--min-scale", str(f.min_scale), "needs --scale em, got --scale " + f.scale);
  }

  std::uint32_t criteria = 0;
  std::stringstream list(f.criterion);
  std::string name;
  while (std::getline(list, name, ',')) {
    if (name == "cost-drop") {
      criteria |= ppcr::kCriterionCostDrop;
    } else if (name == "mse-prev") {
      criteria |= ppcr::kCriterionMsePrev;
    } else if (name == "successful-steps") {
      criteria |= ppcr::kCriterionSuccessfulSteps;
    } else if (name == "fixed") {
      criteria |= ppcr::kCriterionFixed;
    } else {
      return bad("--criterion", f.criterion,
                 "unknown criterion '" + name +
                     "' (expected cost-drop, mse-prev, successful-steps or fixed)");
    }
  }
  if (criteria == 0) return bad("--criterion", "''", "expected at least one criterion");
  ppcr::TerminationCriteria& c = o->termination;
  c.criteria = criteria;
  c.cost_drop_threshold = f.cost_drop_threshold;
  c.cost_drop_patience = f.patience;
  c.max_iterations = f.max_iterations;
  c.fixed_iterations = f.max_iterations;
  c.mse_ratio_threshold = f.mse_ratio;
  c.mse_patience = f.mse_patience;
  c.successful_steps_threshold = f.steps_threshold;
  if (f.error_model == "point") {
    o->error_model = ppcr::ErrorModel::kPoint;
  } else if (f.error_model == "plane") {
    o->error_model = ppcr::ErrorModel::kPlane;
  } else {
    return bad("--error-model", f.error_model, "expected point or plane");
  }
  o->plane.epsilon = f.plane_epsilon;
  o->plane.normal_neighbours = f.normal_neighbours;
  if (f.source_normals && o->error_model != ppcr::ErrorModel::kPlane) {
    return bad("--source-normals", "set", "needs --error-model plane, got " + f.error_model);
  }
  o->plane.source_normals = f.source_normals;
  if (!(std::isfinite(f.noise_floor) && f.noise_floor >= 0.0)) {
    return bad("--noise-floor", str(f.noise_floor), "expected a number >= 0");
  }
  if (f.noise_floor > 0.0 && o->error_model != ppcr::ErrorModel::kPlane) {
    return bad("--noise-floor", str(f.noise_floor),
               "needs --error-model plane, got " + f.error_model);
  }
  if (f.noise_floor > 0.0 && f.scale != "em") {
    return bad("--noise-floor", str(f.noise_floor), "needs --scale em, got --scale " + f.scale);
  }
  o->plane.noise_floor = f.noise_floor;
  if (!(std::isfinite(f.motion_guard) && f.motion_guard >= 0.0)) {
    return bad("--motion-guard", str(f.motion_guard), "expected a number >= 0");
  }
  c.cost_drop_max_motion = f.motion_guard;
  o->weights.em_coarse_max_motion = f.motion_guard;
  if (f.coarse_patience < 0) {
    return bad("--coarse-patience", std::to_string(f.coarse_patience), "expected >= 0");
  }
  o->weights.em_coarse_patience = f.coarse_patience;
  if (!(f.scale_shrink > 0.0 && f.scale_shrink <= 1.0)) {
    return bad("--scale-shrink", str(f.scale_shrink), "expected a number in (0, 1]");
  }
  o->weights.em_min_shrink = f.scale_shrink;
  if (!(std::isfinite(f.reassociate_motion) && f.reassociate_motion >= 0.0)) {
    return bad("--reassociate-motion", str(f.reassociate_motion), "expected a number >= 0");
  }
  o->reassociate_motion = f.reassociate_motion;
  if (f.neighbour_cache < 0) {
    return bad("--neighbour-cache", std::to_string(f.neighbour_cache), "expected >= 0");
  }
  o->neighbour_cache = f.neighbour_cache;
  if (f.coarse_stride == "auto") {
    o->coarse_stride = ppcr::RegistrationOptions::kAutomatic;
  } else {
    const int max_stride = ppcr::RegistrationOptions::kMaxCoarseStride;
    double v = 0.0;
    if (!(parse_finite(f.coarse_stride, &v) && v >= 1.0 && v <= max_stride && v == std::floor(v))) {
      return bad("--coarse-stride", f.coarse_stride,
                 "expected auto or an integer in [1, " + std::to_string(max_stride) + "]");
    }
    if (v > 1.0 && f.scale != "em") {
      return bad("--coarse-stride", f.coarse_stride, "needs --scale em, got --scale " + f.scale);
    }
    o->coarse_stride = static_cast<int>(v);
  }
  if (!(std::isfinite(f.lm_tolerance) && f.lm_tolerance >= 0.0)) {
    return bad("--lm-tolerance", str(f.lm_tolerance), "expected a number >= 0");
  }
  o->lm.function_tolerance = f.lm_tolerance;
  if (f.lm_fine_tolerance == "auto") {
    o->lm.fine_function_tolerance = ppcr::LMOptions::kAutomatic;
  } else {
    double v = 0.0;
    if (!(parse_finite(f.lm_fine_tolerance, &v) && v >= 0.0)) {
      return bad("--lm-fine-tolerance", f.lm_fine_tolerance, "expected auto or a number >= 0");
    }
    if (v > 0.0 && f.scale != "em") {
      return bad("--lm-fine-tolerance", f.lm_fine_tolerance,
                 "needs --scale em, got --scale " + f.scale);
    }
    o->lm.fine_function_tolerance = v;
  }
  o->source_voxel = f.source_voxel;
  o->target_voxel = f.target_voxel;
  o->num_threads = f.threads;

  // The core's validation, re-worded with the flag names.
  const ppcr::Status s = ppcr::validate(*o);
  if (!s.ok()) {
    if (!(std::isfinite(f.radius) && f.radius > 0.0)) {
      return bad("--radius", str(f.radius), "expected a number > 0");
    }
    if (f.max_neighbours < 1 || f.max_neighbours > 1024) {
      return bad("--max-neighbours", std::to_string(f.max_neighbours), "expected 1..1024");
    }
    if (!f.gaussian && !(std::isfinite(f.dof) && f.dof > 0.0)) {
      return bad("--dof", str(f.dof), "expected a number > 0");
    }
    if (f.max_iterations < 1) {
      return bad("--max-iterations", std::to_string(f.max_iterations), "expected >= 1");
    }
    if (f.patience < 0) return bad("--patience", std::to_string(f.patience), "expected >= 0");
    if (f.mse_patience < 0) {
      return bad("--mse-patience", std::to_string(f.mse_patience), "expected >= 0");
    }
    if (!(std::isfinite(f.mse_ratio) && f.mse_ratio > 0.0)) {
      return bad("--mse-ratio", str(f.mse_ratio), "expected a number > 0");
    }
    if (!std::isfinite(f.cost_drop_threshold)) {
      return bad("--cost-drop-threshold", str(f.cost_drop_threshold), "expected a number");
    }
    if (!(std::isfinite(f.source_voxel) && f.source_voxel >= 0.0)) {
      return bad("--source-voxel", str(f.source_voxel), "expected a number >= 0");
    }
    if (!(std::isfinite(f.target_voxel) && f.target_voxel >= 0.0)) {
      return bad("--target-voxel", str(f.target_voxel), "expected a number >= 0");
    }
    if (f.normal_neighbours < 5 || f.normal_neighbours > 64) {
      return bad("--normal-neighbours", std::to_string(f.normal_neighbours), "expected 5..64");
    }
    if (!(f.plane_epsilon > 0.0 && f.plane_epsilon <= 1.0)) {
      return bad("--plane-epsilon", str(f.plane_epsilon), "expected a number in (0, 1]");
    }
    if (f.threads < 1 || f.threads > 1024) {
      return bad("--threads", std::to_string(f.threads), "expected 1..1024");
    }
    return s;
  }
  return ppcr::Status::Ok();
}

}  // namespace ppcr_tools
