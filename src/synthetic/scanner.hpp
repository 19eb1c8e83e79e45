// scanner.hpp - one range scan of a scene by a spinning lidar or a depth camera (internal to
// ppcr_synthetic).
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

/// The measurement model of a scan (see ScanOptions): Gaussian range noise of standard deviation
/// sigma (constant) or sqrt(sigma^2 + (per_metre r)^2) at true range r, then depth quantisation.
struct RangeNoise {
  double sigma = 0.0;
  double per_metre = 0.0;
  double quantisation = 0.0;  // q, 1/metres: depths become 1 / (q k), k a positive integer
};

/// Casts one ray per (azimuth step, beam) of the sensor (see SensorModel) from the pose
/// world_T_sensor and appends the returns to *out, in the sensor's frame, azimuth-major (for a
/// camera: column-major, then row). A ray returns when the first surface it meets is at a
/// distance r in [min_range, max_range); the point is (r + s n) times the ray's unit direction,
/// with s the noise's standard deviation at r and n a standard normal deviate drawn from *noise
/// (one per return, in order, when s > 0), then quantised (noise.quantisation > 0). The sensor
/// must be valid.
void scan(const Scene& scene, const SensorModel& sensor, const Eigen::Isometry3d& world_T_sensor,
          const RangeNoise& noise, Rng* rng, PointCloud* out);

}  // namespace internal
}  // namespace synthetic
}  // namespace PPCR_ABI_NAMESPACE
}  // namespace ppcr
