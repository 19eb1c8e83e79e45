// scan_pair.cpp - option checks, the two sensor poses, outliers: make_scan_pair().
#include <cmath>
#include <cstddef>
#include <exception>
#include <sstream>
#include <string>
#include <utility>

#include "option_checks.hpp"
#include "outliers.hpp"
#include "ppcr/synthetic.hpp"
#include "random.hpp"
#include "scanner.hpp"
#include "scene.hpp"

namespace ppcr {
inline namespace PPCR_ABI_NAMESPACE {
namespace synthetic {
namespace {

using internal::invalid;
using internal::Rng;
using internal::Stream;

constexpr double kDegree = Rng::kPi / 180.0;
constexpr double kMaxRotationAxisTilt = 10.0 * kDegree;  // from the vertical
constexpr double kMaxTranslationElevation = 3.0 * kDegree;
constexpr double kStreetAzimuthSpread = 5.0 * kDegree;  // about the road's direction

Status check_options(const ScanOptions& o) {
  if (o.scene != SceneKind::kRoom && o.scene != SceneKind::kStreet &&
      o.scene != SceneKind::kObjects) {
    return invalid("ScanOptions.scene", static_cast<int>(o.scene),
                   "must be SceneKind::kRoom, kStreet or kObjects");
  }
  const Status status = internal::check_sensor_and_measurement(o, "ScanOptions.");
  if (!status.ok()) return status;
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

namespace {

// The noise or outliers stream of options.noise_draw (ScanOptions): the seed's own for draw 0.
Rng draw(const ScanOptions& options, Stream stream) {
  return options.noise_draw == 0 ? Rng(options.seed, stream)
                                 : Rng(options.seed, stream, options.noise_draw);
}

}  // namespace

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
    Rng source_noise = draw(options, Stream::kSourceNoise);
    internal::scan(scene, options.sensor, pair.T_world_source, noise, &source_noise, &pair.source);
    pair.source_returns = pair.source.size();
    Rng target_noise = draw(options, Stream::kTargetNoise);
    internal::scan(scene, options.sensor, pair.T_world_target, noise, &target_noise, &pair.target);
    pair.target_returns = pair.target.size();

    Rng source_outliers = draw(options, Stream::kSourceOutliers);
    internal::add_outliers(scene, options.outlier_fraction, options.sensor.max_range,
                           pair.T_world_source, &source_outliers, &pair.source);
    Rng target_outliers = draw(options, Stream::kTargetOutliers);
    internal::add_outliers(scene, options.outlier_fraction, options.sensor.max_range,
                           pair.T_world_target, &target_outliers, &pair.target);
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
