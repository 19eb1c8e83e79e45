// resolve_options.hpp - the public options resolved into each unit's settings: the E-step and scale
// schedule, the termination criteria, the inner LM, and the associator's speed measures.
#pragma once

#include <cstddef>

#include "model/normal_equations.hpp"
#include "ppcr/abi.hpp"
#include "ppcr/options.hpp"
#include "registration/scale_schedule.hpp"
#include "registration/termination.hpp"
#include "solver/lm_options.hpp"

namespace ppcr {
inline namespace PPCR_ABI_NAMESPACE {
namespace detail {

/// The options with every length divided by `unit` (cloud_preparation.hpp's internal frame): the
/// radius, the E-step scales and the scale floor. ScaleMode::kRaw's s = 1 cloud unit becomes the
/// fixed scale 1 / unit. The voxel leaves are applied before the change of unit and kept.
RegistrationOptions in_internal_units(const RegistrationOptions& o, double unit);

/// The E-step's model and dof (the scale is the schedule's).
WeightParams weight_params(const RegistrationOptions& o);

/// The scale schedule; with the plane model's noise floor, s >= noise_floor x surface_noise.
WeightOptions schedule_options(const RegistrationOptions& o, double target_surface_noise);

TerminationCriteria termination_criteria(const RegistrationOptions& o);

/// The inner LM's settings in the EM coarse phase (or throughout without the EM scale).
LMOptions lm_options(const RegistrationOptions& o);

/// The inner LM's function tolerance in the EM fine phase, or 0 for the coarse one throughout.
/// kAutomatic: with the plane model and the cost-drop criterion alone, 1e-2 capped at the
/// cost-drop threshold (a solve that ends on a step predicted to lower the cost by less than the
/// tolerance then counts as low only if that is also below the threshold); otherwise none. In the
/// fine phase the inner problem changes at every outer iteration (scale, weights, associations),
/// so solving each one to 1e-5 mostly re-confirms a pose.
double fine_function_tolerance(const RegistrationOptions& o);

/// The coarse level's stride for a source of n points (1 = none): only with the EM scale;
/// kAutomatic is 2 with the plane model and 1 with the point model (with which subsampling sent
/// lidar problems into a local minimum); lowered to n / 1000 where that is smaller, so the coarse
/// level keeps at least 1000 points.
std::size_t coarse_stride(const RegistrationOptions& o, std::size_t n);

}  // namespace detail
}  // namespace PPCR_ABI_NAMESPACE
}  // namespace ppcr
