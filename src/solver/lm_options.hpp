// lm_options.hpp - settings and summary of the inner loop: Levenberg-Marquardt on SE(3).
//
// The inner problem of one outer iteration has fixed associations and minimises
//   cost(T) = 1/2 * sum_j sum_k w_kj * r_kj(T)                                (paper eq. 1)
// with the weights w_kj recomputed from the pose after every accepted step (IRLS, as the
// authors do in a Ceres iteration callback). A step is accepted when it lowers the cost under the
// SAME weights as the pose it starts from; the weights are then refreshed at the new pose.
// A step whose predicted decrease (the damped Gauss-Newton model's) is below
// function_tolerance x cost, right after an accepted step, is taken without evaluating it and
// ends the solve: its pass would only confirm the stop, and the next outer iteration evaluates at
// the new pose anyway. The summary's final_cost is then the cost before that step. At the start
// of a solve the same shortcut applies unless evaluate_first_step is set: then the first step is
// always evaluated, so the solve's cost drop is a measured one.
#pragma once

#include "ppcr/abi.hpp"
#include "ppcr/options.hpp"

namespace ppcr {
inline namespace PPCR_ABI_NAMESPACE {

/// The inner LM's settings. max_iterations and function_tolerance default to the options'
/// (ExpertOptions::lm_max_iterations, lm_function_tolerance: defined there once); the others have
/// no option and are defined here.
struct LMOptions {
  // LM iterations (accepted + rejected steps) per inner problem.
  int max_iterations = ExpertOptions{}.lm_max_iterations;
  // Stop after an accepted step that lowers the cost by less than this fraction of the cost
  // before it (authors: 1e-5).
  double function_tolerance = ExpertOptions{}.lm_function_tolerance;
  double gradient_tolerance = 1e-10;  // stop when max_i |g_i| <= this * max_i |g_i| at the start
  double step_tolerance = 1e-7;       // stop when a step would move no source point by more than
                                      // this fraction of the step reference (the radius; bound:
                                      // |omega| * r_max + |v|, r_max the source's extent)
  double initial_lambda = 1e-4;      // initial damping (Ceres' default trust radius 1e4 = 1/lambda)
  double max_lambda = 1e16;          // give up (kLambdaTooLarge) when damping exceeds this
  bool evaluate_first_step = false;  // never end a solve on an unevaluated first step
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
