// pose_acceleration.hpp - Anderson acceleration of the outer loop's pose (as AA-ICP does for ICP).
//
// While the E-step scale is held (the EM coarse phase), each outer iteration applies one fixed map
// G to the pose: from the pose it starts at to the pose its inner solve ends at (associate at x,
// solve: Sec. 3.1). Where the data hold the optimum only weakly (a tabletop turned about its
// normal) G contracts slowly: the pose creeps a little per iteration, each iteration drops the
// cost by little, the phase ends and the criterion stops while the pose is still degrees off
// (docs/TERMINATION.md, "Slow creep"). Anderson's method (type II, memory m) extrapolates from the
// last m + 1 iterations. With f_i = G(x_i) - x_i and dF, dG the differences of consecutive f and G,
//   gamma = argmin |f_t - dF gamma|,    x_{t+1} = G(x_t) - dG gamma,
// which is the secant (Aitken) step along the creep with m = 1 and, for an affine G, lands on its
// fixed point in a few steps. Poses are charted as twists of T A^-1 (A the first pose since the
// last reset), the rotation part scaled by a length so that both parts are lengths.
//
// Safeguards: the extrapolation is kept within max_gain x |f_t| of G(x_t); the history restarts
// when |f| grows (the last extrapolation overshot); the caller resets it when G changes (the
// scale moves). Every iteration still runs a full inner solve from wherever the extrapolation puts
// it, so an unhelpful extrapolation costs iterations, not the answer's validity.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <Eigen/QR>

#include "ppcr/abi.hpp"

namespace ppcr {
inline namespace PPCR_ABI_NAMESPACE {
namespace detail {

class PoseAcceleration {
 public:
  static constexpr int kMaxMemory = 8;

  /// memory: m, the number of differences kept, from the last m + 1 iterations (0: no
  /// acceleration, next() returns G(x));
  /// length: the rotation part's scale (the source's RMS radius about the rotation centre);
  /// max_gain: the extrapolation's bound, in multiples of the last step |f|.
  PoseAcceleration(int memory, double length, double max_gain);

  /// Forgets the history: the next call starts a new chart.
  void reset();

  /// x: the pose an outer iteration started at; g: the pose it ended at (G(x)). Returns the pose
  /// the next iteration starts at.
  Eigen::Isometry3d next(const Eigen::Isometry3d& x, const Eigen::Isometry3d& g);

 private:
  using Vector6d = Eigen::Matrix<double, 6, 1>;
  Vector6d chart(const Eigen::Isometry3d& T) const;
  Eigen::Isometry3d pose(const Vector6d& y) const;

  int memory_;
  double length_;
  double max_gain_;
  bool started_ = false;  // the chart's anchor is set
  bool have_previous_ = false;
  int columns_ = 0;  // differences stored, <= memory_
  int newest_ = -1;  // the ring's newest column
  Eigen::Isometry3d anchor_ = Eigen::Isometry3d::Identity();
  Vector6d previous_f_, previous_g_;
  Eigen::Matrix<double, 6, kMaxMemory> dF_, dG_;
  // Sized at most 6 x kMaxMemory without the heap, so next() does not allocate, even with
  // linearly dependent columns (a creep along one line), where a complete orthogonal
  // decomposition would: the dependent ones get gamma 0.
  using Columns = Eigen::Matrix<double, 6, Eigen::Dynamic, 0, 6, kMaxMemory>;
  Eigen::ColPivHouseholderQR<Columns> solver_;
};

}  // namespace detail
}  // namespace PPCR_ABI_NAMESPACE
}  // namespace ppcr
