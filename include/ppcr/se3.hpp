// se3.hpp - the one Lie-group convention of ppcr.
//
// A twist is a 6-vector xi = (omega, v): rotation first, then translation.
//   hat(xi) = [ [omega]_x  v ; 0 0 ]  (4x4),   exp(xi) = [ R(omega)  V(omega) v ; 0 1 ]
// with R the Rodrigues rotation and V = I + (1-cos a)/a^2 [omega]_x + (a-sin a)/a^3 [omega]_x^2,
// a = |omega|. Updates are applied on the LEFT: T <- exp(delta) * T. For a point p = T x the
// derivative of exp(delta) * p at delta = 0 is  [ -[p]_x | I ]  (3x6).
// Small angles use Taylor expansions, so exp/log are accurate down to a = 0.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "ppcr/abi.hpp"

namespace ppcr {
inline namespace PPCR_ABI_NAMESPACE {
namespace se3 {

using Vector6d = Eigen::Matrix<double, 6, 1>;

/// [w]_x : the 3x3 skew-symmetric matrix with [w]_x p = w x p. Inline: the plane model's
/// normal-equation pass builds one per source point and pass.
inline Eigen::Matrix3d skew(const Eigen::Vector3d& w) {
  Eigen::Matrix3d S;
  S << 0.0, -w.z(), w.y(), w.z(), 0.0, -w.x(), -w.y(), w.x(), 0.0;
  return S;
}

/// Rodrigues: rotation by angle |w| about w / |w|.
Eigen::Matrix3d exp_so3(const Eigen::Vector3d& w);

/// Inverse of exp_so3 on rotations of angle in [0, pi]. At angle pi exactly, where +-pi n are
/// both logs, one of the two is returned.
Eigen::Vector3d log_so3(const Eigen::Matrix3d& R);

/// exp of a twist (omega, v).
Eigen::Isometry3d exp(const Vector6d& xi);

/// log of a rigid transform, inverse of exp for rotation angles below pi; at pi it returns the
/// twist built on log_so3's choice of axis sign, and exp of it reproduces T.
Vector6d log(const Eigen::Isometry3d& T);

/// Rotation angle of R in radians, in [0, pi] (robust near 0 and pi).
double rotation_angle(const Eigen::Matrix3d& R);

/// Re-orthonormalises the rotation part of T (polar decomposition via SVD), keeping det = +1.
Eigen::Isometry3d orthonormalized(const Eigen::Isometry3d& T);

/// True if T's top-left 3x3 block is a rotation within tol (R^T R = I, det R = 1) and the last
/// row is (0 0 0 1): what a caller should check before trusting a user-given matrix.
bool is_rigid(const Eigen::Matrix4d& T, double tol = 1e-6);

}  // namespace se3
}  // namespace PPCR_ABI_NAMESPACE
}  // namespace ppcr
