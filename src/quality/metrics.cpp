// metrics.cpp - pose errors, O(1) MSE between two poses, the benchmark's metric.
#include "ppcr/metrics.hpp"

#include <cmath>

#include "ppcr/se3.hpp"

namespace ppcr {
inline namespace PPCR_ABI_NAMESPACE {

CloudMoments compute_moments(const PointCloud& cloud) {
  CloudMoments m;
  m.count = cloud.size();
  if (cloud.empty()) return m;
  // Two passes (mean, then centred products): no cancellation for clouds far from the origin.
  Eigen::Vector3d sum = Eigen::Vector3d::Zero();
  for (const Eigen::Vector3d& p : cloud) sum += p;
  m.mean = sum / static_cast<double>(cloud.size());
  Eigen::Matrix3d c = Eigen::Matrix3d::Zero();
  for (const Eigen::Vector3d& p : cloud) {
    const Eigen::Vector3d d = p - m.mean;
    c.noalias() += d * d.transpose();
  }
  m.covariance = c / static_cast<double>(cloud.size());
  return m;
}

double mse_between(const CloudMoments& m, const Eigen::Isometry3d& A, const Eigen::Isometry3d& B) {
  if (m.count == 0) return 0.0;
  // A x - B x = D x + u. Written about the mean, x = mean + y with E[y] = 0, E[y y^T] = C:
  //   E|D x + u|^2 = |D mean + u|^2 + trace(D C D^T)   (same value as the header's form, better
  //   conditioned when the cloud is far from the origin).
  const Eigen::Matrix3d D = A.linear() - B.linear();
  const Eigen::Vector3d offset = D * m.mean + (A.translation() - B.translation());
  return offset.squaredNorm() + (D * m.covariance * D.transpose()).trace();
}

double rotation_error_deg(const Eigen::Isometry3d& T_est, const Eigen::Isometry3d& T_gt) {
  return se3::rotation_angle(T_est.linear().transpose() * T_gt.linear()) * 180.0 / M_PI;
}

double translation_error(const Eigen::Isometry3d& T_est, const Eigen::Isometry3d& T_gt) {
  return (T_est.translation() - T_gt.translation()).norm();
}

double benchmark_error(const PointCloud& source, const Eigen::Isometry3d& T_gt,
                       const Eigen::Isometry3d& T_est) {
  if (source.empty()) return 0.0;
  Eigen::Vector3d sum = Eigen::Vector3d::Zero();
  for (const Eigen::Vector3d& x : source) sum += T_gt * x;
  const Eigen::Vector3d c = sum / static_cast<double>(source.size());
  double total = 0.0;
  std::size_t used = 0;
  for (const Eigen::Vector3d& x : source) {
    const Eigen::Vector3d p = T_gt * x;
    const double denom = (p - c).norm();
    if (!(denom > 0.0)) continue;
    total += (p - T_est * x).norm() / denom;
    ++used;
  }
  return used > 0 ? total / static_cast<double>(used) : 0.0;
}

PoseErrors evaluate(const PointCloud& source, const Eigen::Isometry3d& T_est,
                    const Eigen::Isometry3d& T_gt) {
  PoseErrors e;
  e.rotation_error_deg = rotation_error_deg(T_est, T_gt);
  e.translation_error = translation_error(T_est, T_gt);
  e.benchmark_error = benchmark_error(source, T_gt, T_est);
  e.mse = mse_between(compute_moments(source), T_est, T_gt);
  return e;
}

}  // namespace PPCR_ABI_NAMESPACE
}  // namespace ppcr
