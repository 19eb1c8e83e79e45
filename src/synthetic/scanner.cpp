// scanner.cpp - ray casting a scan.
#include "scanner.hpp"

#include <cmath>
#include <cstddef>
#include <vector>

namespace ppcr {
inline namespace PPCR_ABI_NAMESPACE {
namespace synthetic {
namespace internal {
namespace {

constexpr double kDegree = Rng::kPi / 180.0;

/// The measured range along a ray of unit direction `direction` (sensor frame) whose true range
/// is t; returns false when the measurement is dropped (its depth quantises to infinity).
bool measure(double t, const Eigen::Vector3d& direction, bool pinhole, const RangeNoise& noise,
             Rng* rng, double* range) {
  if (noise.per_metre > 0.0) {
    const double sigma = std::hypot(noise.sigma, noise.per_metre * t);
    *range = t + sigma * rng->normal();
  } else {
    *range = noise.sigma > 0.0 ? t + noise.sigma * rng->normal() : t;
  }
  if (noise.quantisation > 0.0) {
    // Depth along the optical axis (camera) or along the ray (lidar); disparity 1 / depth is
    // quantised in steps of q, and the point stays on its ray.
    const double cosine = pinhole ? direction.x() : 1.0;
    const double depth = *range * cosine;
    if (!(depth > 0.0)) return false;
    const double level = std::round(1.0 / (noise.quantisation * depth));
    if (level < 1.0) return false;
    *range = 1.0 / (noise.quantisation * level) / cosine;
  }
  return true;
}

}  // namespace

void scan(const Scene& scene, const SensorModel& sensor, const Eigen::Isometry3d& world_T_sensor,
          const RangeNoise& noise, Rng* rng, PointCloud* out) {
  const auto beams = static_cast<std::size_t>(sensor.beams);
  const auto steps = static_cast<std::size_t>(sensor.horizontal_steps);
  const bool pinhole = sensor.projection == Projection::kPinhole;
  const bool full_turn = !pinhole && sensor.horizontal_fov_deg >= 360.0;
  // Per-beam (row) elevation cosines and sines, or image-plane heights, computed once per scan.
  std::vector<double> cos_elevation(beams);
  std::vector<double> sin_elevation(beams);
  for (std::size_t b = 0; b < beams; ++b) {
    if (pinhole) {
      const double low = std::tan(sensor.fov_down_deg * kDegree);
      const double high = std::tan(sensor.fov_up_deg * kDegree);
      cos_elevation[b] = 1.0;
      sin_elevation[b] =
          low + (static_cast<double>(b) + 0.5) / static_cast<double>(beams) * (high - low);
      continue;
    }
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
  const double half_width = pinhole ? std::tan(0.5 * sensor.horizontal_fov_deg * kDegree) : 0.0;
  for (std::size_t k = 0; k < steps; ++k) {
    // Column k: centred at ((k + 1/2) / K - 1/2) of the field of view, from +y (left) to -y.
    const double column = (static_cast<double>(k) + 0.5) / static_cast<double>(steps) - 0.5;
    const double azimuth =
        full_turn ? 2.0 * Rng::kPi * static_cast<double>(k) / static_cast<double>(steps)
                  : -column * sensor.horizontal_fov_deg * kDegree;
    const double cos_azimuth = pinhole ? 1.0 : std::cos(azimuth);
    const double sin_azimuth = pinhole ? -2.0 * column * half_width : std::sin(azimuth);
    for (std::size_t b = 0; b < beams; ++b) {
      // Unit direction in the sensor frame; the world ray has the rotated direction.
      Eigen::Vector3d direction(cos_elevation[b] * cos_azimuth, cos_elevation[b] * sin_azimuth,
                                sin_elevation[b]);
      if (pinhole) direction.normalize();
      ray.direction = rotation * direction;
      const double t = scene.cast(ray, sensor.max_range);
      if (t == kNoHit || t < sensor.min_range) continue;  // nothing, or blinded by a close hit
      double range = t;
      if (!measure(t, direction, pinhole, noise, rng, &range)) continue;
      out->push_back(range * direction);
    }
  }
}

}  // namespace internal
}  // namespace synthetic
}  // namespace PPCR_ABI_NAMESPACE
}  // namespace ppcr
