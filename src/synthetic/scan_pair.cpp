// scan_pair.cpp - option checks, the two sensor poses, outliers: make_scan_pair().
#include <cmath>
#include <cstddef>
#include <exception>
#include <sstream>
#include <string>
#include <utility>

#include "ppcr/synthetic.hpp"
#include "random.hpp"
#include "scanner.hpp"
#include "scene.hpp"

namespace ppcr {
inline namespace PPCR_ABI_NAMESPACE {
namespace synthetic {
namespace {

using internal::Rng;
using internal::Stream;

constexpr double kDegree = Rng::kPi / 180.0;
constexpr double kMaxRotationAxisTilt = 10.0 * kDegree;  // from the vertical
constexpr double kMaxTranslationElevation = 3.0 * kDegree;
constexpr double kStreetAzimuthSpread = 5.0 * kDegree;  // about the road's direction
constexpr double kMaxOutlierFraction = 0.95;
constexpr long long kMaxRays = 1LL << 22;  // beams * horizontal_steps (4194304)

/// Integers as integers (36864000, not 3.6864e+07); other values with 6 significant digits.
std::string number(double value) {
  std::ostringstream text;
  if (std::abs(value) < 1e15 && value == std::floor(value)) {
    text << static_cast<long long>(value);
  } else {
    text << value;
  }
  return text.str();
}

Status invalid(const std::string& name, double value, const std::string& requirement) {
  std::ostringstream message;
  message << name << " = " << number(value) << ": " << requirement;
  return Status(StatusCode::kInvalidArgument, message.str());
}

Status check_sensor(const SensorModel& s) {
  const std::string p = "ScanOptions.sensor.";
  if (s.beams < 1 || s.beams > 1024) return invalid(p + "beams", s.beams, "must be in [1, 1024]");
  if (s.horizontal_steps < 1 || s.horizontal_steps > 36000) {
    return invalid(p + "horizontal_steps", s.horizontal_steps, "must be in [1, 36000]");
  }
  if (static_cast<long long>(s.beams) * s.horizontal_steps > kMaxRays) {
    return invalid(p + "beams * horizontal_steps",
                   static_cast<double>(s.beams) * s.horizontal_steps,
                   "must be at most 4194304 rays per scan");
  }
  if (!(std::abs(s.fov_up_deg) <= 90.0)) {
    return invalid(p + "fov_up_deg", s.fov_up_deg, "must be in [-90, 90] degrees");
  }
  if (!(std::abs(s.fov_down_deg) <= 90.0)) {
    return invalid(p + "fov_down_deg", s.fov_down_deg, "must be in [-90, 90] degrees");
  }
  if (s.beams > 1 && !(s.fov_down_deg < s.fov_up_deg)) {
    return invalid(p + "fov_down_deg", s.fov_down_deg,
                   "must be below fov_up_deg = " + number(s.fov_up_deg));
  }
  if (s.beams == 1 && !(s.fov_down_deg <= s.fov_up_deg)) {
    return invalid(p + "fov_down_deg", s.fov_down_deg,
                   "must not exceed fov_up_deg = " + number(s.fov_up_deg));
  }
  if (!(s.min_range >= 0.0 && std::isfinite(s.min_range))) {
    return invalid(p + "min_range", s.min_range, "must be finite and >= 0 (metres)");
  }
  if (!(s.max_range > s.min_range && s.max_range <= 10000.0)) {
    return invalid(
        p + "max_range", s.max_range,
        "must be above min_range = " + number(s.min_range) + " and at most 10000 (metres)");
  }
  if (s.projection != Projection::kSpinning && s.projection != Projection::kPinhole) {
    return invalid(p + "projection", static_cast<int>(s.projection),
                   "must be Projection::kSpinning or Projection::kPinhole");
  }
  if (s.projection == Projection::kSpinning) {
    if (!(s.horizontal_fov_deg > 0.0 && s.horizontal_fov_deg <= 360.0)) {
      return invalid(p + "horizontal_fov_deg", s.horizontal_fov_deg,
                     "must be in (0, 360] degrees for a spinning sensor");
    }
    return Status::Ok();
  }
  if (!(s.horizontal_fov_deg > 0.0 && s.horizontal_fov_deg < 180.0)) {
    return invalid(p + "horizontal_fov_deg", s.horizontal_fov_deg,
                   "must be in (0, 180) degrees for a depth camera (Projection::kPinhole)");
  }
  if (!(std::abs(s.fov_up_deg) < 90.0)) {
    return invalid(p + "fov_up_deg", s.fov_up_deg,
                   "must be in (-90, 90) degrees for a depth camera (Projection::kPinhole)");
  }
  if (!(std::abs(s.fov_down_deg) < 90.0)) {
    return invalid(p + "fov_down_deg", s.fov_down_deg,
                   "must be in (-90, 90) degrees for a depth camera (Projection::kPinhole)");
  }
  return Status::Ok();
}

Status check_options(const ScanOptions& o) {
  if (o.scene != SceneKind::kRoom && o.scene != SceneKind::kStreet &&
      o.scene != SceneKind::kObjects) {
    return invalid("ScanOptions.scene", static_cast<int>(o.scene),
                   "must be SceneKind::kRoom, kStreet or kObjects");
  }
  Status status = check_sensor(o.sensor);
  if (!status.ok()) return status;
  if (!(o.noise_sigma >= 0.0 && std::isfinite(o.noise_sigma))) {
    return invalid("ScanOptions.noise_sigma", o.noise_sigma, "must be finite and >= 0 (metres)");
  }
  if (!(o.noise_per_metre >= 0.0 && o.noise_per_metre <= 1.0)) {
    return invalid("ScanOptions.noise_per_metre", o.noise_per_metre, "must be in [0, 1]");
  }
  if (!(o.depth_quantisation >= 0.0 && o.depth_quantisation <= 1000.0)) {
    return invalid("ScanOptions.depth_quantisation", o.depth_quantisation,
                   "must be in [0, 1000] (1/metres)");
  }
  if (!(o.outlier_fraction >= 0.0 && o.outlier_fraction <= kMaxOutlierFraction)) {
    return invalid("ScanOptions.outlier_fraction", o.outlier_fraction, "must be in [0, 0.95]");
  }
  if (!(o.rotation_deg >= 0.0 && o.rotation_deg <= 180.0)) {
    return invalid("ScanOptions.rotation_deg", o.rotation_deg, "must be in [0, 180] degrees");
  }
  const double max_translation = max_translation_m(o.scene);
  if (!(o.translation_m >= 0.0 && o.translation_m <= max_translation)) {
    std::ostringstream requirement;
    requirement << "must be in [0, " << max_translation << "] metres for the " << to_string(o.scene)
                << " scene";
    return invalid("ScanOptions.translation_m", o.translation_m, requirement.str());
  }
  return Status::Ok();
}

// Target: level, at a seeded yaw. Source: target_T_source = [R, t] with R of angle
// +-rotation_deg about an axis tilted up to 10 degrees from the vertical, and t the displacement
// between the positions (drawn in the scene frame, see ScanOptions::translation_m) expressed in
// the target frame. The positions are symmetric about the layout's sensor midpoint. All the
// numbers are drawn whatever the options, so that a seed always gives the same directions.
// A layout whose sensors look at a point (the objects): the target looks at it (x toward it, y
// horizontal, no roll) instead of being level, and the rotation's sign turns the source toward
// it: against the source's sideways displacement (its y in the target frame).
void make_poses(const internal::Scene& scene, const ScanOptions& options, ScanPair* pair) {
  Rng rng(options.seed, Stream::kPoses);
  const double yaw = rng.uniform(0.0, 2.0 * Rng::kPi);
  const double axis_tilt = rng.uniform(0.0, kMaxRotationAxisTilt);
  const double axis_azimuth = rng.uniform(0.0, 2.0 * Rng::kPi);
  const double rotation_sign = rng.bernoulli(0.5) ? 1.0 : -1.0;
  const double backwards = rng.bernoulli(0.5) ? Rng::kPi : 0.0;
  const double azimuth = scene.sensor_zone.along_x
                             ? backwards + rng.uniform(-kStreetAzimuthSpread, kStreetAzimuthSpread)
                             : rng.uniform(0.0, 2.0 * Rng::kPi);
  const double elevation = rng.uniform(-kMaxTranslationElevation, kMaxTranslationElevation);

  const Eigen::Vector3d axis(std::sin(axis_tilt) * std::cos(axis_azimuth),
                             std::sin(axis_tilt) * std::sin(axis_azimuth), std::cos(axis_tilt));
  const Eigen::Vector3d direction(std::cos(elevation) * std::cos(azimuth),
                                  std::cos(elevation) * std::sin(azimuth), std::sin(elevation));
  const Eigen::Vector3d displacement = options.translation_m * direction;  // scene frame

  Eigen::Isometry3d world_T_target = Eigen::Isometry3d::Identity();
  world_T_target.linear() = Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  world_T_target.translation() = scene.sensor_zone.midpoint - 0.5 * displacement;
  double sign = rotation_sign;
  if (scene.sensor_zone.looks_at) {
    const Eigen::Vector3d forward =
        (scene.sensor_zone.look_at - world_T_target.translation()).normalized();
    const Eigen::Vector3d left = Eigen::Vector3d::UnitZ().cross(forward).normalized();
    world_T_target.linear().col(0) = forward;
    world_T_target.linear().col(1) = left;
    world_T_target.linear().col(2) = forward.cross(left);
    const double sideways = world_T_target.linear().col(1).dot(displacement);
    if (sideways != 0.0) sign = sideways > 0.0 ? -1.0 : 1.0;
  }

  Eigen::Isometry3d target_T_source = Eigen::Isometry3d::Identity();
  target_T_source.linear() =
      Eigen::AngleAxisd(sign * options.rotation_deg * kDegree, axis).toRotationMatrix();
  target_T_source.translation() = world_T_target.linear().transpose() * displacement;

  pair->T_target_source = target_T_source;
  pair->T_world_target = world_T_target;
  pair->T_world_source = world_T_target * target_T_source;
}

// Appends round(n f / (1 - f)) points drawn uniformly in the part of the scene's bounds within
// max_range (per axis) of the sensor, expressed in the sensor frame.
void add_outliers(const internal::Scene& scene, const ScanOptions& options,
                  const Eigen::Isometry3d& world_T_sensor, Rng* rng, PointCloud* cloud) {
  const double fraction = options.outlier_fraction;
  if (fraction <= 0.0) return;
  const auto count = static_cast<std::size_t>(
      std::llround(static_cast<double>(cloud->size()) * fraction / (1.0 - fraction)));
  const Eigen::Vector3d position = world_T_sensor.translation();
  const Eigen::Vector3d reach = Eigen::Vector3d::Constant(options.sensor.max_range);
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

}  // namespace

SensorModel depth_camera(int columns, int rows, double max_range) {
  SensorModel camera;
  camera.projection = Projection::kPinhole;
  camera.horizontal_steps = columns;
  camera.beams = rows;
  camera.horizontal_fov_deg = 58.0;
  camera.fov_up_deg = 22.5;
  camera.fov_down_deg = -22.5;
  camera.min_range = 0.4;
  camera.max_range = max_range;
  return camera;
}

Status make_scan_pair(const ScanOptions& options, ScanPair* out) {
  if (out == nullptr) {
    return Status(StatusCode::kInvalidArgument, "make_scan_pair: out is null");
  }
  Status status = check_options(options);
  if (!status.ok()) return status;
  try {
    const internal::Scene scene = internal::make_scene(options.scene, options.seed);
    ScanPair pair;
    make_poses(scene, options, &pair);

    internal::RangeNoise noise;
    noise.sigma = options.noise_sigma;
    noise.per_metre = options.noise_per_metre;
    noise.quantisation = options.depth_quantisation;
    Rng source_noise(options.seed, Stream::kSourceNoise);
    internal::scan(scene, options.sensor, pair.T_world_source, noise, &source_noise, &pair.source);
    pair.source_returns = pair.source.size();
    Rng target_noise(options.seed, Stream::kTargetNoise);
    internal::scan(scene, options.sensor, pair.T_world_target, noise, &target_noise, &pair.target);
    pair.target_returns = pair.target.size();

    Rng source_outliers(options.seed, Stream::kSourceOutliers);
    add_outliers(scene, options, pair.T_world_source, &source_outliers, &pair.source);
    Rng target_outliers(options.seed, Stream::kTargetOutliers);
    add_outliers(scene, options, pair.T_world_target, &target_outliers, &pair.target);
    *out = std::move(pair);
  } catch (const std::exception& e) {  // std::bad_alloc: the clouds do not fit in memory
    return Status(StatusCode::kInvalidArgument,
                  std::string("make_scan_pair: the scans do not fit in memory (") + e.what() +
                      "); reduce ScanOptions.sensor.beams, horizontal_steps or outlier_fraction");
  }
  return Status::Ok();
}

}  // namespace synthetic
}  // namespace PPCR_ABI_NAMESPACE
}  // namespace ppcr
