// options.hpp - what a user sets for a registration, with defaults, units and ranges.
//
// RegistrationOptions holds the settings a user chooses; ExpertOptions holds the research and
// speed parameters of the method, each with the default that measured best (docs/BENCHMARK.md,
// docs/PERFORMANCE.md). validate() checks both and names the field and the value it refuses.
#pragma once

#include <cstddef>
#include <cstdint>
#include <functional>

#include "ppcr/abi.hpp"
#include "ppcr/status.hpp"

namespace ppcr {
inline namespace PPCR_ABI_NAMESPACE {

/// How the error of an association (source point x_j, target point y_k) is measured.
enum class ErrorModel {
  /// Point-to-point (paper eq. 1): r_kj = |e_kj|^2, e_kj = y_k - T x_j.
  kPoint,
  /// Plane-aware: r_kj = e_kj^T Omega e_kj with Omega = n n^T + epsilon I, n the unit normal of a
  /// PCA plane fit to y_k's nearest target points (or, with ExpertOptions::source_normals, the
  /// mean of the target's and the rotated source's normals). The error along the surface normal
  /// counts fully, along the surface by epsilon only, so points are not dragged along a surface to
  /// their sampled counterparts. Omega replaces |e|^2 everywhere: the E-step, the cost, the EM
  /// scale and the LM normal equations.
  kPlane,
};

/// The E-step's posterior (paper eq. 2-4).
enum class WeightModel {
  kStudentT,  // eq. 3-4: heavy-tailed, robust to outliers (default)
  kGaussian,  // eq. 2: the limit dof -> infinity
};

/// The E-step scale s (the standard deviation of the residuals, cloud units).
enum class ScaleMode {
  kRaw,    // s = 1 cloud unit: the paper's (the weights then depend on the data's units)
  kFixed,  // s = ExpertOptions::scale
  kEM,     // coarse-to-fine (default): s held at a wide value until the pose settles, then
           // re-estimated by EM after every outer iteration (docs/TERMINATION.md)
};

/// Termination criteria (paper Sec. 3.2), bits of RegistrationOptions::criteria; the loop stops
/// when any enabled one fires (docs/TERMINATION.md gives each rule).
enum Criterion : std::uint32_t {
  kCriterionFixed = 1u << 0,            // at ExpertOptions::fixed_iterations
  kCriterionCostDrop = 1u << 1,         // eq. 7: relative cost drop (default)
  kCriterionMsePrev = 1u << 2,          // eq. 5-6: motion w.r.t. the previous iteration
  kCriterionSuccessfulSteps = 1u << 3,  // inner LM accepted steps per solve
};

/// Research and speed parameters. Their defaults are the best measured; change them to study the
/// method, not to make a registration work (set radius, voxels and neighbours for that).
struct ExpertOptions {
  static constexpr double kAutomatic = -1.0;

  // E-step (weights and scale).
  WeightModel weight_model = WeightModel::kStudentT;
  ScaleMode scale_mode = ScaleMode::kEM;
  double scale = 0.0;            // kFixed: s (> 0). kEM: the coarse s (0 = radius / 2). Cloud units
  double em_coarse_drop = 0.01;  // kEM coarse phase: a relative cost drop below this is settled...
  int em_coarse_patience = 5;    // ...for more than this many consecutive iterations (>= 0)
  double em_min_shrink = 0.25;   // kEM fine phase: s^2 shrinks by at most this factor per
                                 // iteration, in (0, 1]
  double em_min_scale = 0.0;     // kEM fine phase: floor on s, cloud units (>= 0; 0 = none)

  // Plane error model.
  int normal_neighbours = 20;   // target (and source) points per PCA normal fit, [5, 64]
  double plane_epsilon = 0.05;  // in-plane weight epsilon of Omega, (0, 1]
  bool source_normals = true;   // pairs use the mean of both clouds' normals (GICP-like)
  bool reject_boundary = true;  // plane model, kEM: after the coarse phase, leave out the source
                                // points whose nearest target point lies on the target's
                                // boundary, unless over half of the matched ones would go
                                // (docs/BENCHMARK.md)
  double noise_floor = 0.8;     // kEM: floor s at this multiple of the target's surface noise
                                // (RegistrationResult::target_surface_noise); >= 0, 0 = none

  // Termination (docs/TERMINATION.md).
  int fixed_iterations = 100;          // kCriterionFixed: stop at this iteration (>= 1)
  double cost_drop_threshold = 0.01;   // kCriterionCostDrop: low drop, fraction (paper: 1 %), >= 0
  int cost_drop_patience = 4;          // kCriterionCostDrop: low iterations tolerated (paper: 10)
  double cost_drop_max_motion = 0.03;  // kCriterionCostDrop: a low iteration must also move the
                                       // source by less than this fraction of the radius (RMS);
                                       // 0 = the paper's rule
  int acceleration_memory = 3;         // kEM coarse phase: Anderson acceleration of the outer
                                       // loop's pose with this memory m (from the last m + 1
                                       // iterations), [0, 8]; 0 = the paper's plain loop
                                       // (docs/TERMINATION.md)
  double mse_ratio_threshold = 2.0;    // kCriterionMsePrev: low when MSE_t < MSE_{t-1} / this (> 0)
  int mse_patience = 3;                // kCriterionMsePrev: low iterations tolerated (>= 0)
  int successful_steps_threshold = 1;  // kCriterionSuccessfulSteps: low when steps <= this (>= 0)
  int successful_steps_patience = 3;   // kCriterionSuccessfulSteps: low iterations tolerated

  // Inner Levenberg-Marquardt.
  int lm_max_iterations = 50;           // LM steps (accepted + rejected) per solve (>= 1)
  double lm_function_tolerance = 1e-5;  // a solve ends when an accepted step lowers the cost by
                                        // less than this fraction (authors: 1e-5), >= 0
  double lm_fine_function_tolerance = kAutomatic;  // the same in the EM fine phase (>= 0);
                                                   // kAutomatic: 1e-2 capped at the cost-drop
                                                   // threshold with the plane model and the
                                                   // cost-drop criterion alone, else none

  // Speed; the registration's result does not depend on them beyond rounding.
  int neighbour_cache = 4;  // extra candidates kept per point for exact incremental association
                            // (0 = query the k-d tree for every point in every iteration)
  int coarse_stride = static_cast<int>(kAutomatic);  // kEM: while the scale settles (coarse,
                                                     // then shrinking at its limit) register
                                                     // every n-th source point (Z-order),
                                                     // [1, 64]; kAutomatic: 2 (plane), 1 (point)
};

struct IterationRecord;

/// What a user sets. Lengths are in cloud units (the units of the points), whatever they are:
/// the solver divides every length by the radius (or the target's extent when smaller), so the
/// same pair in millimetres or kilometres, lengths scaled alike, gives the same rotation.
struct RegistrationOptions {
  /// radius = kAutomaticRadius: kAutomaticRadiusSpacings x the (filtered) target's median point
  /// spacing (RegistrationResult::target_spacing); the radius used is RegistrationResult::radius.
  /// It matches the tuned radius on both shared sets; a radius set from the expected
  /// misalignment does better where that is known (docs/BENCHMARK.md, "The automatic radius").
  static constexpr double kAutomaticRadius = 0.0;
  static constexpr double kAutomaticRadiusSpacings = 8.0;
  double radius = kAutomaticRadius;  // association radius (> 0, or automatic): farther target
                                     // points are ignored; it must cover the misalignment
  int max_neighbours = 6;            // target points associated per source point, k, [1, 1024]
  ErrorModel error_model = ErrorModel::kPlane;
  double dof = 1.25;          // Student-t degrees of freedom nu (finite, > 0; authors: 5); as nu
                              // grows the weights tend to kGaussian's (to 1e-9 from about 1e12)
  /// source_voxel or target_voxel = kAutomaticVoxel: that cloud's leaf is chosen from the cloud,
  /// the one that leaves about kAutomaticVoxelPoints points (within 15 % but on odd clouds; a
  /// smaller cloud is not filtered); the leaves used are RegistrationResult::source_voxel and
  /// target_voxel.
  static constexpr double kAutomaticVoxel = -1.0;
  static constexpr std::size_t kAutomaticVoxelPoints = 10000;
  double source_voxel = 0.0;  // voxel-grid leaf for the source (>= 0, or automatic; 0 = none)
  double target_voxel = 0.0;  // voxel-grid leaf for the target (>= 0, or automatic; 0 = none)
  std::uint32_t criteria = kCriterionCostDrop;  // bitwise OR of Criterion
  int max_iterations = 100;    // hard cap on outer iterations, whatever the criteria (>= 1)
  int num_threads = 1;         // threads, [1, 1024]; the result does not depend on it
  bool record_history = true;  // keep one IterationRecord per outer iteration in the result
  /// Called after each outer iteration on the calling thread (progress, time budgets). Return
  /// false to stop (StopReason::kCancelled). Must not throw.
  std::function<bool(const IterationRecord&)> on_iteration;
  ExpertOptions expert;
};

/// Checks every field; the message names the field and the value seen.
Status validate(const RegistrationOptions& options);

}  // namespace PPCR_ABI_NAMESPACE
}  // namespace ppcr
