// scanner.hpp - one range scan of a scene by a spinning lidar (internal to ppcr_synthetic).
#pragma once

#include <Eigen/Geometry>

#include "ppcr/abi.hpp"
#include "ppcr/synthetic.hpp"
#include "ppcr/types.hpp"
#include "random.hpp"
#include "scene.hpp"

namespace ppcr {
inline namespace PPCR_ABI_NAMESPACE {
namespace synthetic {
namespace internal {

/// Casts one ray per (azimuth step, beam) of the sensor (see SensorModel) from the pose
/// world_T_sensor and appends the returns to *out, in the sensor's frame, azimuth-major. A ray
/// returns when the first surface it meets is at a distance r in [min_range, max_range); the
/// point is (r + noise_sigma * n) times the ray's unit direction, with n a standard normal
/// deviate drawn from *noise (one per return, in order). The sensor must be valid.
void scan(const Scene& scene, const SensorModel& sensor, const Eigen::Isometry3d& world_T_sensor,
          double noise_sigma, Rng* noise, PointCloud* out);

}  // namespace internal
}  // namespace synthetic
}  // namespace PPCR_ABI_NAMESPACE
}  // namespace ppcr
