// metrics.hpp - errors between poses and the point clouds registration benchmark's metric:
// evaluation against a ground truth, run by the caller after a registration (never inside it).
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cstddef>

#include "ppcr/abi.hpp"
#include "ppcr/types.hpp"

namespace ppcr {
inline namespace PPCR_ABI_NAMESPACE {

/// First and second moments of a cloud: enough to evaluate mean |A x - B x|^2 in O(1).
struct CloudMoments {
  std::size_t count = 0;
  Eigen::Vector3d mean = Eigen::Vector3d::Zero();        // (1/N) sum x
  Eigen::Matrix3d covariance = Eigen::Matrix3d::Zero();  // (1/N) sum (x - mean)(x - mean)^T
};

CloudMoments compute_moments(const PointCloud& cloud);

/// mean_i |A x_i - B x_i|^2 over the cloud described by m (paper eq. 5), in O(1):
/// with D = R_A - R_B, u = t_A - t_B and M = covariance + mean mean^T,
///   = trace(D M D^T) + 2 u^T D mean + |u|^2.
double mse_between(const CloudMoments& m, const Eigen::Isometry3d& A, const Eigen::Isometry3d& B);

/// Angle in degrees of R_est^T R_gt.
double rotation_error_deg(const Eigen::Isometry3d& T_est, const Eigen::Isometry3d& T_gt);

/// |t_est - t_gt| in cloud units.
double translation_error(const Eigen::Isometry3d& T_est, const Eigen::Isometry3d& T_gt);

/// The benchmark's error (Fontana et al. 2020; ../shared/data/README.md): with P_i = T_gt x_i
/// (the source in its true pose), Q_i = T_est x_i and c the centroid of P,
///   e = mean_i |P_i - Q_i| / |P_i - c|.
/// Points with P_i == c are skipped. Returns 0 for an empty cloud.
double benchmark_error(const PointCloud& source, const Eigen::Isometry3d& T_gt,
                       const Eigen::Isometry3d& T_est);

/// A registration's errors against a ground truth.
struct PoseErrors {
  double rotation_error_deg = 0.0;  // rotation_error_deg(T_est, T_gt)
  double translation_error = 0.0;   // translation_error(T_est, T_gt), cloud units
  double benchmark_error = 0.0;     // benchmark_error(source, T_gt, T_est)
  double mse = 0.0;                 // mean |T_est x - T_gt x|^2 over source, cloud units^2
};

/// All of PoseErrors for T_est on `source` (the cloud that was registered).
PoseErrors evaluate(const PointCloud& source, const Eigen::Isometry3d& T_est,
                    const Eigen::Isometry3d& T_gt);

}  // namespace PPCR_ABI_NAMESPACE
}  // namespace ppcr
