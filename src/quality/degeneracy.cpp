// degeneracy.cpp - see degeneracy.hpp.
#include "quality/degeneracy.hpp"

#include <Eigen/Eigenvalues>
#include <algorithm>

namespace ppcr {
inline namespace PPCR_ABI_NAMESPACE {
namespace detail {

int degenerate_directions(const Matrix6d& H_normal, double rms_radius) {
  const double rms = std::max(rms_radius, 1e-150);
  Vector6d inverse_scaling;
  inverse_scaling << 1.0 / rms, 1.0 / rms, 1.0 / rms, 1.0, 1.0, 1.0;
  const Matrix6d normalised =
      inverse_scaling.asDiagonal() * H_normal * inverse_scaling.asDiagonal();
  if (!normalised.allFinite() || !(normalised.diagonal().maxCoeff() > 0.0)) return -1;
  Eigen::SelfAdjointEigenSolver<Matrix6d> eig(normalised, Eigen::EigenvaluesOnly);
  const Vector6d ev = eig.eigenvalues();
  return static_cast<int>((ev.array() < kDegenerateRatio * ev.maxCoeff()).count());
}

}  // namespace detail
}  // namespace PPCR_ABI_NAMESPACE
}  // namespace ppcr
