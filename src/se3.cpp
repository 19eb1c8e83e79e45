// se3.cpp - exp/log on SO(3) and SE(3), twist (omega, v), left update (see se3.hpp).
#include "ppcr/se3.hpp"

#include <Eigen/SVD>
#include <algorithm>
#include <cmath>

namespace ppcr {
namespace se3 {
namespace {

// Coefficients of exp: A = sin(a)/a, B = (1 - cos a)/a^2, C = (a - sin a)/a^3, with Taylor
// series below a = 1e-4 rad where the closed forms lose digits to cancellation.
struct ExpCoefficients {
  double A, B, C;
};

ExpCoefficients exp_coefficients(double a) {
  const double a2 = a * a;
  if (a < 1e-4) {
    return {1.0 - a2 / 6.0 + a2 * a2 / 120.0, 0.5 - a2 / 24.0 + a2 * a2 / 720.0,
            1.0 / 6.0 - a2 / 120.0 + a2 * a2 / 5040.0};
  }
  return {std::sin(a) / a, (1.0 - std::cos(a)) / a2, (a - std::sin(a)) / (a2 * a)};
}

}  // namespace

Eigen::Matrix3d skew(const Eigen::Vector3d& w) {
  Eigen::Matrix3d S;
  S << 0.0, -w.z(), w.y(), w.z(), 0.0, -w.x(), -w.y(), w.x(), 0.0;
  return S;
}

Eigen::Matrix3d exp_so3(const Eigen::Vector3d& w) {
  // Rodrigues: R = I + A [w]_x + B [w]_x^2.
  const ExpCoefficients c = exp_coefficients(w.norm());
  const Eigen::Matrix3d W = skew(w);
  return Eigen::Matrix3d::Identity() + c.A * W + c.B * W * W;
}

double rotation_angle(const Eigen::Matrix3d& R) {
  // atan2(|sin|, cos) is accurate over the whole range, unlike acos((tr - 1) / 2) near 0 and pi.
  const double cos_a = 0.5 * (R.trace() - 1.0);
  const Eigen::Vector3d axis_sin(R(2, 1) - R(1, 2), R(0, 2) - R(2, 0), R(1, 0) - R(0, 1));
  const double sin_a = 0.5 * axis_sin.norm();
  return std::atan2(sin_a, cos_a);
}

Eigen::Vector3d log_so3(const Eigen::Matrix3d& R) {
  const double a = rotation_angle(R);
  const Eigen::Vector3d v(R(2, 1) - R(1, 2), R(0, 2) - R(2, 0), R(1, 0) - R(0, 1));  // 2 sin a n
  if (a < 1e-4) {
    // a / (2 sin a) = 1/2 + a^2/12 + O(a^4)
    return (0.5 + a * a / 12.0) * v;
  }
  if (a < M_PI - 1e-4) return (a / (2.0 * std::sin(a))) * v;
  // Near pi the antisymmetric part vanishes: recover the axis from the symmetric part,
  // R + I = 2 n n^T + O(pi - a); take the largest column and fix its sign with v.
  const Eigen::Matrix3d S = 0.5 * (R + Eigen::Matrix3d::Identity());
  int k = 0;
  S.diagonal().maxCoeff(&k);
  Eigen::Vector3d n = S.col(k) / std::sqrt(std::max(S(k, k), 1e-300));
  n.normalize();
  if (n.dot(v) < 0.0) n = -n;
  return a * n;
}

Eigen::Isometry3d exp(const Vector6d& xi) {
  const Eigen::Vector3d w = xi.head<3>();
  const Eigen::Vector3d v = xi.tail<3>();
  const ExpCoefficients c = exp_coefficients(w.norm());
  const Eigen::Matrix3d W = skew(w);
  const Eigen::Matrix3d W2 = W * W;
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = Eigen::Matrix3d::Identity() + c.A * W + c.B * W2;
  T.translation() = (Eigen::Matrix3d::Identity() + c.B * W + c.C * W2) * v;  // V v
  return T;
}

Vector6d log(const Eigen::Isometry3d& T) {
  const Eigen::Vector3d w = log_so3(T.linear());
  const double a = w.norm();
  const Eigen::Matrix3d W = skew(w);
  // V^{-1} = I - 1/2 [w]_x + D [w]_x^2, D = (1 - A / (2 B)) / a^2, Taylor 1/12 + a^2/720.
  double D;
  if (a < 1e-4) {
    D = 1.0 / 12.0 + a * a / 720.0;
  } else {
    const ExpCoefficients c = exp_coefficients(a);
    D = (1.0 - c.A / (2.0 * c.B)) / (a * a);
  }
  const Eigen::Matrix3d V_inv = Eigen::Matrix3d::Identity() - 0.5 * W + D * W * W;
  Vector6d xi;
  xi.head<3>() = w;
  xi.tail<3>() = V_inv * T.translation();
  return xi;
}

Eigen::Isometry3d orthonormalized(const Eigen::Isometry3d& T) {
  Eigen::JacobiSVD<Eigen::Matrix3d> svd(T.linear(), Eigen::ComputeFullU | Eigen::ComputeFullV);
  Eigen::Matrix3d U = svd.matrixU();
  const Eigen::Matrix3d V = svd.matrixV();
  if ((U * V.transpose()).determinant() < 0.0) U.col(2) = -U.col(2);
  Eigen::Isometry3d out = Eigen::Isometry3d::Identity();
  out.linear() = U * V.transpose();
  out.translation() = T.translation();
  return out;
}

bool is_rigid(const Eigen::Matrix4d& T, double tol) {
  if (!T.allFinite()) return false;
  const Eigen::Matrix3d R = T.topLeftCorner<3, 3>();
  if ((R.transpose() * R - Eigen::Matrix3d::Identity()).cwiseAbs().maxCoeff() > tol) return false;
  if (std::abs(R.determinant() - 1.0) > tol) return false;
  const Eigen::RowVector4d last = T.row(3);
  return (last - Eigen::RowVector4d(0, 0, 0, 1)).cwiseAbs().maxCoeff() <= tol;
}

}  // namespace se3
}  // namespace ppcr
