// sensor_path.hpp - the path of a sequence's sensor through a scene, and its pose at any time
// (internal to ppcr_synthetic; see SequenceOptions for the motion of each scene).
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cstdint>
#include <functional>
#include <utility>
#include <vector>

#include "ppcr/abi.hpp"
#include "ppcr/synthetic.hpp"
#include "scene.hpp"

namespace ppcr {
inline namespace PPCR_ABI_NAMESPACE {
namespace synthetic {
namespace internal {

/// A plane curve c(u), u in [u_begin, u_end], re-parameterised by its arc length s, so that a
/// speed in metres per second moves the sensor by that distance along the curve. The arc length
/// is tabulated from the chords of `samples` equal steps in u (relative error below 1e-8 for the
/// smooth curves used here); points are evaluated on the curve itself.
class ArcLengthPath {
 public:
  using Curve = std::function<Eigen::Vector2d(double u)>;
  ArcLengthPath(Curve curve, double u_begin, double u_end, bool closed, int samples = 20000);

  double length() const { return cumulative_.back(); }
  bool closed() const { return closed_; }
  /// The point at arc length s (closed: s modulo the length; open: s clamped to [0, length]).
  Eigen::Vector2d point(double s) const;
  /// The direction of travel at arc length s: the angle of dc/ds from the x axis, radians.
  double heading(double s) const;

 private:
  double parameter(double s) const;  // u at arc length s

  Curve curve_;
  double u_begin_, u_end_;
  bool closed_;
  std::vector<double> cumulative_;  // arc length at the i-th of samples + 1 equally spaced u
};

/// A sine sway a sin(2 pi f t + phase): the bob, roll, pitch and yaw of a carried sensor.
struct Sway {
  double amplitude = 0.0;
  double frequency_hz = 0.0;
  double phase = 0.0;
  double at(double t) const;
};

/// The sensor's motion: along `path` at height `height`, with the speed
/// v(t) = speed (1 + swing sin(2 pi t / period + phase)), and the sways.
struct SensorPath {
  explicit SensorPath(ArcLengthPath p) : path(std::move(p)) {}

  ArcLengthPath path;
  double height = 0.0;
  double speed = 1.0;          // mean, m/s
  double speed_swing = 0.25;   // relative amplitude of the speed's sine, < 1
  double speed_period = 8.0;   // seconds
  double speed_phase = 0.0;    // radians
  Sway bob, roll, pitch, yaw;  // metres, radians

  /// The arc length travelled at time t >= 0: the integral of v from 0 to t, in closed form.
  double distance(double t) const;
  /// world_T_sensor at time t: at the path's point and heading, x forward, z up, then rotated by
  /// the yaw, pitch and roll sways (R = Rz(heading + yaw) Ry(pitch) Rx(roll)).
  Eigen::Isometry3d pose(double t) const;
};

/// The path of a sequence in the room (a closed ellipse about the sensor zone) or the street (a
/// weave along the road), drawn from the seed, at the mean speed `speed`.
SensorPath make_sensor_path(SceneKind kind, const Scene& scene, std::uint64_t seed, double speed);

}  // namespace internal
}  // namespace synthetic
}  // namespace PPCR_ABI_NAMESPACE
}  // namespace ppcr
