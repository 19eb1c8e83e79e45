// covariance.hpp - the covariance of the estimated pose (RegistrationResult::covariance).
//
// The estimate T solves g(T) = sum_j g_j(T) = 0, with g_j = J_j^T ebar_j the gradient of source
// point j's terms (normal_equations.hpp). To first order its error delta (T = exp(delta) T_true,
// the twist on the left) is -H^-1 g(T_true), so
//   Cov(delta) = H^-1 Cov(g) H^-1,
// the sandwich covariance of an M-estimator. It holds whatever the weights (Student-t or
// Gaussian) and the residuals' scale, which a scaled H^-1 does not: Cov(g) is measured from the
// final pass's own terms, not assumed. The terms are not independent: the k pairs of a source
// point share its noise, neighbouring source points share target points and the target normals
// fitted over them, and a voxel filter's points are not independent samples of the surface. So
// Cov(g) sums the outer products of cluster sums, G_c G_c^T with G_c = sum_{j in c} g_j, over
// clusters of kClusterPoints consecutive source points: the source is in spatial order
// (spatial_order.hpp), so a cluster is a patch of surface, and terms correlated within a patch
// count as one measurement (the cluster-robust sandwich).
//
// H is not the Gauss-Newton H of the solver: that one treats the weights as constants, but the
// weights are the E-step's posteriors at T, and the function the estimate maximises is the
// mixture's log-likelihood sum_j log sum_k p_kj (eq. 3). Its curvature, with
// a_kj = J_j^T Omega_kj e_kj (g_j = sum_k w_kj a_kj) and z_kj = e^T Omega e / s^2, is
//   H_true = H_GN - (1 / s^2) sum_j ( sum_k c_kj a_kj a_kj^T - g_j g_j^T ),
//   c_kj = w_kj (nu + d + 2) / (nu + z_kj) (Student-t, d = 3),  c_kj = w_kj (Gaussian):
// the weights fall as a pair's error grows, and a point's posteriors move between its
// neighbours. Where errors are large against the scale s, H_true is much smaller than H_GN, and
// the pose much looser than H_GN says.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cstddef>
#include <vector>

#include "association/association_table.hpp"
#include "model/normal_equations.hpp"
#include "ppcr/abi.hpp"
#include "ppcr/types.hpp"

namespace ppcr {
inline namespace PPCR_ABI_NAMESPACE {
namespace detail {

class Parallel;  // parallel.hpp

/// Source points per cluster of Cov(g), and the factor the sandwich is multiplied by; chosen on
/// one half of the calibration study (docs/COVARIANCE.md).
constexpr std::size_t kClusterPoints = 64;
constexpr double kCovarianceCalibration = 2.0;
/// Below this many clusters with pairs, sum_c G_c G_c^T is too few samples of Cov(g) (of rank at
/// most their count): s^2 H_GN, the residuals' scale times the solver's H, stands in for it.
constexpr std::size_t kMinClusters = 30;

/// What the final pass's terms are formed from (as NormalEquations::evaluate).
struct GradientTerms {
  const PointCloud* source = nullptr;  // the associated source points
  const AssociationTable* table = nullptr;
  const double* weights = nullptr;  // the E-step weights at T, the table's stride
  Eigen::Isometry3d T_target_source = Eigen::Isometry3d::Identity();
  const PointCloud* target = nullptr;  // point model
  const PlaneModel* plane = nullptr;   // null: point model
  WeightParams e_step;                 // the weights' model, dof and 1 / s^2
};

/// The two sums the covariance is formed from.
struct CovarianceSums {
  Matrix6d meat = Matrix6d::Zero();       // Cov(g): sum_c G_c G_c^T over the clusters
  Matrix6d curvature = Matrix6d::Zero();  // sum_j (sum_k c_kj a_kj a_kj^T - g_j g_j^T) (header)
  std::size_t clusters = 0;               // clusters with at least one row used
};

/// Both sums, parallel over the clusters on the threads of `parallel` (null: the calling
/// thread), each cluster's into (*clusters)[c] (resized; allocates only when it grows), summed
/// in order: the same for any thread count.
CovarianceSums covariance_sums(const GradientTerms& terms, const Parallel* parallel,
                               std::vector<CovarianceSums>* clusters);

/// H^-1 M H^-1 (times kCovarianceCalibration), with H's eigenvalues floored at 1e-12 of its
/// largest so that a singular H gives large, finite variances, never NaN. Zero when H is zero or
/// not finite.
Matrix6d sandwich_covariance(const Matrix6d& H, const Matrix6d& M);

/// C made exactly symmetric and positive semi-definite: the rounding of H^-1 M H^-1 and of the
/// changes of frame leaves eigenvalues of about -1e-16 of the largest, which may show as a
/// negative variance. The eigenvalues of C scaled to unit diagonal are clamped at 0 (scaled, so
/// that rotations in radians and translations in any unit keep their relative precision);
/// a variance that is not positive zeroes its row and column.
Matrix6d positive_semidefinite(const Matrix6d& C);

}  // namespace detail
}  // namespace PPCR_ABI_NAMESPACE
}  // namespace ppcr
