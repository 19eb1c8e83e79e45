// sensor_path.cpp - arc-length paths, the speed profile and the sways of a sequence's sensor.
#include "sensor_path.hpp"

#include <algorithm>
#include <cmath>
#include <utility>

#include "random.hpp"

namespace ppcr {
inline namespace PPCR_ABI_NAMESPACE {
namespace synthetic {
namespace internal {
namespace {

constexpr double kPi = Rng::kPi;
constexpr double kDegree = kPi / 180.0;

// Room: an ellipse about the sensor zone's midpoint. Its farthest point from the room's axis is
// 1.4 + 0.3 sqrt(2) = 1.82 m, inside the 2.3 m disc the layout keeps free of furniture; its
// tightest bend (radius 1.03 m) turns a walker at 1.25 m/s by 70 degrees/s.
constexpr double kRoomSemiMajor = 1.4;
constexpr double kRoomSemiMinor = 1.2;
// Street: the road's usable length and the weave across it. |y| <= 1 + 1.5 = 2.5 m, clear of the
// parked cars (|y| >= 5.6 - 1 m).
constexpr double kStreetRoad = 140.0;
constexpr double kStreetWeave = 1.5;
constexpr double kStreetWeavePeriod = 40.0;

}  // namespace

ArcLengthPath::ArcLengthPath(Curve curve, double u_begin, double u_end, bool closed, int samples)
    : curve_(std::move(curve)), u_begin_(u_begin), u_end_(u_end), closed_(closed) {
  cumulative_.resize(static_cast<std::size_t>(samples) + 1, 0.0);
  const double step = (u_end_ - u_begin_) / samples;
  Eigen::Vector2d previous = curve_(u_begin_);
  for (int i = 1; i <= samples; ++i) {
    const Eigen::Vector2d next = curve_(u_begin_ + i * step);
    cumulative_[static_cast<std::size_t>(i)] =
        cumulative_[static_cast<std::size_t>(i) - 1] + (next - previous).norm();
    previous = next;
  }
}

double ArcLengthPath::parameter(double s) const {
  const double total = length();
  s = closed_ ? s - total * std::floor(s / total) : std::clamp(s, 0.0, total);
  const auto upper = std::upper_bound(cumulative_.begin(), cumulative_.end(), s);
  const std::size_t i = std::min<std::size_t>(
      static_cast<std::size_t>(std::max<std::ptrdiff_t>(upper - cumulative_.begin(), 1)) - 1,
      cumulative_.size() - 2);
  const double chord = cumulative_[i + 1] - cumulative_[i];
  const double fraction = chord > 0.0 ? (s - cumulative_[i]) / chord : 0.0;
  const double step = (u_end_ - u_begin_) / static_cast<double>(cumulative_.size() - 1);
  return u_begin_ + (static_cast<double>(i) + fraction) * step;
}

Eigen::Vector2d ArcLengthPath::point(double s) const { return curve_(parameter(s)); }

double ArcLengthPath::heading(double s) const {
  // Central difference in u: the curves are analytic, the step small against their curvature.
  const double u = parameter(s);
  const double h = 1e-6 * (u_end_ - u_begin_);
  const Eigen::Vector2d d = curve_(u + h) - curve_(u - h);
  return std::atan2(d.y(), d.x());
}

double Sway::at(double t) const {
  return amplitude * std::sin(2.0 * kPi * frequency_hz * t + phase);
}

double SensorPath::distance(double t) const {
  const double w = 2.0 * kPi / speed_period;
  return speed * (t - speed_swing / w * (std::cos(w * t + speed_phase) - std::cos(speed_phase)));
}

Eigen::Isometry3d SensorPath::pose(double t) const {
  const double s = distance(t);
  const Eigen::Vector2d xy = path.point(s);
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.translation() = Eigen::Vector3d(xy.x(), xy.y(), height + bob.at(t));
  T.linear() = (Eigen::AngleAxisd(path.heading(s) + yaw.at(t), Eigen::Vector3d::UnitZ()) *
                Eigen::AngleAxisd(pitch.at(t), Eigen::Vector3d::UnitY()) *
                Eigen::AngleAxisd(roll.at(t), Eigen::Vector3d::UnitX()))
                   .toRotationMatrix();
  return T;
}

SensorPath make_sensor_path(SceneKind kind, const Scene& scene, std::uint64_t seed, double speed) {
  Rng rng(seed, Stream::kTrajectory);
  // Every number is drawn whatever the scene, so that a seed always gives the same phases.
  const double orientation = rng.uniform(0.0, kPi);
  const double start = rng.uniform(0.0, 2.0 * kPi);
  const double direction = rng.bernoulli(0.5) ? 1.0 : -1.0;
  double phases[5];
  for (double& phase : phases) phase = rng.uniform(0.0, 2.0 * kPi);
  const Eigen::Vector3d mid = scene.sensor_zone.midpoint;

  const bool room = kind != SceneKind::kStreet;
  ArcLengthPath::Curve curve;
  if (room) {
    const Eigen::Matrix2d axes = Eigen::Rotation2Dd(orientation).toRotationMatrix();
    curve = [=](double u) {
      const double a = start + direction * u;
      return Eigen::Vector2d(mid.head<2>() + axes * Eigen::Vector2d(kRoomSemiMajor * std::cos(a),
                                                                    kRoomSemiMinor * std::sin(a)));
    };
  } else {
    curve = [=](double u) {
      return Eigen::Vector2d(
          mid.x() + direction * (u - 0.5 * kStreetRoad),
          mid.y() + kStreetWeave * std::sin(2.0 * kPi * u / kStreetWeavePeriod + start));
    };
  }
  SensorPath motion(ArcLengthPath(curve, 0.0, room ? 2.0 * kPi : kStreetRoad, room));
  motion.height = mid.z();
  motion.speed = speed;
  motion.speed_period = room ? 8.0 : 12.0;
  motion.speed_phase = phases[0];
  if (room) {  // handheld, walking
    motion.bob = {0.03, 1.8, phases[1]};
    motion.roll = {2.0 * kDegree, 0.35, phases[2]};
    motion.pitch = {2.0 * kDegree, 0.5, phases[3]};
    motion.yaw = {3.0 * kDegree, 0.25, phases[4]};
  } else {  // on a vehicle
    motion.bob = {0.01, 1.5, phases[1]};
    motion.roll = {0.5 * kDegree, 0.7, phases[2]};
    motion.pitch = {0.5 * kDegree, 1.1, phases[3]};
  }
  return motion;
}

}  // namespace internal
}  // namespace synthetic
}  // namespace PPCR_ABI_NAMESPACE
}  // namespace ppcr
