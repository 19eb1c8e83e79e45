// lm_solver.cpp - the inner loop.
#include "lm_solver.hpp"

#include <Eigen/Cholesky>
#include <algorithm>
#include <cassert>
#include <cmath>

#include "ppcr/se3.hpp"

namespace ppcr {
inline namespace PPCR_ABI_NAMESPACE {
namespace detail {

void LMSolver::resize(std::size_t source_points, int k) {
  const std::size_t slots = source_points * static_cast<std::size_t>(k);
  w_.resize(slots);
  normal_equations_.resize(source_points, k);
}

LMSummary LMSolver::solve(const LMOptions& options, const LMProblem& pb, Eigen::Isometry3d* T) {
  LMSummary summary;
  auto evaluate = [&](const Eigen::Isometry3d& pose, const double* w_prev, double* w_new,
                      Evaluation* out) {
    normal_equations_.evaluate(*pb.source, *pb.target, *pb.assoc, pb.weights, pose, w_prev, w_new,
                               nullptr, pb.pool, out, pb.plane);
  };

  evaluate(*T, nullptr, w_.data(), &current_);
  summary.initial_cost = summary.final_cost = current_.cost;
  if (!std::isfinite(current_.cost) || !current_.H.allFinite() || !current_.g.allFinite()) {
    summary.termination = LMTermination::kNumericalFailure;
    return summary;
  }
  if (!(current_.weight_sum > 0.0)) {
    summary.termination = LMTermination::kNoResiduals;
    return summary;
  }

  double lambda = options.initial_lambda;
  double lambda_growth = 2.0;  // Nielsen's nu
  // The shortcut below needs an accepted step before it, or the start of a solve that may end
  // unevaluated (lm.hpp).
  bool last_accepted = !options.evaluate_first_step;
  const double gradient_start = current_.g.cwiseAbs().maxCoeff();
  summary.termination = LMTermination::kMaxIterations;

  while (summary.iterations < options.max_iterations) {
    if (current_.g.cwiseAbs().maxCoeff() <= options.gradient_tolerance * gradient_start) {
      summary.termination = LMTermination::kGradientTolerance;
      break;
    }
    // (H + lambda D) delta = -g, D = diag(H) floored so that directions the data leave
    // unconstrained still get damped (Ceres' min_diagonal, made relative).
    const double diag_floor = 1e-12 * current_.H.diagonal().maxCoeff();
    const Vector6d D = current_.H.diagonal().cwiseMax(diag_floor);
    Matrix6d A = current_.H;
    A.diagonal() += lambda * D;
    const Vector6d delta = A.ldlt().solve(-current_.g);
    if (!delta.allFinite()) {
      summary.termination = LMTermination::kNumericalFailure;
      break;
    }
    // Largest motion of a source point under the step: |omega| r_max + |v|.
    const double motion = delta.head<3>().norm() * pb.source_extent + delta.tail<3>().norm();
    if (motion <= options.step_tolerance * pb.step_reference) {
      summary.termination = LMTermination::kStepTolerance;
      break;
    }

    // The model's predicted decrease, 1/2 delta^T (lambda D delta - g), for the gain ratio.
    const double predicted = 0.5 * delta.dot(lambda * D.cwiseProduct(delta) - current_.g);
    const Eigen::Isometry3d T_trial = se3::exp(delta) * (*T);
    // A step the model says lowers the cost by less than function_tolerance would end the solve
    // after its pass (the test below). Take it without the pass: the caller evaluates at the new
    // pose anyway (the next outer iteration re-associates there), so the summary's final_cost,
    // last() and weights() stay those of the pose before this step. Only after an accepted step
    // or at the start (unless evaluate_first_step), where lambda is not inflated by rejections.
    if (last_accepted && predicted > 0.0 &&
        predicted < options.function_tolerance * current_.cost) {
      *T = T_trial;
      ++summary.iterations;
      ++summary.successful_steps;
      summary.termination = LMTermination::kFunctionTolerance;
      break;
    }
    // In place: w_ becomes the trial pose's weights (normal_equations.hpp).
    evaluate(T_trial, w_.data(), w_.data(), &trial_);
    ++summary.iterations;

    const double actual = current_.cost - trial_.cost_prev_weights;  // same weights
    if (std::isfinite(trial_.cost_prev_weights) && std::isfinite(trial_.cost) && actual > 0.0) {
      // Accept: move, and take the weights refreshed at the new pose (IRLS).
      const double cost_before = current_.cost;
      *T = T_trial;
      std::swap(current_, trial_);
      ++summary.successful_steps;
      const double rho = predicted > 0.0 ? actual / predicted : 0.0;
      lambda *= std::max(1.0 / 3.0, 1.0 - std::pow(2.0 * rho - 1.0, 3));
      lambda_growth = 2.0;
      last_accepted = true;
      if (actual < options.function_tolerance * cost_before) {
        summary.termination = LMTermination::kFunctionTolerance;
        break;
      }
    } else {
      // Reject: back to the current pose's weights, which the next trial (and weights()) needs.
      // The pass repeats the one that made current_, to the bit.
      evaluate(*T, nullptr, w_.data(), &trial_);
      assert(trial_.cost == current_.cost && trial_.H == current_.H && trial_.g == current_.g);
      ++summary.unsuccessful_steps;
      last_accepted = false;
      lambda *= lambda_growth;
      lambda_growth *= 2.0;
      if (lambda > options.max_lambda) {
        summary.termination = LMTermination::kLambdaTooLarge;
        break;
      }
    }
  }
  summary.final_cost = current_.cost;
  return summary;
}

}  // namespace detail

const char* to_string(LMTermination t) {
  switch (t) {
    case LMTermination::kFunctionTolerance:
      return "function_tolerance";
    case LMTermination::kGradientTolerance:
      return "gradient_tolerance";
    case LMTermination::kStepTolerance:
      return "step_tolerance";
    case LMTermination::kMaxIterations:
      return "max_iterations";
    case LMTermination::kLambdaTooLarge:
      return "lambda_too_large";
    case LMTermination::kNoResiduals:
      return "no_residuals";
    case LMTermination::kNumericalFailure:
      return "numerical_failure";
  }
  return "unknown";
}

}  // namespace PPCR_ABI_NAMESPACE
}  // namespace ppcr
