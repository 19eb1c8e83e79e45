// se3.cpp - exp/log on SO(3) and SE(3), twist (omega, v), left update (see se3.hpp).
#include "ppcr/se3.hpp"

#include <Eigen/SVD>
#include <algorithm>
#include <cmath>

namespace ppcr {
inline namespace PPCR_ABI_NAMESPACE {
namespace se3 {
namespace {

// Coefficients of the SO(3)/SE(3) exponential and of V^{-1}, a = |omega| (Barfoot, State
// Estimation for Robotics, ch. 7: Rodrigues' formula and the left Jacobian J = V of SO(3) with
// its inverse; Sola et al., 'A micro Lie theory for state estimation in robotics',
// arXiv:1812.01537, SO(3)/SE(3) appendices):
//   R      = I + A W + B W^2                                        (W = [omega]_x)
//   V      = I + B W + C W^2
//   V^{-1} = I - 1/2 W + D W^2
//   A = sin(a)/a,  B = (1 - cos a)/a^2 = 2 sin^2(a/2)/a^2,  C = (a - sin a)/a^3,
//   D = (1 - A/(2B))/a^2 = (1 - (a/2) cot(a/2))/a^2.
// A and B are evaluated in cancellation-free forms (sin(a)/a and the half-angle form of B), so
// they carry a few ulps of relative error for every a > 0; the Taylor series below 1e-4 only
// avoid 0/0 (truncation error a^6/5040 < 1e-27). C and D are differences of O(1) terms that
// cancel to O(1/6) and O(1/12): the closed forms lose about log10(1/a^2) digits, so below
// a = 0.1 the Taylor series (truncated where the next term is < 1e-18 relative) are used.
constexpr double kTaylorAB = 1e-4;
constexpr double kTaylorCD = 0.1;

struct ExpCoefficients {
  double A, B, C;
};

ExpCoefficients exp_coefficients(double a) {
  const double a2 = a * a;
  ExpCoefficients c;
  if (a < kTaylorAB) {
    // sin(a)/a = 1 - a^2/6 + a^4/120 - ..., (1 - cos a)/a^2 = 1/2 - a^2/24 + a^4/720 - ...
    c.A = 1.0 - a2 / 6.0 + a2 * a2 / 120.0;
    c.B = 0.5 - a2 / 24.0 + a2 * a2 / 720.0;
  } else {
    const double s = std::sin(0.5 * a) / (0.5 * a);
    c.A = std::sin(a) / a;
    c.B = 0.5 * s * s;  // 2 sin^2(a/2) / a^2: no 1 - cos a cancellation.
  }
  if (a < kTaylorCD) {
    // (a - sin a)/a^3 = sum_k (-1)^k a^(2k) / (2k+3)!
    c.C = 1.0 / 6.0 - a2 * (1.0 / 120.0 -
                            a2 * (1.0 / 5040.0 - a2 * (1.0 / 362880.0 - a2 * (1.0 / 39916800.0))));
  } else {
    c.C = (a - std::sin(a)) / (a2 * a);
  }
  return c;
}

// D of V^{-1} above. Taylor (from x cot x = 1 - x^2/3 - x^4/45 - 2x^6/945 - x^8/4725 - ...,
// x = a/2): D = 1/12 + a^2/720 + a^4/30240 + a^6/1209600 + a^8/47900160 + ...
// At a = pi, cot(pi/2) = 0 and D = 1/pi^2: V^{-1} is finite on the whole range [0, pi].
double v_inverse_coefficient(double a) {
  const double a2 = a * a;
  if (a < kTaylorCD) {
    return 1.0 / 12.0 +
           a2 * (1.0 / 720.0 + a2 * (1.0 / 30240.0 + a2 * (1.0 / 1209600.0 + a2 / 47900160.0)));
  }
  const double half = 0.5 * a;
  return (1.0 - half / std::tan(half)) / a2;
}

}  // namespace

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
  // Barfoot ch. 7 / Sola et al. (SO(3) appendix): R = cos a I + (1 - cos a) n n^T + sin a [n]_x.
  const double a = rotation_angle(R);
  const Eigen::Vector3d v(R(2, 1) - R(1, 2), R(0, 2) - R(2, 0), R(1, 0) - R(0, 1));  // 2 sin a n
  if (a < kTaylorAB) {
    // a / (2 sin a) = 1/2 + a^2/12 + 7 a^4/720 + ...; the a^4 term is < 1e-17 relative here.
    return (0.5 + a * a / 12.0) * v;
  }
  // From the antisymmetric part, n = v / (2 sin a) carries an absolute error ~ eps / sin a
  // (the entries of R are O(1)); from the symmetric part, n n^T = (sym(R) - cos a I) /
  // (1 - cos a) carries ~ eps / (1 - cos a). The two bounds cross at a = pi/2, so each form
  // is used on its own half: the axis is then accurate to a few eps all the way up to pi.
  if (a <= 0.5 * M_PI) return (a / (2.0 * std::sin(a))) * v;
  const double cos_a = 0.5 * (R.trace() - 1.0);
  const Eigen::Matrix3d sym = 0.5 * (R + R.transpose());
  const Eigen::Matrix3d nnT = (sym - cos_a * Eigen::Matrix3d::Identity()) / (1.0 - cos_a);
  // The column of the largest diagonal entry n_k^2 >= 1/3 is n_k n: divide by |n_k|.
  int k = 0;
  nnT.diagonal().maxCoeff(&k);
  Eigen::Vector3d n = nnT.col(k) / std::sqrt(nnT(k, k));
  n.normalize();
  // n n^T fixes n only up to sign; n . v = 2 sin a > 0 selects it. At a = pi exactly (v = 0)
  // both signs are valid logs and this one is kept; when sin a is within rounding of 0 a wrong
  // sign moves exp(a n) by only O(sin a).
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
  const Eigen::Matrix3d W = skew(w);
  // v = V^{-1} t with V^{-1} = I - 1/2 [w]_x + D [w]_x^2 (see v_inverse_coefficient).
  const double D = v_inverse_coefficient(w.norm());
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
}  // namespace PPCR_ABI_NAMESPACE
}  // namespace ppcr
