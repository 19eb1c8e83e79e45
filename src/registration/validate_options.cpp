// validate_options.cpp - validate(): every field of RegistrationOptions and ExpertOptions, by
// group.
#include <cmath>
#include <string>
#include <utility>

#include "association/association_table.hpp"
#include "common/format.hpp"
#include "ppcr/options.hpp"
#include "registration/pose_acceleration.hpp"

namespace ppcr {
inline namespace PPCR_ABI_NAMESPACE {
namespace {

using detail::num;

bool finite_positive(double v) { return std::isfinite(v) && v > 0.0; }
bool non_negative(double v) { return std::isfinite(v) && v >= 0.0; }

// Accumulates the first failure; each check names the field and the value seen.
class Checker {
 public:
  void require(bool ok, const char* field, const std::string& rule, const std::string& value) {
    if (ok || !status_.ok()) return;
    status_ = Status(StatusCode::kInvalidArgument,
                     std::string(field) + " must be " + rule + ", got " + value);
  }
  void non_negative_value(double v, const char* field) {
    require(non_negative(v), field, ">= 0", num(v));
  }
  void positive_value(double v, const char* field) {
    require(finite_positive(v), field, "> 0", num(v));
  }
  void int_range(int v, int lo, int hi, const char* field) {
    require(v >= lo && v <= hi, field,
            "in [" + std::to_string(lo) + ", " + std::to_string(hi) + "]", std::to_string(v));
  }
  const Status& status() const { return status_; }

 private:
  Status status_;
};

constexpr int kIntMax = 1 << 30;

void check_user(const RegistrationOptions& o, Checker* c) {
  c->require(o.radius == RegistrationOptions::kAutomaticRadius || finite_positive(o.radius),
             "radius", "> 0, or 0 for automatic", num(o.radius));
  c->int_range(o.max_neighbours, 1, detail::AssociationTable::kMaxNeighbours, "max_neighbours");
  if (o.expert.weight_model == WeightModel::kStudentT) c->positive_value(o.dof, "dof");
  for (const auto& [leaf, field] : {std::pair<double, const char*>{o.source_voxel, "source_voxel"},
                                    {o.target_voxel, "target_voxel"}}) {
    c->require(non_negative(leaf) || leaf == RegistrationOptions::kAutomaticVoxel, field,
               ">= 0 or kAutomaticVoxel (-1)", num(leaf));
  }
  c->require((o.criteria & ~std::uint32_t{0xF}) == 0, "criteria", "a combination of Criterion bits",
             std::to_string(o.criteria));
  c->int_range(o.max_iterations, 1, kIntMax, "max_iterations");
  c->int_range(o.num_threads, 1, 1024, "num_threads");
}

void check_e_step(const ExpertOptions& e, Checker* c) {
  if (e.scale_mode == ScaleMode::kFixed) {
    c->positive_value(e.scale, "expert.scale (fixed scale)");
  } else {
    c->non_negative_value(e.scale, "expert.scale");
  }
  c->non_negative_value(e.em_coarse_drop, "expert.em_coarse_drop");
  c->int_range(e.em_coarse_patience, 0, kIntMax, "expert.em_coarse_patience");
  c->require(e.em_min_shrink > 0.0 && e.em_min_shrink <= 1.0, "expert.em_min_shrink", "in (0, 1]",
             num(e.em_min_shrink));
  c->non_negative_value(e.em_min_scale, "expert.em_min_scale");
}

void check_plane(const ExpertOptions& e, Checker* c) {
  c->int_range(e.normal_neighbours, 5, 64, "expert.normal_neighbours");
  c->require(e.plane_epsilon > 0.0 && e.plane_epsilon <= 1.0, "expert.plane_epsilon", "in (0, 1]",
             num(e.plane_epsilon));
  c->non_negative_value(e.noise_floor, "expert.noise_floor");
}

void check_termination(const ExpertOptions& e, Checker* c) {
  c->int_range(e.fixed_iterations, 1, kIntMax, "expert.fixed_iterations");
  c->non_negative_value(e.cost_drop_threshold, "expert.cost_drop_threshold");
  c->int_range(e.cost_drop_patience, 0, kIntMax, "expert.cost_drop_patience");
  c->non_negative_value(e.cost_drop_max_motion, "expert.cost_drop_max_motion");
  c->int_range(e.acceleration_memory, 0, detail::PoseAcceleration::kMaxMemory,
               "expert.acceleration_memory");
  c->positive_value(e.mse_ratio_threshold, "expert.mse_ratio_threshold");
  c->int_range(e.mse_patience, 0, kIntMax, "expert.mse_patience");
  c->int_range(e.successful_steps_threshold, 0, kIntMax, "expert.successful_steps_threshold");
  c->int_range(e.successful_steps_patience, 0, kIntMax, "expert.successful_steps_patience");
}

void check_lm_and_speed(const ExpertOptions& e, Checker* c) {
  c->int_range(e.lm_max_iterations, 1, kIntMax, "expert.lm_max_iterations");
  c->non_negative_value(e.lm_function_tolerance, "expert.lm_function_tolerance");
  c->require(e.lm_fine_function_tolerance == ExpertOptions::kAutomatic ||
                 non_negative(e.lm_fine_function_tolerance),
             "expert.lm_fine_function_tolerance", ">= 0 or ExpertOptions::kAutomatic (-1)",
             num(e.lm_fine_function_tolerance));
  c->int_range(e.neighbour_cache, 0, 1024, "expert.neighbour_cache");
  c->require(e.coarse_stride == static_cast<int>(ExpertOptions::kAutomatic) ||
                 (e.coarse_stride >= 1 && e.coarse_stride <= 64),
             "expert.coarse_stride", "in [1, 64] or ExpertOptions::kAutomatic (-1)",
             std::to_string(e.coarse_stride));
}

}  // namespace

Status validate(const RegistrationOptions& options) {
  Checker c;
  check_user(options, &c);
  check_e_step(options.expert, &c);
  if (options.error_model == ErrorModel::kPlane) check_plane(options.expert, &c);
  check_termination(options.expert, &c);
  check_lm_and_speed(options.expert, &c);
  return c.status();
}

}  // namespace PPCR_ABI_NAMESPACE
}  // namespace ppcr
