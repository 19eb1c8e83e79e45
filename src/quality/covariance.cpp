// covariance.cpp - see covariance.hpp.
#include "quality/covariance.hpp"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>

#include "common/parallel.hpp"
#include "model/pair_normals.hpp"
#include "ppcr/se3.hpp"

namespace ppcr {
inline namespace PPCR_ABI_NAMESPACE {
namespace detail {
namespace {

// Source point j's terms at p = T x_j (covariance.hpp): with omega_k = Omega_k e_k, e_k = y_k - p
// and Omega_k = a I + n n^T (the target point's normal, the pair's normal as q s s^T
// (PairNormal), or I for the point model), a_k = J_j^T omega_k shares J_j = [ [p]_x | -I ], so
//   g_j = J_j^T ebar_j,  ebar_j = sum_k w_k omega_k,
//   sum_k c_k a_k a_k^T - g_j g_j^T = J_j^T (S_j - ebar_j ebar_j^T) J_j,
//   S_j = sum_k c_k omega_k omega_k^T:
// a 3x3 sum per pair, one 6x6 product per point. Adds g_j to *G and the point's term to *curvature.
void add_point(const GradientTerms& t, std::size_t j, Vector6d* G, Matrix6d* curvature) {
  const std::size_t k = static_cast<std::size_t>(t.table->k);
  const std::size_t count = t.table->count[j];
  const std::uint32_t* idx = &t.table->index[j * k];
  const double* w = &t.weights[j * k];
  const Eigen::Vector3d p = t.T_target_source * (*t.source)[j];
  const PlanePoint* points = t.plane != nullptr ? t.plane->points->data() : nullptr;
  const PairNormalSource* pairs = t.plane != nullptr ? t.plane->pair_source : nullptr;
  const Eigen::Vector3d m_j = pairs != nullptr
                                  ? Eigen::Vector3d(pairs->R_target_source * (*pairs->normals)[j])
                                  : Eigen::Vector3d::Zero();
  const bool student = t.e_step.model == WeightModel::kStudentT;
  const double nu = t.e_step.dof;
  Eigen::Vector3d ebar = Eigen::Vector3d::Zero();
  Eigen::Matrix3d S = Eigen::Matrix3d::Zero();
  // The pairs' normals as the pass forms them, kChunk pairs at a time (a small stack array).
  constexpr std::size_t kChunk = 16;
  PairNormal pair_normals[kChunk];
  for (std::size_t m = 0; m < count; ++m) {
    Eigen::Vector3d e, omega_e;  // e_k and Omega_k e_k
    if (points == nullptr) {
      e = (*t.target)[idx[m]] - p;
      omega_e = e;
    } else if (pairs != nullptr) {
      if (m % kChunk == 0) {
        pair_normals_of_point(m_j, &idx[m], std::min(kChunk, count - m), points, pair_normals);
      }
      const PairNormal& n = pair_normals[m % kChunk];
      e = points[idx[m]].y - p;
      omega_e = pair_isotropic(n, t.plane->epsilon) * e + (n.q * n.s.dot(e)) * n.s;
    } else {
      const PlanePoint& y = points[idx[m]];
      e = y.y - p;
      omega_e = y.a * e + y.n.dot(e) * y.n;
    }
    // c_k = w_k (nu + d + 2) / (nu + z_k), z_k = e^T Omega e / s^2, d = 3; Gaussian: c_k = w_k.
    const double z = e.dot(omega_e) * t.e_step.inv_scale_sq;
    const double c = student ? w[m] * (nu + 5.0) / (nu + z) : w[m];
    ebar += w[m] * omega_e;
    S.noalias() += (c * omega_e) * omega_e.transpose();
  }
  // J^T X J = [ -P X P , P X ; -X P , X ] with P = [p]_x (P^T = -P), X symmetric.
  const Eigen::Matrix3d X = S - ebar * ebar.transpose();
  const Eigen::Matrix3d P = se3::skew(p);
  const Eigen::Matrix3d PX = P * X;
  G->head<3>() += ebar.cross(p);
  G->tail<3>() -= ebar;
  curvature->topLeftCorner<3, 3>().noalias() -= PX * P;
  curvature->topRightCorner<3, 3>() += PX;
  curvature->bottomLeftCorner<3, 3>() += PX.transpose();
  curvature->bottomRightCorner<3, 3>() += X;
}

}  // namespace

CovarianceSums covariance_sums(const GradientTerms& terms, const Parallel* parallel,
                               std::vector<CovarianceSums>* clusters) {
  const std::size_t n = terms.source->size();
  clusters->resize(block_count(n, kClusterPoints));
  // Each cluster's own sums; a cluster without a used row adds nothing and counts 0.
  const auto cluster_sums = [&](std::ptrdiff_t c, std::size_t begin, std::size_t end) {
    CovarianceSums& sums = (*clusters)[static_cast<std::size_t>(c)];
    sums = CovarianceSums();
    Vector6d G = Vector6d::Zero();
    for (std::size_t j = begin; j < end; ++j) {
      if (!terms.table->used(j)) continue;
      add_point(terms, j, &G, &sums.curvature);
      sums.clusters = 1;
    }
    sums.meat = G * G.transpose();
  };
  parallel_for_blocks(parallel, n, kClusterPoints, cluster_sums);
  CovarianceSums sums;
  for (const CovarianceSums& cluster : *clusters) {
    sums.meat += cluster.meat;
    sums.curvature += cluster.curvature;
    sums.clusters += cluster.clusters;
  }
  return sums;
}

Matrix6d sandwich_covariance(const Matrix6d& H, const Matrix6d& M) {
  if (!H.allFinite() || !M.allFinite() || !(H.diagonal().maxCoeff() > 0.0)) {
    return Matrix6d::Zero();
  }
  Eigen::SelfAdjointEigenSolver<Matrix6d> eig(H);
  const Vector6d ev = eig.eigenvalues().cwiseMax(1e-12 * eig.eigenvalues().maxCoeff());
  const Matrix6d H_inverse =
      eig.eigenvectors() * ev.cwiseInverse().asDiagonal() * eig.eigenvectors().transpose();
  const Matrix6d C = kCovarianceCalibration * (H_inverse * M * H_inverse);
  return 0.5 * (C + C.transpose());
}

Matrix6d positive_semidefinite(const Matrix6d& C) {
  if (!C.allFinite()) return Matrix6d::Zero();
  Vector6d inverse_sd = Vector6d::Zero();
  for (int i = 0; i < 6; ++i) {
    if (C(i, i) > 0.0) inverse_sd[i] = 1.0 / std::sqrt(C(i, i));
  }
  const Matrix6d K =
      inverse_sd.asDiagonal() * (0.5 * (C + C.transpose())) * inverse_sd.asDiagonal();
  Eigen::SelfAdjointEigenSolver<Matrix6d> eig(K);
  const Matrix6d V = eig.eigenvectors();
  // Each diagonal entry of V D V^T is a sum of V_ik^2 D_k >= 0: never negative.
  const Matrix6d K_clamped = V * eig.eigenvalues().cwiseMax(0.0).asDiagonal() * V.transpose();
  Vector6d sd = Vector6d::Zero();
  for (int i = 0; i < 6; ++i) {
    if (inverse_sd[i] > 0.0) sd[i] = std::sqrt(C(i, i));
  }
  const Matrix6d out = sd.asDiagonal() * K_clamped * sd.asDiagonal();
  return 0.5 * (out + out.transpose());
}

}  // namespace detail
}  // namespace PPCR_ABI_NAMESPACE
}  // namespace ppcr
