// lm_solver.cpp - the inner loop.
#include "solver/lm_solver.hpp"

#include <Eigen/Cholesky>
#include <algorithm>
#include <cassert>
#include <cmath>

#include "ppcr/se3.hpp"

namespace ppcr {
inline namespace PPCR_ABI_NAMESPACE {
namespace detail {

namespace {

// The damped Gauss-Newton step of an evaluation: (H + lambda D) delta = -g, D = diag(H) floored
// so that directions the data leave unconstrained still get damped (Ceres' min_diagonal, made
// relative); and the model's predicted decrease, 1/2 delta^T (lambda D delta - g), for the gain
// ratio and the tolerance shortcut (lm_options.hpp).
struct DampedStep {
  Vector6d delta;
  double predicted = 0.0;
};

DampedStep damped_step(const Evaluation& e, double lambda) {
  const double diag_floor = 1e-12 * e.H.diagonal().maxCoeff();
  const Vector6d D = e.H.diagonal().cwiseMax(diag_floor);
  Matrix6d A = e.H;
  A.diagonal() += lambda * D;
  DampedStep step;
  step.delta = A.ldlt().solve(-e.g);
  step.predicted = 0.5 * step.delta.dot(lambda * D.cwiseProduct(step.delta) - e.g);
  return step;
}

// Nielsen's damping update: lambda shrinks by at most 3 after an accepted step of gain ratio rho,
// and grows by 2, 4, 8, ... over consecutive rejected ones.
class Damping {
 public:
  explicit Damping(double initial) : lambda_(initial) {}
  double lambda() const { return lambda_; }
  void accepted(double rho) {
    lambda_ *= std::max(1.0 / 3.0, 1.0 - std::pow(2.0 * rho - 1.0, 3));
    growth_ = 2.0;
  }
  void rejected() {
    lambda_ *= growth_;
    growth_ *= 2.0;
  }

 private:
  double lambda_;
  double growth_ = 2.0;  // Nielsen's nu
};

// Largest motion of a source point under the step: |omega| r_max + |v|.
double largest_motion(const Vector6d& delta, double source_extent) {
  return delta.head<3>().norm() * source_extent + delta.tail<3>().norm();
}

}  // namespace

void LMSolver::resize(std::size_t source_points, int k) {
  // One row more: a coarse level of every 2nd point of an odd count has (n + 1) / 2 rows.
  const std::size_t slots = (source_points + 1) * static_cast<std::size_t>(k);
  w_.resize(slots);
  normal_equations_.resize(source_points, k);
}

void LMSolver::evaluate(const LMProblem& pb, const Eigen::Isometry3d& pose, const double* w_prev,
                        double* w_new, Evaluation* out, PairNormalMemo memo) {
  normal_equations_.evaluate(*pb.source, *pb.target, *pb.assoc, pb.weights, pose, w_prev, w_new,
                             nullptr, pb.parallel, out, pb.plane, memo);
}

LMSummary LMSolver::solve(const LMOptions& options, const LMProblem& pb, Eigen::Isometry3d* T) {
  LMSummary summary;
  // The pair normals' memo in w_ past the table's slots, where they leave room for it: the first
  // pass fills it, the others read it (a coarse solve runs several passes).
  const std::size_t used = pb.assoc->index.size();
  // The weights' slots are the table's (one per slot of each row), and the memo's follow them.
  assert(used == pb.assoc->count.size() * static_cast<std::size_t>(pb.assoc->k));
  PairNormalMemo memo;
  if (2 * used <= w_.size()) memo.slots = w_.data() + used;
  evaluate(pb, *T, nullptr, w_.data(), &current_, memo);
  memo.fill = false;
  summary.initial_cost = summary.final_cost = current_.cost;
  if (!std::isfinite(current_.cost) || !current_.H.allFinite() || !current_.g.allFinite()) {
    summary.termination = LMTermination::kNumericalFailure;
    return summary;
  }
  if (!(current_.weight_sum > 0.0)) {
    summary.termination = LMTermination::kNoResiduals;
    return summary;
  }

  Damping damping(options.initial_lambda);
  // The shortcut below needs an accepted step before it, or the start of a solve that may end
  // unevaluated (lm_options.hpp).
  bool last_accepted = !options.evaluate_first_step;
  const double gradient_start = current_.g.cwiseAbs().maxCoeff();
  summary.termination = LMTermination::kMaxIterations;

  while (summary.iterations < options.max_iterations) {
    if (current_.g.cwiseAbs().maxCoeff() <= options.gradient_tolerance * gradient_start) {
      summary.termination = LMTermination::kGradientTolerance;
      break;
    }
    const DampedStep step = damped_step(current_, damping.lambda());
    if (!step.delta.allFinite()) {
      summary.termination = LMTermination::kNumericalFailure;
      break;
    }
    if (largest_motion(step.delta, pb.source_extent) <=
        options.step_tolerance * pb.step_reference) {
      summary.termination = LMTermination::kStepTolerance;
      break;
    }
    const Eigen::Isometry3d T_trial = se3::exp(step.delta) * (*T);
    ++summary.iterations;
    // A step the model says lowers the cost by less than function_tolerance would end the solve
    // after its pass (the test below). Take it without the pass: the caller evaluates at the new
    // pose anyway (the next outer iteration re-associates there), so the summary's final_cost,
    // last() and weights() stay those of the pose before this step. Only after an accepted step
    // or at the start (unless evaluate_first_step), where lambda is not inflated by rejections.
    if (last_accepted && step.predicted > 0.0 &&
        step.predicted < options.function_tolerance * current_.cost) {
      *T = T_trial;
      ++summary.successful_steps;
      summary.termination = LMTermination::kFunctionTolerance;
      break;
    }
    // In place: w_ becomes the trial pose's weights (normal_equations.hpp).
    evaluate(pb, T_trial, w_.data(), w_.data(), &trial_, memo);
    const double actual = current_.cost - trial_.cost_prev_weights;  // same weights
    last_accepted =
        std::isfinite(trial_.cost_prev_weights) && std::isfinite(trial_.cost) && actual > 0.0;
    if (last_accepted) {
      // Accept: move, and take the weights refreshed at the new pose (IRLS).
      const double cost_before = current_.cost;
      *T = T_trial;
      std::swap(current_, trial_);
      ++summary.successful_steps;
      damping.accepted(step.predicted > 0.0 ? actual / step.predicted : 0.0);
      if (actual < options.function_tolerance * cost_before) {
        summary.termination = LMTermination::kFunctionTolerance;
        break;
      }
    } else {
      // Reject: back to the current pose's weights, which the next trial (and weights()) needs.
      // The pass repeats the one that made current_, to the bit.
      evaluate(pb, *T, nullptr, w_.data(), &trial_, memo);
      assert(trial_.cost == current_.cost && trial_.H == current_.H && trial_.g == current_.g);
      ++summary.unsuccessful_steps;
      damping.rejected();
      if (damping.lambda() > options.max_lambda) {
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
