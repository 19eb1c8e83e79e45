// alignment_quality.cpp - see alignment_quality.hpp.
#include "alignment_quality.hpp"

#include <algorithm>
#include <cmath>
#include <vector>

#include "parallel.hpp"

namespace ppcr {
inline namespace PPCR_ABI_NAMESPACE {
namespace detail {
namespace {

constexpr std::size_t kBlock = 1024;

struct Sums {
  double matched = 0.0;  // a count, exact in a double up to 2^53
  double dist_sq = 0.0;
};

// Nearest point of `tree` within radius of each T * points[i], summed per block, then in order.
Sums nearest_within(const KdTree& tree, const PointCloud& points, const Eigen::Isometry3d& T,
                    double radius_sq, int num_threads, std::vector<double>* scratch) {
  const std::size_t n_blocks = (points.size() + kBlock - 1) / kBlock;
  scratch->resize(2 * n_blocks);
  double* blocks = scratch->data();
  parallel_for(num_threads, static_cast<std::ptrdiff_t>(n_blocks), [&](std::ptrdiff_t b) {
    Sums s;
    const std::size_t begin = static_cast<std::size_t>(b) * kBlock;
    const std::size_t end = std::min(points.size(), begin + kBlock);
    for (std::size_t i = begin; i < end; ++i) {
      std::uint32_t index;
      double d_sq;
      if (tree.radius_knn(T * points[i], 1, radius_sq, &index, &d_sq) == 1) {
        s.matched += 1.0;
        s.dist_sq += d_sq;
      }
    }
    blocks[2 * static_cast<std::size_t>(b)] = s.matched;
    blocks[2 * static_cast<std::size_t>(b) + 1] = s.dist_sq;
  });
  Sums total;
  for (std::size_t b = 0; b < n_blocks; ++b) {
    total.matched += blocks[2 * b];
    total.dist_sq += blocks[2 * b + 1];
  }
  return total;
}

}  // namespace

AlignmentQuality measure_alignment(const KdTree& target_tree, const PointCloud& target,
                                   const PointCloud& source, const KdTree* source_tree,
                                   const Eigen::Isometry3d& T_target_source, double radius,
                                   int num_threads, std::vector<double>* scratch) {
  AlignmentQuality q;
  if (source.empty() || target.empty()) return q;
  const double radius_sq = radius * radius;
  const Sums s =
      nearest_within(target_tree, source, T_target_source, radius_sq, num_threads, scratch);
  q.fitness = s.matched / static_cast<double>(source.size());
  q.inlier_rmse = s.matched > 0.0 ? std::sqrt(s.dist_sq / s.matched) : 0.0;
  q.overlap = q.fitness;
  if (source_tree != nullptr) {
    const Sums back = nearest_within(*source_tree, target, T_target_source.inverse(), radius_sq,
                                     num_threads, scratch);
    q.overlap = std::min(q.fitness, back.matched / static_cast<double>(target.size()));
  }
  return q;
}

}  // namespace detail
}  // namespace PPCR_ABI_NAMESPACE
}  // namespace ppcr
