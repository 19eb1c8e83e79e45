// automatic_voxel.cpp - the leaf that leaves about a given number of points.
#include "preparation/automatic_voxel.hpp"

#include <algorithm>
#include <cmath>
#include <utility>
#include <vector>

#include "ppcr/voxel.hpp"

namespace ppcr {
inline namespace PPCR_ABI_NAMESPACE {
namespace detail {
namespace {

// The extent of the middle 98 % of the points along each axis: a few far points (a (0, 0, 0)
// placeholder in georeferenced coordinates) do not set the first leaf.
Eigen::Vector3d robust_extent(const PointCloud& in) {
  std::vector<double> values(in.size());
  Eigen::Vector3d extent;
  const std::size_t lo = in.size() / 100, hi = in.size() - 1 - in.size() / 100;
  for (int axis = 0; axis < 3; ++axis) {
    for (std::size_t i = 0; i < in.size(); ++i) values[i] = in[i][axis];
    std::nth_element(values.begin(), values.begin() + lo, values.end());
    const double low = values[lo];
    std::nth_element(values.begin(), values.begin() + hi, values.end());
    extent[axis] = values[hi] - low;
  }
  return extent;
}

}  // namespace

Status automatic_voxel_filter(const PointCloud& in, std::size_t points, PointCloud* out,
                              double* leaf) {
  *leaf = 0.0;
  if (in.size() <= points || points == 0) {
    *out = in;
    return Status::Ok();
  }
  // A surface of area A holds about A / leaf^2 voxels: the first trial takes A from the two
  // largest extents (square roots first: no overflow for extents up to the largest double).
  Eigen::Vector3d extent = robust_extent(in);
  if (!(extent.maxCoeff() > 0.0)) {  // the middle points coincide: the whole cloud's extent
    Eigen::Vector3d lo = in.front(), hi = in.front();
    for (const Eigen::Vector3d& p : in) lo = lo.cwiseMin(p), hi = hi.cwiseMax(p);
    extent = hi - lo;
  }
  std::sort(extent.data(), extent.data() + 3);
  const double wanted = static_cast<double>(points);
  double trial =
      std::sqrt(extent[2]) * std::sqrt(std::max(extent[1], 1e-3 * extent[2])) / std::sqrt(wanted);
  if (!(trial > 0.0 && std::isfinite(trial))) {  // all points equal (or spans beyond a double)
    *out = in;
    return Status::Ok();
  }
  // The count falls as the leaf grows: bracket the wanted count and halve the bracket in
  // log(leaf), keeping the closest trial.
  constexpr int kMaxSteps = 12;
  constexpr double kTolerance = 0.15;
  double too_small = 0.0, too_large = HUGE_VAL, best_error = HUGE_VAL;
  PointCloud trial_out;
  for (int step = 0; step < kMaxSteps; ++step) {
    Status s = voxel_downsample(in, trial, &trial_out);
    if (!s.ok()) return s;
    const double ratio = static_cast<double>(trial_out.size()) / wanted;
    const double error = std::abs(std::log(ratio));
    if (error < best_error) {
      best_error = error;
      *leaf = trial;
      std::swap(*out, trial_out);
    }
    if (std::abs(ratio - 1.0) <= kTolerance) break;
    (ratio > 1.0 ? too_small : too_large) = trial;
    trial = too_small > 0.0 && too_large < HUGE_VAL
                ? std::sqrt(too_small) * std::sqrt(too_large)
                : trial * std::clamp(std::sqrt(ratio), 0.25, 4.0);
  }
  return Status::Ok();
}

}  // namespace detail
}  // namespace PPCR_ABI_NAMESPACE
}  // namespace ppcr
