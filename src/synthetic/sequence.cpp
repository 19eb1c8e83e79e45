// sequence.cpp - option checks, the trajectory and the scans of a sequence: make_scan_sequence().
#include <cmath>
#include <exception>
#include <string>

#include "option_checks.hpp"
#include "outliers.hpp"
#include "ppcr/synthetic.hpp"
#include "random.hpp"
#include "scanner.hpp"
#include "scene.hpp"
#include "sensor_path.hpp"

namespace ppcr {
inline namespace PPCR_ABI_NAMESPACE {
namespace synthetic {
namespace {

using internal::invalid;
using internal::number;
using internal::Rng;
using internal::Stream;

constexpr std::size_t kMaxScans = 1000000;
constexpr double kMaxRate = 1000.0;
constexpr double kMaxSpeed = 50.0;

double speed_of(const SequenceOptions& o) {
  return o.speed_mps > 0.0 ? o.speed_mps : default_speed_mps(o.scene);
}

double time_of(const SequenceOptions& o, std::size_t index) {
  return static_cast<double>(index) / o.rate_hz;
}

Status check_options(const SequenceOptions& o) {
  if (o.scene != SceneKind::kRoom && o.scene != SceneKind::kStreet) {
    return Status(StatusCode::kInvalidArgument,
                  std::string("SequenceOptions.scene = ") + to_string(o.scene) +
                      ": must be SceneKind::kRoom or kStreet (sequences sweep a room or a street)");
  }
  const Status status = internal::check_sensor_and_measurement(o, "SequenceOptions.");
  if (!status.ok()) return status;
  if (o.scans < 2 || o.scans > kMaxScans) {
    return invalid("SequenceOptions.scans", static_cast<double>(o.scans),
                   "must be in [2, 1000000]");
  }
  if (!(o.rate_hz > 0.0 && o.rate_hz <= kMaxRate)) {
    return invalid("SequenceOptions.rate_hz", o.rate_hz, "must be in (0, 1000] (scans/s)");
  }
  if (!(o.speed_mps >= 0.0 && o.speed_mps <= kMaxSpeed)) {
    return invalid("SequenceOptions.speed_mps", o.speed_mps,
                   "must be in [0, 50] (m/s; 0 = the scene's default)");
  }
  return Status::Ok();
}

// An open path (the street) must hold the distance travelled by the last scan.
Status check_length(const SequenceOptions& o, const internal::SensorPath& motion) {
  const double needed = motion.distance(time_of(o, o.scans - 1));
  if (motion.path.closed() || needed <= motion.path.length()) return Status::Ok();
  return invalid("SequenceOptions.scans", static_cast<double>(o.scans),
                 "needs " + number(needed) + " m of path at speed_mps = " + number(speed_of(o)) +
                     " and rate_hz = " + number(o.rate_hz) + ", more than the " +
                     number(motion.path.length()) + " m the " + to_string(o.scene) +
                     " has: lower scans or speed_mps, or raise rate_hz");
}

Status trajectory(const SequenceOptions& o, const internal::Scene& scene,
                  std::vector<Eigen::Isometry3d>* poses) {
  const internal::SensorPath motion =
      internal::make_sensor_path(o.scene, scene, o.seed, speed_of(o));
  Status status = check_length(o, motion);
  if (!status.ok()) return status;
  poses->clear();
  poses->reserve(o.scans);
  for (std::size_t i = 0; i < o.scans; ++i) poses->push_back(motion.pose(time_of(o, i)));
  return Status::Ok();
}

}  // namespace

double default_speed_mps(SceneKind kind) { return kind == SceneKind::kStreet ? 6.0 : 1.0; }

Status make_sequence_trajectory(const SequenceOptions& options,
                                std::vector<Eigen::Isometry3d>* T_world_sensor) {
  if (T_world_sensor == nullptr) {
    return Status(StatusCode::kInvalidArgument, "make_sequence_trajectory: output is null");
  }
  Status status = check_options(options);
  if (!status.ok()) return status;
  return trajectory(options, internal::make_scene(options.scene, options.seed), T_world_sensor);
}

Status make_scan_sequence(const SequenceOptions& options, const ScanSink& sink) {
  Status status = check_options(options);
  if (!status.ok()) return status;
  if (!sink) return Status(StatusCode::kInvalidArgument, "make_scan_sequence: sink is empty");
  const internal::Scene scene = internal::make_scene(options.scene, options.seed);
  std::vector<Eigen::Isometry3d> poses;
  status = trajectory(options, scene, &poses);
  if (!status.ok()) return status;
  internal::RangeNoise noise;
  noise.sigma = options.noise_sigma;
  noise.per_metre = options.noise_per_metre;
  noise.quantisation = options.depth_quantisation;
  PointCloud scan;
  for (std::size_t i = 0; i < poses.size(); ++i) {
    try {
      scan.clear();
      Rng scan_noise(options.seed, Stream::kSequenceNoise, i);
      internal::scan(scene, options.sensor, poses[i], noise, &scan_noise, &scan);
      Rng scan_outliers(options.seed, Stream::kSequenceOutliers, i);
      internal::add_outliers(scene, options.outlier_fraction, options.sensor.max_range, poses[i],
                             &scan_outliers, &scan);
    } catch (const std::exception& e) {  // std::bad_alloc
      return Status(StatusCode::kInvalidArgument, std::string("make_scan_sequence: scan ") +
                                                      std::to_string(i) +
                                                      " does not fit in memory (" + e.what() + ")");
    }
    status = sink(i, poses[i], scan);
    if (!status.ok()) return status;
  }
  return Status::Ok();
}

}  // namespace synthetic
}  // namespace PPCR_ABI_NAMESPACE
}  // namespace ppcr
