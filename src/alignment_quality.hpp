// alignment_quality.hpp - how well the registered clouds agree, in cloud units, measured after the
// last iteration (not in the loop): Open3D's fitness and inlier RMSE, the overlap both ways, and
// the share of the matched points that lie on the target's surface (the verdict's main signal).
#pragma once

#include <Eigen/Geometry>
#include <vector>

#include "kdtree.hpp"
#include "ppcr/abi.hpp"
#include "ppcr/types.hpp"

namespace ppcr {
inline namespace PPCR_ABI_NAMESPACE {
namespace detail {

struct AlignmentQuality {
  double fitness = 0.0;         // fraction of source points with a target point within the radius
  double inlier_rmse = 0.0;     // RMS distance of those points to their nearest target point
  double overlap = 0.0;         // the same fraction both ways: min(fitness, target's fraction)
  double close_fraction = 0.0;  // of the source points within near_distance of the target, the
                                // fraction within close_distance
};

/// For source moved by T_target_source (both clouds in the tree's frame): each source point's
/// nearest target point within radius. With source_tree (indexing source) also the target's
/// fraction with a source point within radius, else overlap = fitness. close_distance: the
/// distance within which a matched point counts as on the target's surface; near_distance
/// (<= radius): the reach of the points that fraction is taken over, so that it does not fall
/// with a radius far larger than the data's scale. Parallel, deterministic
/// (integer counts and blocked sums in a fixed order). scratch holds the per-block partial sums
/// (kept by the caller: a same-size call allocates nothing).
AlignmentQuality measure_alignment(const KdTree& target_tree, const PointCloud& target,
                                   const PointCloud& source, const KdTree* source_tree,
                                   const Eigen::Isometry3d& T_target_source, double radius,
                                   double near_distance, double close_distance, int num_threads,
                                   std::vector<double>* scratch);

}  // namespace detail
}  // namespace PPCR_ABI_NAMESPACE
}  // namespace ppcr
