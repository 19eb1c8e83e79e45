// degeneracy.cpp - see degeneracy.hpp.
#include "quality/degeneracy.hpp"

#include <Eigen/Eigenvalues>
#include <algorithm>

namespace ppcr {
inline namespace PPCR_ABI_NAMESPACE {
namespace detail {

namespace {

// diag(1 / rms, 1): H_normal's rotation block in cloud units^2, like its translation block.
Vector6d inverse_scaling(double rms_radius) {
  const double rms = std::max(rms_radius, 1e-150);
  Vector6d s;
  s << 1.0 / rms, 1.0 / rms, 1.0 / rms, 1.0, 1.0, 1.0;
  return s;
}

// The eigen-decomposition of the scaled H_normal; false when it is not finite or zero.
bool scaled_eigen(const Matrix6d& H_normal, double rms_radius,
                  Eigen::SelfAdjointEigenSolver<Matrix6d>* eig, int options) {
  const Vector6d s = inverse_scaling(rms_radius);
  const Matrix6d normalised = s.asDiagonal() * H_normal * s.asDiagonal();
  if (!normalised.allFinite() || !(normalised.diagonal().maxCoeff() > 0.0)) return false;
  eig->compute(normalised, options);
  return true;
}

}  // namespace

int degenerate_directions(const Matrix6d& H_normal, double rms_radius) {
  Eigen::SelfAdjointEigenSolver<Matrix6d> eig;
  if (!scaled_eigen(H_normal, rms_radius, &eig, Eigen::EigenvaluesOnly)) return -1;
  const Vector6d ev = eig.eigenvalues();
  return static_cast<int>((ev.array() < kDegenerateRatio * ev.maxCoeff()).count());
}

Matrix6d release_free_directions(const Matrix6d& C, const Matrix6d& H_normal, double rms_radius,
                                 double reach) {
  Eigen::SelfAdjointEigenSolver<Matrix6d> eig;
  if (!scaled_eigen(H_normal, rms_radius, &eig, Eigen::ComputeEigenvectors)) return C;
  const Vector6d ev = eig.eigenvalues();
  Matrix6d free_projector = Matrix6d::Zero();
  for (int i = 0; i < 6; ++i) {
    if (ev[i] < kDegenerateRatio * ev.maxCoeff()) {
      free_projector += eig.eigenvectors().col(i) * eig.eigenvectors().col(i).transpose();
    }
  }
  if (free_projector.isZero(0.0)) return C;
  // In the scaled coordinates z = D delta, D = diag(rms I, I) (every axis a length), the free
  // directions' part of Cov(z) becomes reach^2 times their projector.
  const Vector6d d = inverse_scaling(rms_radius).cwiseInverse();
  const Matrix6d kept = Matrix6d::Identity() - free_projector;
  const Matrix6d C_z = d.asDiagonal() * C * d.asDiagonal();
  const Matrix6d released = kept * C_z * kept + (reach * reach) * free_projector;
  const Vector6d s = inverse_scaling(rms_radius);
  return s.asDiagonal() * released * s.asDiagonal();
}

}  // namespace detail
}  // namespace PPCR_ABI_NAMESPACE
}  // namespace ppcr
