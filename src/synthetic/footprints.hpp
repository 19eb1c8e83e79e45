// footprints.hpp - placing objects on a floor or a table: their footprints (discs) avoid each
// other when they can, and they stand upright, turned about the vertical axis.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <vector>

#include "ppcr/abi.hpp"

namespace ppcr {
inline namespace PPCR_ABI_NAMESPACE {
namespace synthetic {
namespace internal {

/// The rotation by yaw (radians) about the vertical axis z: how objects stand on a floor or table.
inline Eigen::Matrix3d yaw_matrix(double yaw) {
  return Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()).toRotationMatrix();
}

class FootprintPlanner {
 public:
  /// gap: the clearance kept between two footprints' discs, metres.
  explicit FootprintPlanner(double gap) : gap_(gap) {}

  /// Up to 200 candidate centres from sample(&p) (false: outside the allowed region, skipped):
  /// the first whose disc of `radius` keeps the gap to every footprint placed, else the first
  /// allowed one, else `fallback`. Records the footprint placed.
  template <class Sample>
  Eigen::Vector2d place(double radius, const Eigen::Vector2d& fallback, Sample&& sample) {
    Eigen::Vector2d chosen = fallback;
    bool have_valid = false;
    for (int attempt = 0; attempt < 200; ++attempt) {
      Eigen::Vector2d p;
      if (!sample(&p)) continue;
      if (!have_valid) {
        chosen = p;
        have_valid = true;
      }
      bool free = true;
      for (const Eigen::Vector3d& f : placed_) {
        if ((p - f.head<2>()).norm() < radius + f.z() + gap_) free = false;
      }
      if (free) {
        chosen = p;
        break;
      }
    }
    placed_.emplace_back(chosen.x(), chosen.y(), radius);
    return chosen;
  }

 private:
  double gap_;
  std::vector<Eigen::Vector3d> placed_;  // (x, y, radius)
};

}  // namespace internal
}  // namespace synthetic
}  // namespace PPCR_ABI_NAMESPACE
}  // namespace ppcr
