// alignment_quality.hpp - how well the registered clouds agree, in cloud units, measured after the
// last iteration (not in the loop): Open3D's fitness and inlier RMSE, the overlap both ways, and
// the share of the matched points that lie on the target's surface (the verdict's main signal).
#pragma once

#include <Eigen/Geometry>
#include <vector>

#include "association/kdtree.hpp"
#include "model/normal_equations.hpp"
#include "ppcr/abi.hpp"
#include "ppcr/types.hpp"

namespace ppcr {
inline namespace PPCR_ABI_NAMESPACE {
namespace detail {

class Parallel;  // parallel.hpp

struct AlignmentQuality {
  double fitness = 0.0;         // fraction of source points with a target point within the radius
  double inlier_rmse = 0.0;     // RMS distance of those points to their nearest target point
  double overlap = 0.0;         // the same fraction both ways: min(fitness, target's fraction)
  double close_fraction = 0.0;  // of the source points within near_distance of the target, the
                                // fraction on its surface (SurfaceTest)
};

/// When a source point p counts as on the target's surface, given its nearest target point y:
/// within close_distance of y; or, when `planes` (indexed like the target) gives y a normal n,
/// within close_distance of y's tangent plane (|n . (p - y)|) and within max(reach,
/// close_distance) of y, reach being the target's typical normal-fit reach (one value for the
/// cloud). A scanner samples along rings far apart: a right result's points lie on the target's
/// planes but often several spacings from the nearest sample, up to about the reach of a normal
/// fit, whose neighbours line up along a ring.
struct SurfaceTest {
  double close_distance = 0.0;
  const Buffer<PlanePoint>* planes = nullptr;
  double reach = 0.0;
};

/// For source moved by T_target_source (both clouds in the tree's frame): each source point's
/// nearest target point within radius. With source_tree (indexing source) also the target's
/// fraction with a source point within radius, else overlap = fitness. close_fraction: of the
/// source points within near_distance (<= radius) of their nearest target point, the share on
/// the target's surface (`surface`); near_distance is the reach of the points that share is taken
/// over, so that it does not fall with a radius far larger than the data's scale. Parallel,
/// deterministic (integer counts and blocked sums in a fixed order). scratch holds the per-block
/// partial sums (kept by the caller: a same-size call allocates nothing).
AlignmentQuality measure_alignment(const KdTree& target_tree, const PointCloud& target,
                                   const PointCloud& source, const KdTree* source_tree,
                                   const Eigen::Isometry3d& T_target_source, double radius,
                                   double near_distance, const SurfaceTest& surface,
                                   const Parallel* parallel, std::vector<double>* scratch);

}  // namespace detail
}  // namespace PPCR_ABI_NAMESPACE
}  // namespace ppcr
