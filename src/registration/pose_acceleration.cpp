// pose_acceleration.cpp - Anderson acceleration of the outer loop's pose (pose_acceleration.hpp).
#include "registration/pose_acceleration.hpp"

#include <algorithm>

#include "ppcr/se3.hpp"

namespace ppcr {
inline namespace PPCR_ABI_NAMESPACE {
namespace detail {

PoseAcceleration::PoseAcceleration(int memory, double length, double max_gain)
    : memory_(std::clamp(memory, 0, kMaxMemory)), length_(length), max_gain_(max_gain) {}

void PoseAcceleration::reset() {
  started_ = have_previous_ = false;
  columns_ = 0;
  newest_ = -1;
}

PoseAcceleration::Vector6d PoseAcceleration::chart(const Eigen::Isometry3d& T) const {
  Vector6d y = se3::log(T * anchor_.inverse());
  y.head<3>() *= length_;
  return y;
}

Eigen::Isometry3d PoseAcceleration::pose(const Vector6d& y) const {
  Vector6d xi = y;
  xi.head<3>() /= length_;
  return se3::exp(xi) * anchor_;
}

Eigen::Isometry3d PoseAcceleration::next(const Eigen::Isometry3d& x, const Eigen::Isometry3d& g) {
  if (memory_ == 0 || !(length_ > 0.0)) return g;
  if (!started_) {
    anchor_ = x;
    started_ = true;
  }
  const Vector6d g_chart = chart(g);
  const Vector6d f = g_chart - chart(x);
  const double step = f.norm();
  if (have_previous_) {
    if (step > previous_f_.norm()) {  // the last extrapolation overshot: start again from here
      columns_ = 0;
      newest_ = -1;
    } else {
      newest_ = (newest_ + 1) % memory_;
      dF_.col(newest_) = f - previous_f_;
      dG_.col(newest_) = g_chart - previous_g_;
      columns_ = std::min(columns_ + 1, memory_);
    }
  }
  previous_f_ = f;
  previous_g_ = g_chart;
  have_previous_ = true;
  if (columns_ == 0 || !(step > 0.0)) return g;

  // Columns 0 .. columns_ - 1 are the stored ones (the ring fills from 0); their order does not
  // matter to the least-squares problem.
  solver_.compute(dF_.leftCols(columns_));
  const Eigen::Matrix<double, Eigen::Dynamic, 1, 0, kMaxMemory, 1> gamma = solver_.solve(f);
  Vector6d extrapolation = -dG_.leftCols(columns_) * gamma;
  if (!extrapolation.allFinite()) return g;
  const double reach = extrapolation.norm(), bound = max_gain_ * step;
  if (reach > bound) extrapolation *= bound / reach;
  return pose(g_chart + extrapolation);
}

}  // namespace detail
}  // namespace PPCR_ABI_NAMESPACE
}  // namespace ppcr
