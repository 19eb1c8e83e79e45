// result.hpp - what a registration returns: the pose, why it stopped, and its trace.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cstddef>
#include <vector>

#include "ppcr/abi.hpp"
#include "ppcr/status.hpp"

namespace ppcr {
inline namespace PPCR_ABI_NAMESPACE {

enum class StopReason {
  kNone,               // not stopped (still running)
  kFixedIterations,    // kCriterionFixed fired
  kCostDrop,           // kCriterionCostDrop fired
  kMsePrev,            // kCriterionMsePrev fired
  kSuccessfulSteps,    // kCriterionSuccessfulSteps fired
  kMaxIterations,      // the hard cap was reached before any criterion fired
  kZeroCost,           // an inner problem started with zero cost: every association exact
  kNoCorrespondences,  // an outer iteration found no source point with a neighbour in the radius
  kNumericalFailure,   // the LM solve failed (non-finite values)
  kInvalidInput,       // registration refused its input (see RegistrationResult::status)
  kCancelled,          // RegistrationOptions::on_iteration returned false
};

const char* to_string(StopReason reason);

/// The verdict on a result (RegistrationResult::quality), from its measures of agreement; the
/// rules and how they were chosen are in docs/BENCHMARK.md ("The verdict").
enum class Quality {
  kGood,    // the clouds agree: no rule below fired
  kWeak,    // plausible, but a warning sign: low fitness, a loose fit, free directions with a
            // loose fit, the iteration cap or a cancel; check it
  kFailed,  // refused input or a failure, nothing matched, or most matched points off the
            // target's surface: the pose is not to be used
};

const char* to_string(Quality quality);

/// True for the reasons that mean "a termination criterion decided" (fixed, cost drop, MSE,
/// successful steps, zero cost); false for the hard cap, failures and refused input.
bool is_criterion_stop(StopReason reason);

/// One row of the per-iteration trace.
struct IterationRecord {
  int iteration = 0;           // 1-based
  bool coarse = false;         // the EM scale's coarse phase (a wide scale, a subsampled source)
  int successful_steps = 0;    // LM accepted steps
  int unsuccessful_steps = 0;  // LM rejected steps
  double initial_cost = 0.0;   // inner problem's cost before / after LM
  double final_cost = 0.0;
  double cost_drop = 0.0;  // (initial - final) / initial (paper eq. 7); NaN when initial is 0
  double mse_prev = 0.0;   // mean |T_t x - T_{t-1} x|^2 over the source (eq. 5), cloud units^2
  double scale = 0.0;      // s used by the E-step, cloud units
  // Associated (source, target) pairs and source points with at least one neighbour (of the
  // subsampled source while the EM scale settles: the coarse phase and the halving after it),
  // rows left out beyond the target's boundary included.
  std::size_t correspondences = 0;
  std::size_t matched_source_points = 0;
  Eigen::Isometry3d T_target_source = Eigen::Isometry3d::Identity();  // pose after the iteration
  double time_ms = 0.0;  // wall time of this outer iteration
};

struct RegistrationResult {
  Status status;  // not ok: input refused or a failure (see stop_reason)
  StopReason stop_reason = StopReason::kNone;
  /// Maps source into target. Refused input: the initial guess (identity if it is not finite).
  Eigen::Isometry3d T_target_source = Eigen::Isometry3d::Identity();
  int iterations = 0;             // outer iterations run
  int lm_iterations = 0;          // LM steps over all outer iterations (accepted + rejected)
  int lm_successful_steps = 0;    // accepted LM steps over all outer iterations
  double initial_cost = 0.0;      // first inner problem's initial cost
  double final_cost = 0.0;        // last inner problem's final cost
  double scale = 0.0;             // final E-step scale s (cloud units)
  std::size_t source_points = 0;  // source points registered (after filtering)
  std::size_t target_points = 0;  // target points (after filtering)
  // Source points with a neighbour and associated pairs in the last iteration, those left out
  // beyond the target's boundary (ExpertOptions::reject_boundary) included; the costs and the
  // scale are of the rows used.
  std::size_t matched_source_points = 0;
  std::size_t correspondences = 0;
  // Points dropped as non-finite, or so far from the cloud's median that their squared distance
  // overflows (|p - median| > ~1e154).
  std::size_t source_non_finite = 0;
  std::size_t target_non_finite = 0;
  // Copies of a kept point, registered once: equal in the solver's frame (centred and scaled;
  // exact copies, or points within a rounding of each other), after the voxel filter. The points
  // in source_points / target_points are distinct. The minimum of 3 points counts copies: a
  // cloud of identical points registers as one point.
  std::size_t source_duplicates = 0;
  std::size_t target_duplicates = 0;
  /// Plane model: the target's surface noise, cloud units: the median RMS distance of a normal
  /// fit's points from their plane (sensor noise and roughness); 0 for the point model.
  double target_surface_noise = 0.0;
  /// The target's point spacing, cloud units: the median distance from a (filtered) target point
  /// to its nearest other point (duplicates skipped), over every floor(n / 4096)-th point.
  double target_spacing = 0.0;
  /// The association radius used, cloud units: RegistrationOptions::radius, or the automatic one.
  double radius = 0.0;
  /// The voxel leaves used, cloud units (0: that cloud was not filtered): the options' leaves, or
  /// the ones chosen for RegistrationOptions::kAutomaticVoxel.
  double source_voxel = 0.0;
  double target_voxel = 0.0;
  /// Gauss-Newton information (J^T W Omega J, unit-free weights w) at the final pose, twist
  /// (omega, v) applied on the left about the target's per-axis median point, in the target's
  /// axes, radians and cloud units. Not a covariance's inverse: see `covariance`.
  Eigen::Matrix<double, 6, 6> information = Eigen::Matrix<double, 6, 6>::Zero();
  /// Covariance of the pose: of the twist delta = (omega, v), rotation first, such that
  /// T_target_source = exp(delta) T_true (applied on the left, about the target frame's origin,
  /// in its axes; radians and cloud units; se3.hpp's exp). The robust (sandwich) covariance of
  /// the Student-t fit, its terms summed over patches of the source (docs/COVARIANCE.md: how it
  /// is made, and where it is calibrated against known truth). Along a direction the surfaces
  /// leave free (degenerate_directions) the standard deviation is the association radius
  /// (rotations: the radius over the source's RMS distance from its centroid): large, finite,
  /// never NaN; so is every direction when no pair was left at the end. Zero when no iteration
  /// ran (status not ok).
  Eigen::Matrix<double, 6, 6> covariance = Eigen::Matrix<double, 6, 6>::Zero();
  /// Plane model: directions of motion the target's surfaces leave unconstrained (eigenvalues of
  /// the surface-normal information, rotations scaled by the source's RMS radius, below 1e-2 of
  /// the largest): 3 for a plane, 2 for a cylinder, 3 for a sphere, 0 for well-constrained
  /// geometry. Point model: -1 (not assessed).
  int degenerate_directions = -1;
  /// How well the clouds agree at the final pose, measured after the last iteration on the
  /// registered (filtered) clouds, with the association radius (Open3D's definitions):
  double fitness = 0.0;         // fraction of source points with a target point within the radius
  double inlier_rmse = 0.0;     // RMS distance of those points to their nearest target point
  double overlap = 0.0;         // the matched fraction both ways: min(fitness, target's fraction);
                                // fitness when no source index exists (source normals off)
  double close_fraction = 0.0;  // of the source points within min(radius, 8 target point
                                // spacings) of the target, the fraction on its surface: within 2
                                // spacings of the nearest target point's tangent plane and that
                                // point within the target's median normal-fit reach, at least 2
                                // spacings (plane model; a point without a normal: the point
                                // test), or within 2 spacings of that point (point model); NaN
                                // when the target has no spacing
  Quality quality = Quality::kFailed;  // the verdict (see Quality), set by every align()
  const char* quality_reason = "";     // why it is not kGood: one sentence, static text
  double quality_ms = 0.0;  // wall time of these measures, the covariance and the free directions
  std::vector<IterationRecord> history;

  /// True when a termination criterion stopped the loop (not the cap, not a failure).
  bool converged() const { return status.ok() && is_criterion_stop(stop_reason); }
};

}  // namespace PPCR_ABI_NAMESPACE
}  // namespace ppcr
