// registration.hpp - the PPCR outer loop: associate, solve (LM), compose, ask the criteria.
//
//   Registration reg(options);
//   reg.set_target(target);                               // filters, builds the k-d tree once
//   RegistrationResult r = reg.align(source, T_initial);  // r.T_target_source maps source ->
//   target
//
// Everything the loop needs is allocated in set_target()/align() set-up; the loop itself
// (association, weights, normal equations) allocates nothing.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cstddef>
#include <functional>
#include <memory>
#include <vector>

#include "ppcr/abi.hpp"
#include "ppcr/error_model.hpp"
#include "ppcr/lm.hpp"
#include "ppcr/status.hpp"
#include "ppcr/termination.hpp"
#include "ppcr/types.hpp"
#include "ppcr/weights.hpp"

namespace ppcr {
inline namespace PPCR_ABI_NAMESPACE {

struct RegistrationOptions {
  double radius = 1.0;      // association radius, cloud units (> 0): target points farther
                            // than this from a transformed source point are ignored
  int max_neighbours = 10;  // associations per source point, k (>= 1)
  WeightOptions weights;    // E-step model, dof and scale
  ErrorModel error_model = ErrorModel::kPlane;  // plane-aware (default, measured: README)
                                                // or point-to-point (the paper's)
  PlaneOptions plane;                           // kPlane: normal estimation and in-plane weight
  LMOptions lm;                                 // inner loop
  TerminationCriteria termination;              // outer loop
  /// Re-associate only when some source point may have moved more than this fraction of the
  /// radius since the last association (a bound from the pose change and the source's extent);
  /// otherwise the outer iteration reuses the neighbour lists (IterationRecord::lists_reused).
  /// 0 = every iteration (the paper). An iteration on reused lists re-solves the problem just
  /// solved, so its cost drop and motion are ~0 by construction: it counts neither toward an
  /// adaptive termination criterion (cost drop, MSE, successful steps; fixed iterations and the
  /// max_iterations cap count every iteration) nor toward the end of the EM scale's coarse
  /// phase, and the next iteration re-associates when it would have, or while a streak toward
  /// either runs (termination.hpp). Before that rule (commit 2ee5201 and earlier) such
  /// iterations did count, and 0.05 stopped a point-model lidar run in the 1.2 degree local
  /// minimum and a line 2.4 cm short. With the rule the stop's iterations re-associate, and 0.05
  /// measured error medians within 0.05 % and 0.6-4.2 % less time on the benchmark sets, about
  /// the run-to-run noise (docs/PERFORMANCE.md, update 65b0f00). Hence still off by default.
  double reassociate_motion = 0.0;
  /// Extra candidates kept per source point for exact incremental association (k + this many
  /// nearest target points within 1.25 x radius, re-ranked or re-sorted at each association; a
  /// point is re-queried only when its list cannot prove the answer: src/neighbour_cache.hpp). The
  /// associations are those of a fresh k-d tree query either way; 0 = query every point in every
  /// iteration. Used only when k + this <= 256. 4 rather than 8 since the set certificate made
  /// most re-ranks cheap (1-4 % faster on the benchmark sets, docs/PERFORMANCE.md).
  int neighbour_cache = 4;
  /// Coarse-phase subsampling. With the EM scale (weights.hpp), during its coarse phase only
  /// every coarse_stride-th source point (in a Z-order of the source, so spread over the whole
  /// cloud) is associated and registered; from the first fine-phase iteration on, every point
  /// (the coarse phase's neighbour lists carried over). The coarse phase only brings the source
  /// near its place at a wide scale; the fine phase, on every point, sets the accuracy. 1 = every
  /// point throughout (the paper); at most kMaxCoarseStride. kAutomatic: kPlaneCoarseStride with
  /// the plane model, 1 with
  /// the point model. Lowered to the source's size / kMinCoarsePoints where that is smaller (a
  /// source of fewer than 2 x kMinCoarsePoints points is registered whole). Measured
  /// (docs/PERFORMANCE.md, update "coarse-phase subsampling"; 350 lidar problems: the
  /// benchmark's 50 and 300 more drawn alike by tools/bench/make_problems.py): with the plane
  /// model, stride 2 takes 24-30 % off the benchmark sets' time at one thread, medians within
  /// 0.3 %, and no failure more with the defaults, source normals or issue #8's setting (nor on
  /// the 50 with four more plane settings); with the point model it sends 16 of the 300 into a
  /// 1.2 degree local minimum (1 with every point), hence 1 there. Strides 3 and 4 are faster
  /// still and failed 1-2 more of the hardest (~29 degree) lidar problems with source normals.
  /// kMinCoarsePoints is a floor, not tuned: the sets' levels hold 3.4k-4.2k points at stride 2.
  /// While the coarse level is registered, the history's correspondences and
  /// matched_source_points count its points; a run that stops there (an iteration cap, a
  /// cancel) reports the coarse level's counts and information. A coarse level that finds no
  /// pair is dropped for the rest of the run (every point is associated instead).
  int coarse_stride = kAutomatic;
  static constexpr int kAutomatic = -1;
  static constexpr int kPlaneCoarseStride = 2;
  static constexpr int kMaxCoarseStride = 64;
  static constexpr std::size_t kMinCoarsePoints = 1000;
  double source_voxel = 0.0;   // voxel leaf for the source, cloud units (0 = no filtering)
  double target_voxel = 0.0;   // voxel leaf for the target, cloud units (0 = no filtering)
  int num_threads = 1;         // threads for association and reductions (>= 1; the result
                               // does not depend on it)
  bool record_history = true;  // keep one IterationRecord per outer iteration in the result
  /// Called on the calling thread after each outer iteration with that iteration's record
  /// (progress display, time budgets). Return false to stop: StopReason::kCancelled.
  /// Must not throw.
  std::function<bool(const struct IterationRecord&)> on_iteration;
};

/// One row of the per-iteration trace.
struct IterationRecord {
  int iteration = 0;           // 1-based
  int successful_steps = 0;    // LM accepted steps
  int unsuccessful_steps = 0;  // LM rejected steps
  double initial_cost = 0.0;   // inner problem's cost before / after LM
  double final_cost = 0.0;
  double cost_drop = 0.0;          // (initial - final) / initial; NaN when initial is 0
  double mse_prev = 0.0;           // mean |T_t x - T_{t-1} x|^2 over the source (eq. 5)
  double mse_ground_truth = -1.0;  // mean |T_t x - T_gt x|^2; -1 without a ground truth
  double benchmark_error = -1.0;   // benchmark metric w.r.t. the ground truth; -1 without one
  double scale = 0.0;              // s used by the E-step (cloud units; 1 in raw mode)
  // Associated (source, target) pairs and source points with at least one neighbour; of the
  // coarse level in the EM coarse phase (RegistrationOptions::coarse_stride).
  std::size_t correspondences = 0;
  std::size_t matched_source_points = 0;
  bool lists_reused = false;  // reused the last neighbour lists (reassociate_motion); false:
                              // associated afresh
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
  // Source points with a neighbour and associated pairs, last iteration (of the coarse level,
  // RegistrationOptions::coarse_stride, when the run stopped in the EM coarse phase).
  std::size_t matched_source_points = 0;
  std::size_t correspondences = 0;
  // Points dropped as non-finite, or so far from the cloud's median that their squared distance
  // overflows (|p - median| > ~1e154).
  std::size_t source_non_finite = 0;
  std::size_t target_non_finite = 0;
  /// Plane model: the target's surface noise (error_model.hpp, "Noise floor"), cloud units;
  /// 0 for the point model, when no target point has a normal, or when align() refused its input.
  double target_surface_noise = 0.0;
  /// Gauss-Newton information (J^T W Omega J) at the final pose (at the last evaluated pose when
  /// the last inner step was taken unevaluated, lm.hpp: a step predicted to lower the cost by
  /// less than function_tolerance of it), twist (omega, v) applied on the left about the target's
  /// per-axis median point, in the target's axes.
  Eigen::Matrix<double, 6, 6> information = Eigen::Matrix<double, 6, 6>::Zero();
  /// Plane model: directions of motion the target's surfaces leave unconstrained (eigenvalues
  /// of the surface-normal information, rotations scaled by the source's RMS radius, below 1e-2
  /// of the largest): 3 for a single plane (the two in-plane translations and the
  /// rotation about the normal), 2 for a cylinder (translation along and rotation about its
  /// axis), 3 for a sphere (rotations), 0 for well-constrained geometry.
  /// Point model: -1 (not assessed; `information` shows null directions, e.g. the rotation
  /// about a line, or all three rotations for identical points).
  int degenerate_directions = -1;
  std::vector<IterationRecord> history;

  /// True when a termination criterion stopped the loop (not the cap, not a failure).
  bool converged() const { return status.ok() && is_criterion_stop(stop_reason); }
};

/// Checks options; the message names the parameter and the value seen.
Status validate(const RegistrationOptions& options);

class Registration {
 public:
  explicit Registration(const RegistrationOptions& options = RegistrationOptions());
  ~Registration();
  Registration(Registration&&) noexcept;
  Registration& operator=(Registration&&) noexcept;
  Registration(const Registration&) = delete;
  Registration& operator=(const Registration&) = delete;

  const RegistrationOptions& options() const;

  /// Validates the options, drops non-finite points, voxel-filters and indexes the target.
  Status set_target(const PointCloud& target);

  /// Registers source onto the target set last. T_initial maps source into the target frame
  /// (the initial guess). With T_ground_truth given, each history row also records the MSE and
  /// benchmark error w.r.t. it (analysis only: it never influences the registration).
  RegistrationResult align(const PointCloud& source,
                           const Eigen::Isometry3d& T_initial = Eigen::Isometry3d::Identity(),
                           const Eigen::Isometry3d* T_ground_truth = nullptr);

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

/// One-shot convenience: Registration(options).set_target(target) then align(source, ...).
RegistrationResult align(const PointCloud& source, const PointCloud& target,
                         const RegistrationOptions& options = RegistrationOptions(),
                         const Eigen::Isometry3d& T_initial = Eigen::Isometry3d::Identity(),
                         const Eigen::Isometry3d* T_ground_truth = nullptr);

}  // namespace PPCR_ABI_NAMESPACE
}  // namespace ppcr
