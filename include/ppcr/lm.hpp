// lm.hpp - settings and summary of the inner loop: Levenberg-Marquardt on SE(3).
//
// The inner problem of one outer iteration has fixed associations and minimises
//   cost(T) = 1/2 * sum_j sum_k w_kj * |y_k - T x_j|^2                       (paper eq. 1)
// with the weights w_kj recomputed from the pose after every accepted step (IRLS, as the
// authors do in a Ceres iteration callback). A step is accepted when it lowers the cost under the
// SAME weights as the pose it starts from; the weights are then refreshed at the new pose.
// A step whose predicted decrease (the damped Gauss-Newton model's) is below
// function_tolerance x cost, right after an accepted step or at the start, is taken without
// evaluating it and ends the solve: its pass would only confirm the stop, and the next outer
// iteration evaluates at the new pose anyway. The summary's final_cost is then the cost before
// that step.
#pragma once

#include "ppcr/abi.hpp"

namespace ppcr {
inline namespace PPCR_ABI_NAMESPACE {

struct LMOptions {
  int max_iterations = 50;            // LM iterations (accepted + rejected steps) per inner problem
  double function_tolerance = 1e-5;   // stop after an accepted step that lowers the cost by less
                                      // than this fraction of the cost before it (authors: 1e-5),
                                      // or take a step predicted to, unevaluated, and stop
  double gradient_tolerance = 1e-10;  // stop when max_i |g_i| <= this * max_i |g_i| at the start
  double step_tolerance = 1e-7;       // stop when a step would move no source point by more than
                                      // this fraction of the association radius (bound:
                                      // |omega| * r_max + |v|, r_max the source's extent)
  double initial_lambda = 1e-4;  // initial damping (Ceres' default trust radius 1e4 = 1/lambda)
  double max_lambda = 1e16;      // give up (kLambdaTooLarge) when damping exceeds this
  /// fine_function_tolerance's default (it acts with the EM scale only, below): with the plane
  /// error model and the cost-drop criterion alone (TerminationCriteria's defaults),
  /// kPlaneFineTolerance capped at TerminationCriteria::cost_drop_threshold, unless that is not
  /// above function_tolerance; otherwise 0 (off: function_tolerance throughout).
  static constexpr double kAutomatic = -1.0;
  static constexpr double kPlaneFineTolerance = 1e-2;
  /// Registration with the EM scale only: function_tolerance of the inner solves once the scale
  /// has left its coarse phase (0 = function_tolerance throughout; a value below
  /// function_tolerance makes the fine phase stricter; kAutomatic = by error model and
  /// criterion, above). In the fine phase the inner problem changes at every outer iteration
  /// (scale, weights, associations), so solving each one to 1e-5 mostly re-confirms a pose.
  /// With 1e-2 most fine-phase solves end on one step taken unevaluated (its predicted decrease
  /// is below the tolerance; it is not checked). Such an iteration reports the cost before that
  /// step, so its cost drop reads 0 and the cost-drop criterion counts it as low (if the motion
  /// guard, when on, finds the source settled): keep an explicit value at or below
  /// termination.cost_drop_threshold (the automatic one is), or iterations that dropped more
  /// than the threshold count as low. Other criteria read what one-step solves change: mse-prev the
  /// motion per outer iteration (source normals with cost drop + mse-prev and 1e-2: the bunny set
  /// stopped after 14.8 outer iterations instead of 18.1, median error +4.9 %), successful-steps
  /// the steps per solve (mostly one in the fine phase); hence off with them by default. Measured
  /// (docs/PERFORMANCE.md, updates 36a06bf and 03512d7), 1e-2 with the plane model: a third fewer
  /// LM steps on the benchmark sets, time -13 to -21 % (bunny) and -15 to -17 % (lidar) in three
  /// interleaved comparisons on 2026-12-02, bunny errors +0.09 %, lidar 1.5-2.8 % lower. The point
  /// model loses accuracy with it (bunny median 0.0064 -> 0.024, stopping after 35.1 outer
  /// iterations instead of 38.9), hence off there by default; and 3e-3 in the coarse phase too
  /// stopped a hard lidar problem 20 degrees off. (Last member, so that positional initialisers
  /// written for the earlier members keep their meaning.)
  double fine_function_tolerance = kAutomatic;
};

enum class LMTermination {
  kFunctionTolerance,  // converged: relative cost decrease below function_tolerance
  kGradientTolerance,  // converged: gradient vanished
  kStepTolerance,      // converged: steps too small to move any point
  kMaxIterations,      // max_iterations reached
  kLambdaTooLarge,     // no step lowers the cost any more (damping ran away)
  kNoResiduals,        // zero total weight: nothing to minimise
  kNumericalFailure,   // non-finite cost, gradient or step
};

const char* to_string(LMTermination t);

struct LMSummary {
  double initial_cost = 0.0;   // cost at the starting pose, weights computed at that pose
  double final_cost = 0.0;     // cost at the last evaluated pose (the final one, or the one
                               // before an unevaluated last step), weights refreshed there
  int successful_steps = 0;    // accepted steps (cost fell under unchanged weights)
  int unsuccessful_steps = 0;  // rejected steps (lambda increased)
  int iterations = 0;          // successful_steps + unsuccessful_steps
  LMTermination termination = LMTermination::kMaxIterations;
};

}  // namespace PPCR_ABI_NAMESPACE
}  // namespace ppcr
