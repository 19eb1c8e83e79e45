// lm_solver.hpp - Levenberg-Marquardt on SE(3) with an IRLS weight refresh after each accepted
// step (paper Sec. 3.1).
#pragma once

#include <Eigen/Geometry>
#include <vector>

#include "association/association_table.hpp"
#include "common/buffer.hpp"
#include "model/normal_equations.hpp"
#include "ppcr/abi.hpp"
#include "solver/lm_options.hpp"

namespace ppcr {
inline namespace PPCR_ABI_NAMESPACE {
namespace detail {

class Parallel;  // parallel.hpp

struct LMProblem {
  const PointCloud* source = nullptr;  // source points (registration's internal frame)
  const PointCloud* target = nullptr;  // target points (same frame as the tree)
  const AssociationTable* assoc = nullptr;
  WeightParams weights;
  const PlaneModel* plane = nullptr;   // plane error model, or null for point-to-point
  const Parallel* parallel = nullptr;  // null: the calling thread alone
  double step_reference = 1.0;         // length the step tolerance is relative to (the radius)
  double source_extent = 1.0;          // r_max: largest |x| of the source (bounds a step's motion)
};

class LMSolver {
 public:
  /// Sizes every buffer for n source points with k neighbours each (set-up, not in the loop).
  void resize(std::size_t source_points, int k);

  /// Minimises the weighted cost over T (updated in place). Allocation-free.
  LMSummary solve(const LMOptions& options, const LMProblem& problem, Eigen::Isometry3d* T);

  /// The last accepted evaluation: H (information), g, cost and weight sum at the final pose, or
  /// at the pose before an unevaluated last step (lm_options.hpp).
  const Evaluation& last() const { return current_; }
  /// Weights of that evaluation, stride k.
  const Buffer<double>& weights() const { return w_; }

 private:
  // One pass at `pose` (normal_equations.hpp): w_new gets its weights; w_prev, if not null, gives
  // the cost under the previous ones.
  void evaluate(const LMProblem& problem, const Eigen::Isometry3d& pose, const double* w_prev,
                double* w_new, Evaluation* out, PairNormalMemo memo);

  NormalEquations normal_equations_;
  // The weights at the current pose. A trial pass reads them (the cost under the previous
  // weights) and overwrites them with the trial pose's, point by point; a rejected step restores
  // them by a pass at the current pose (within a solve the source, target, associations, error
  // model, pair normals and weight parameters are fixed, so the E-step is a function of the pose
  // alone: they come back to the bit). One array instead of two: a rejected step costs a pass, and
  // none was rejected on the benchmark sets (docs/PERFORMANCE.md).
  // Room for every source point's k weights and k more: while the table holds at most half the
  // rows (the coarse level), the slots past its own hold the solve's PairNormalMemo
  // (normal_equations.hpp) at no extra memory.
  Buffer<double> w_;  // written by each pass before it is read
  Evaluation current_, trial_;
};

}  // namespace detail
}  // namespace PPCR_ABI_NAMESPACE
}  // namespace ppcr
