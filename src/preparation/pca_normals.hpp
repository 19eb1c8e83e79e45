// pca_normals.hpp - PCA normals of a cloud for the plane error model (normal_equations.hpp):
// the target's, and the source's with ExpertOptions::source_normals.
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <vector>

#include "association/kdtree.hpp"
#include "common/buffer.hpp"
#include "ppcr/abi.hpp"
#include "ppcr/types.hpp"

namespace ppcr {
inline namespace PPCR_ABI_NAMESPACE {
namespace detail {

class Parallel;  // parallel.hpp

/// The plane fit of one neighbourhood, points[idx[0..n)] summed in that order: normal is the unit
/// eigenvector of the smallest eigenvalue of their covariance (about their mean), spread the
/// square root of that eigenvalue (cloud units); normal zero and spread -1 when n < 5 or the
/// points do not spread in two directions (middle eigenvalue <= 1e-6 of the largest).
struct NormalFit {
  Eigen::Vector3d normal = Eigen::Vector3d::Zero();
  double spread = -1.0;
};
NormalFit fit_normal(const PointCloud& points, const std::uint32_t* idx, int n);

/// Fits a plane (PCA: the eigenvector of the smallest eigenvalue of the neighbourhood's
/// covariance) to the `neighbours` nearest points of each point of `points` (the target, or the
/// source), in parallel. normals[i] is a unit vector, or zero when fewer than 5 points were found
/// or they do not spread in two directions (middle eigenvalue <= 1e-6 of the largest).
/// Allocation-free per point. If spread is not null, spread[i] = sqrt(smallest eigenvalue): the RMS
/// distance of the fit's points from their plane (cloud units), or -1 where normals[i] is zero. The
/// fit of point i is fit_normal() of its k-d tree query for its k = min(neighbours, 64) nearest,
/// unbounded. The points are visited in the tree's leaf order, in blocks of 64 on one thread each,
/// and when its block's previous point found k neighbours, a point's query is seeded by those k
/// and repeated unbounded should it find fewer (seed_bound_sq and seeded_radius_knn, kdtree.hpp,
/// for why that finds the same neighbours in the same order), so the normals are those of unbounded
/// queries to the bit (test_target_normals). Precondition: tree was built over exactly `points`
/// (the points are visited in its leaf order; asserted).
/// If reach is not null, reach[i] = the distance of the farthest of those neighbours (the fit's
/// reach: about 2.5 spacings where the cloud is sampled evenly, far more along a scanner's rings,
/// whose neighbours line up along one ring), or -1 where none was found.
/// If nearest_sq is not null, nearest_sq[i] = nearest_nonzero_sq() of those neighbours
/// (point_spacing.hpp: what a spacing query would find) when k >= kSpacingNeighbours; with fewer
/// neighbours nearest_sq is left empty (they may not reach past a point's duplicates).
/// If boundary is not null, boundary[i] = 1 where points[i] lies on the cloud's boundary by those
/// neighbours and its normal (on_boundary(), boundary.hpp), else 0.
void compute_normals(const PointCloud& points, const KdTree& tree, int neighbours,
                     const Parallel* parallel, std::vector<Eigen::Vector3d>* normals,
                     Buffer<double>* spread = nullptr, Buffer<double>* reach = nullptr,
                     Buffer<double>* nearest_sq = nullptr,
                     Buffer<std::uint8_t>* boundary = nullptr);

/// The upper median of the values >= 0 (a value of the data), or 0 when there is none: of the
/// spreads written by compute_normals, the cloud's surface noise; of the reaches, its typical
/// reach. Drops the values < 0 from *values and partially sorts the rest in place (no copy).
double upper_median(Buffer<double>* values);

}  // namespace detail
}  // namespace PPCR_ABI_NAMESPACE
}  // namespace ppcr
