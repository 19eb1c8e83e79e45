// outliers.cpp - uniform outliers in the scene's bounds near the sensor.
#include "outliers.hpp"

#include <cmath>
#include <cstddef>

namespace ppcr {
inline namespace PPCR_ABI_NAMESPACE {
namespace synthetic {
namespace internal {

void add_outliers(const Scene& scene, double fraction, double max_range,
                  const Eigen::Isometry3d& world_T_sensor, Rng* rng, PointCloud* cloud) {
  if (fraction <= 0.0) return;
  const auto count = static_cast<std::size_t>(
      std::llround(static_cast<double>(cloud->size()) * fraction / (1.0 - fraction)));
  const Eigen::Vector3d position = world_T_sensor.translation();
  const Eigen::Vector3d reach = Eigen::Vector3d::Constant(max_range);
  Eigen::AlignedBox3d region =
      scene.bounds.intersection(Eigen::AlignedBox3d(position - reach, position + reach));
  if (region.isEmpty()) region = scene.bounds;
  const Eigen::Isometry3d sensor_T_world = world_T_sensor.inverse(Eigen::Isometry);
  cloud->reserve(cloud->size() + count);
  for (std::size_t i = 0; i < count; ++i) {
    Eigen::Vector3d p;
    for (int axis = 0; axis < 3; ++axis) {
      p[axis] = rng->uniform(region.min()[axis], region.max()[axis]);
    }
    cloud->push_back(sensor_T_world * p);
  }
}

}  // namespace internal
}  // namespace synthetic
}  // namespace PPCR_ABI_NAMESPACE
}  // namespace ppcr
