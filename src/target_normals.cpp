// target_normals.cpp - PCA normals of the target (plane error model).
#include "target_normals.hpp"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cassert>
#include <cmath>
#include <limits>

#include "parallel.hpp"

namespace ppcr {
inline namespace PPCR_ABI_NAMESPACE {
namespace detail {

void compute_normals(const PointCloud& points, const KdTree& tree, int neighbours, int num_threads,
                     std::vector<Eigen::Vector3d>* normals, std::vector<double>* spread) {
  normals->assign(points.size(), Eigen::Vector3d::Zero());
  if (spread != nullptr) spread->assign(points.size(), -1.0);
  constexpr int kMaxNeighbours = 64;
  const int k = std::min(neighbours, kMaxNeighbours);
  const double unbounded = std::numeric_limits<double>::max();
  // Points in the tree's leaf order: consecutive queries start from the same leaf.
  const std::vector<std::uint32_t>& order = tree.leaf_order();
  assert(order.size() == points.size());
  parallel_for(num_threads, static_cast<std::ptrdiff_t>(order.size()), [&](std::ptrdiff_t ii) {
    const std::uint32_t i = order[static_cast<std::size_t>(ii)];
    std::uint32_t idx[kMaxNeighbours];
    double d2[kMaxNeighbours];
    const Eigen::Vector3d& q = points[i];
    const int n = tree.radius_knn(q, k, unbounded, idx, d2);
    if (n < 5) return;
    // Covariance about the neighbourhood's mean (two passes: no cancellation).
    Eigen::Vector3d mean = Eigen::Vector3d::Zero();
    for (int m = 0; m < n; ++m) mean += points[idx[m]];
    mean /= n;
    Eigen::Matrix3d C = Eigen::Matrix3d::Zero();
    for (int m = 0; m < n; ++m) {
      const Eigen::Vector3d d = points[idx[m]] - mean;
      C.noalias() += d * d.transpose();
    }
    // Eigen's closed-form 3x3 solver; eigenvalues ascending, so column 0 is the normal.
    Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig;
    eig.computeDirect(C / n);
    const Eigen::Vector3d normal = eig.eigenvectors().col(0);
    // A normal exists only where the neighbourhood spreads in two directions: for collinear
    // (lambda_1 ~ 0) or identical points the smallest eigenvector is an arbitrary direction,
    // and the point keeps a zero normal (Omega = I, point-to-point).
    const Eigen::Vector3d lambda = eig.eigenvalues();
    const bool has_plane = lambda[1] > 1e-6 * lambda[2];
    if (has_plane && normal.allFinite() && std::abs(normal.norm() - 1.0) < 1e-6) {
      (*normals)[i] = normal;
      if (spread != nullptr) {
        (*spread)[i] = std::sqrt(std::max(lambda[0], 0.0));
      }
    }
  });
}

double surface_noise(const std::vector<double>& spread, std::vector<double>* scratch) {
  scratch->clear();
  for (double v : spread) {
    if (v >= 0.0) scratch->push_back(v);
  }
  if (scratch->empty()) return 0.0;
  // Upper median (a value of the data; the median of an even count would be a mean).
  const auto middle = scratch->begin() + static_cast<std::ptrdiff_t>(scratch->size() / 2);
  std::nth_element(scratch->begin(), middle, scratch->end());
  return *middle;
}

}  // namespace detail
}  // namespace PPCR_ABI_NAMESPACE
}  // namespace ppcr
