// scanner.cpp - ray casting a scan.
#include "scanner.hpp"

#include <cmath>
#include <cstddef>
#include <vector>

namespace ppcr {
inline namespace PPCR_ABI_NAMESPACE {
namespace synthetic {
namespace internal {

void scan(const Scene& scene, const SensorModel& sensor, const Eigen::Isometry3d& world_T_sensor,
          double noise_sigma, Rng* noise, PointCloud* out) {
  constexpr double kDegree = Rng::kPi / 180.0;
  const auto beams = static_cast<std::size_t>(sensor.beams);
  const auto steps = static_cast<std::size_t>(sensor.horizontal_steps);
  // Per-beam elevation cosines and sines, computed once per scan (no allocation per ray).
  std::vector<double> cos_elevation(beams);
  std::vector<double> sin_elevation(beams);
  for (std::size_t b = 0; b < beams; ++b) {
    const double fraction =
        beams == 1 ? 0.5 : static_cast<double>(b) / static_cast<double>(beams - 1);
    const double elevation =
        (sensor.fov_down_deg + fraction * (sensor.fov_up_deg - sensor.fov_down_deg)) * kDegree;
    cos_elevation[b] = std::cos(elevation);
    sin_elevation[b] = std::sin(elevation);
  }
  const Eigen::Matrix3d rotation = world_T_sensor.linear();
  Ray ray;
  ray.origin = world_T_sensor.translation();
  out->reserve(out->size() + beams * steps);
  for (std::size_t k = 0; k < steps; ++k) {
    const double azimuth = 2.0 * Rng::kPi * static_cast<double>(k) / static_cast<double>(steps);
    const double cos_azimuth = std::cos(azimuth);
    const double sin_azimuth = std::sin(azimuth);
    for (std::size_t b = 0; b < beams; ++b) {
      // Unit direction in the sensor frame; the world ray has the rotated direction.
      const Eigen::Vector3d direction(cos_elevation[b] * cos_azimuth,
                                      cos_elevation[b] * sin_azimuth, sin_elevation[b]);
      ray.direction = rotation * direction;
      const double t = scene.cast(ray, sensor.max_range);
      if (t == kNoHit || t < sensor.min_range) continue;  // nothing, or blinded by a close hit
      const double range = noise_sigma > 0.0 ? t + noise_sigma * noise->normal() : t;
      out->push_back(range * direction);
    }
  }
}

}  // namespace internal
}  // namespace synthetic
}  // namespace PPCR_ABI_NAMESPACE
}  // namespace ppcr
