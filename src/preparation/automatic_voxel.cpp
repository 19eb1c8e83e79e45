// automatic_voxel.cpp - the leaf that leaves about a given number of points.
#include "preparation/automatic_voxel.hpp"

#include <algorithm>
#include <cmath>

#include "ppcr/voxel.hpp"

namespace ppcr {
inline namespace PPCR_ABI_NAMESPACE {
namespace detail {

Status automatic_voxel_filter(const PointCloud& in, std::size_t points, PointCloud* out,
                              double* leaf) {
  *leaf = 0.0;
  if (in.size() <= points || points == 0) {
    *out = in;
    return Status::Ok();
  }
  Eigen::Vector3d lo = in.front(), hi = in.front();
  for (const Eigen::Vector3d& p : in) lo = lo.cwiseMin(p), hi = hi.cwiseMax(p);
  const double wanted = static_cast<double>(points);
  double trial = (hi - lo).norm() / std::sqrt(wanted);
  if (!(trial > 0.0)) {  // all points equal: one voxel holds them
    *out = PointCloud{in.front()};
    return Status::Ok();
  }
  constexpr int kMaxSteps = 6;
  constexpr double kTolerance = 0.15;
  for (int step = 0; step < kMaxSteps; ++step) {
    Status s = voxel_downsample(in, trial, out);
    if (!s.ok()) return s;
    *leaf = trial;
    const double ratio = static_cast<double>(out->size()) / wanted;
    if (std::abs(ratio - 1.0) <= kTolerance) break;
    trial *= std::clamp(std::sqrt(ratio), 0.25, 4.0);
  }
  return Status::Ok();
}

}  // namespace detail
}  // namespace PPCR_ABI_NAMESPACE
}  // namespace ppcr
