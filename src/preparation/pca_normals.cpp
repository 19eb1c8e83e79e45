// pca_normals.cpp - PCA normals of a cloud for the plane error model: the target's, and the
// source's with ExpertOptions::source_normals.
#include "preparation/pca_normals.hpp"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cassert>
#include <cmath>
#include <limits>

#include "common/parallel.hpp"
#include "preparation/boundary.hpp"
#include "preparation/point_spacing.hpp"

namespace ppcr {
inline namespace PPCR_ABI_NAMESPACE {
namespace detail {

NormalFit fit_normal(const PointCloud& points, const std::uint32_t* idx, int n) {
  NormalFit fit;
  if (n < 5) return fit;
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
    fit.normal = normal;
    fit.spread = std::sqrt(std::max(lambda[0], 0.0));
  }
  return fit;
}

void compute_normals(const PointCloud& points, const KdTree& tree, int neighbours,
                     const Parallel* parallel, std::vector<Eigen::Vector3d>* normals,
                     Buffer<double>* spread, Buffer<double>* reach, Buffer<double>* nearest_sq,
                     Buffer<std::uint8_t>* boundary) {
  // Sized, not filled: the loop writes every entry (each point is in the leaf order once), so
  // that each thread touches its own part of the arrays first (buffer.hpp).
  normals->resize(points.size());
  if (spread != nullptr) spread->resize(points.size());
  if (reach != nullptr) reach->resize(points.size());
  if (boundary != nullptr) boundary->resize(points.size());
  constexpr int kMaxNeighbours = 64;
  const int k = std::min(neighbours, kMaxNeighbours);
  // Fewer neighbours than a spacing query asks for may miss the nearest non-duplicate: none kept.
  if (nearest_sq != nullptr && k < kSpacingNeighbours) {
    nearest_sq->clear();
    nearest_sq = nullptr;
  }
  if (nearest_sq != nullptr) nearest_sq->resize(points.size());
  const double unbounded = std::numeric_limits<double>::max();
  // Points in the tree's leaf order: consecutive queries reach the same first leaf.
  const std::vector<std::uint32_t>& order = tree.leaf_order();
  assert(order.size() == points.size());
  // Blocks of kSeedBlock points in that order, each visited in order by one thread, so that a
  // query can be seeded by its block's previous one (header). The seed changes which cells the
  // search skips, never its result, so neither the blocks nor the threads change the normals.
  constexpr std::size_t kSeedBlock = 64;
  parallel_for_blocks(
      parallel, order.size(), kSeedBlock, [&](std::ptrdiff_t, std::size_t begin, std::size_t end) {
        std::uint32_t idx[kMaxNeighbours];
        double d2[kMaxNeighbours];
        int found = 0;  // the previous point's neighbours, idx[0..found)
        for (std::size_t ii = begin; ii < end; ++ii) {
          const std::uint32_t i = order[ii];
          const Eigen::Vector3d& q = points[i];
          // Seeded when the previous point found k: those are k real points, so they bound q's k-th
          // (seed_bound_sq, kdtree.hpp). Should the bounded query find fewer than k, it is repeated
          // unbounded (seeded_radius_knn).
          const double seed_sq = found == k ? seed_bound_sq(q, points, idx, k) : unbounded;
          found = seeded_radius_knn(tree, q, k, seed_sq, unbounded, idx, d2).found;
          const NormalFit fit = fit_normal(points, idx, found);
          (*normals)[i] = fit.normal;
          if (spread != nullptr) (*spread)[i] = fit.spread;
          if (reach != nullptr) (*reach)[i] = found > 0 ? std::sqrt(d2[found - 1]) : -1.0;
          if (nearest_sq != nullptr) (*nearest_sq)[i] = nearest_nonzero_sq(d2, found);
          if (boundary != nullptr) (*boundary)[i] = on_boundary(points, q, fit.normal, idx, found);
        }
      });
}

double upper_median(Buffer<double>* values) {
  values->erase(
      std::remove_if(values->begin(), values->end(), [](double v) { return !(v >= 0.0); }),
      values->end());
  return upper_median_in_place(values->data(), values->size());
}

}  // namespace detail
}  // namespace PPCR_ABI_NAMESPACE
}  // namespace ppcr
