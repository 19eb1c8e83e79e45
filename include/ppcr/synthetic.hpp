// synthetic.hpp - ppcr_synthetic: procedural scenes scanned by a simulated spinning lidar, with
// an exact ground-truth transform between the two scans.
//
// A scene (an indoor room, an outdoor street or a tabletop of objects) is a union of analytic
// primitives: rectangles, oriented boxes, spheres and capped cylinders, laid out procedurally
// from a seed. It is scanned from two sensor poses by casting one ray per (beam, azimuth step) of
// a spinning lidar, or per pixel of a depth camera: a ray returns the first surface it meets
// within [min_range, max_range]; rays that meet nothing return nothing. So the two scans overlap
// partially, occlude differently, and have the range-dependent density and the ring (or pixel)
// pattern of a real sensor. Range noise is added along each ray: constant Gaussian, and/or
// Gaussian proportional to the range; depths can be quantised like a structured-light or
// time-of-flight camera's (steps growing with depth squared); uniform outliers can be added.
//
// Determinism: the output depends only on the options (never on time, threads or global
// state). Random numbers come from std::mt19937_64 (fully specified by the C++ standard) turned
// into doubles and normal deviates by our own code (53-bit uniforms, Box-Muller), not by the
// implementation-defined std:: distributions, so a seed gives the same clouds with any standard
// library (up to the last bits of the libm functions sin, cos, log, sqrt).
//
// Like the core, nothing here throws across the API or prints: functions return a Status whose
// message names the option at fault and its value.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <vector>

#include "ppcr/abi.hpp"
#include "ppcr/status.hpp"
#include "ppcr/types.hpp"

namespace ppcr {
inline namespace PPCR_ABI_NAMESPACE {
namespace synthetic {

enum class SceneKind {
  /// A closed 12 m x 9 m x 3 m room: floor, ceiling and four walls, with boxes (furniture),
  /// spheres (on the floor and hanging), two floor-to-ceiling columns, a barrel lying on the
  /// floor and a pipe under the ceiling. The middle of the room is kept free for the sensors.
  kRoom,
  /// A 160 m street along the scene's x axis: ground plane, building blocks on both sides with
  /// gaps between them and facade relief (pilasters, ledges), parked cars (two boxes each), poles
  /// with lamps, and trees (sphere crowns on cylinder trunks). The sensors move along the road.
  kStreet,
  /// A tabletop: a 1.2 m x 0.9 m table top (z = 0) with seven objects standing or lying on it
  /// within 0.4 m of its centre, 3 to 30 cm in size: three boxes (one tall) at random yaw, an
  /// upright can, a lying cylinder and two balls. Seen from 0.6 to 1.8 m, from above the table,
  /// by sensors looking at its centre (see ScanOptions::rotation_deg).
  kObjects,
};

/// "room", "street" or "objects".
const char* to_string(SceneKind kind);

/// Largest distance between the two sensor positions a scene accepts (ScanOptions::translation_m),
/// in metres: 3 for the room, 30 for the street (the sensors must stay in the free space), 0.6
/// for the objects.
double max_translation_m(SceneKind kind);

/// A spinning multi-beam lidar. Sensor frame: origin at the optical centre, x forward, y left,
/// z up (the spin axis). Beam b of B has elevation fov_down + b (fov_up - fov_down) / (B - 1)
/// (the mean of the two when B = 1); azimuth step k of K is at 360 k / K degrees.
/// The defaults resemble a 32-beam automotive lidar: 32 x 1024 = 32768 rays per scan.
///
/// With horizontal_fov_deg < 360 the spinning lidar sweeps only the azimuths in
/// [-fov/2, fov/2], from left to right (step k of K at (1/2 - (k + 1/2) / K) fov). With
/// Projection::kPinhole the sensor is a depth camera looking along x: an image of horizontal_steps
/// columns x beams rows whose pixel centres are evenly spaced on the image plane x = 1, spanning
/// [-tan(fov/2), tan(fov/2)] in y (horizontal_fov_deg < 180; column 0 on the left, +y) and
/// [tan(fov_down), tan(fov_up)] in z (both in (-90, 90); row 0 at the bottom); see
/// depth_camera() for a preset. Returns are in column-major order.
enum class Projection {
  kSpinning,  // equiangular beams and azimuth steps (a lidar)
  kPinhole,   // a regular pixel grid on an image plane (a depth camera)
};

struct SensorModel {
  int beams = 32;               // vertical channels, [1, 1024]
  int horizontal_steps = 1024;  // azimuth samples per revolution, [1, 36000] (0.35 deg step)
  double fov_up_deg = 15.0;     // elevation of the highest beam, degrees, in [-90, 90]
  double fov_down_deg = -25.0;  // elevation of the lowest beam, degrees, < fov_up_deg
  double min_range = 0.3;       // metres, >= 0: closer hits are dropped (not returned)
  double max_range = 80.0;      // metres, > min_range, <= 10000: farther hits are not returned
  Projection projection = Projection::kSpinning;
  /// Horizontal field of view, degrees: (0, 360] for kSpinning (360: a full revolution, the
  /// azimuths of the paragraph above), (0, 180) for kPinhole.
  double horizontal_fov_deg = 360.0;
};

/// A structured-light / time-of-flight depth camera like a Kinect: pinhole, 58 x 45 degrees,
/// columns x rows pixels, depths from 0.4 to max_range metres.
SensorModel depth_camera(int columns = 320, int rows = 240, double max_range = 4.5);

struct ScanOptions {
  SceneKind scene = SceneKind::kRoom;
  /// Seeds everything: the scene layout, the sensor poses, the noise and the outliers, each from
  /// its own stream (so changing noise_sigma does not move the scene or the poses). The layout
  /// depends only on (scene, seed), so sample_surface() with the same pair sees the same scene.
  std::uint64_t seed = 1;
  SensorModel sensor;  // the same sensor takes both scans
  /// Standard deviation of the zero-mean Gaussian noise added to each measured range, metres
  /// (the point moves along its ray), >= 0.
  double noise_sigma = 0.0;
  /// Range-proportional noise: with a = noise_per_metre > 0 the Gaussian range noise of a return
  /// at true range r has standard deviation sqrt(noise_sigma^2 + (a r)^2) (a r alone when
  /// noise_sigma = 0), dimensionless, >= 0.
  double noise_per_metre = 0.0;
  /// Depth quantisation q, 1/metres, >= 0 (0 = off): a depth camera measures disparity, which
  /// is quantised uniformly, so the depth d (the distance along the optical axis x with
  /// Projection::kPinhole, the range with kSpinning), after the range noise, becomes the nearest
  /// level 1 / (q k), k a positive integer (the point stays on its ray). Consecutive levels near
  /// d are q d^2 apart (1 / (q k (k + 1)) exactly): 3 mm at 1 m and 4.8 cm at 4 m for
  /// q = 0.003, about a Kinect's. Returns whose depth rounds to k = 0 (beyond 2 / q) are dropped.
  double depth_quantisation = 0.0;
  /// Fraction of each output cloud made of outliers, in [0, 0.95]. Outliers are ADDED to the
  /// returns (none is replaced): round(n f / (1 - f)) points for n returns, drawn uniformly in
  /// the intersection of the scene's bounding box with the cube of half side max_range around
  /// the sensor, and appended after the returns (see ScanPair::source_returns).
  double outlier_fraction = 0.0;
  /// Angle of the rotation between the two sensor poses, degrees, in [0, 180]. Its axis is drawn
  /// from the seed, tilted from the vertical by up to 10 degrees (so all three rotation
  /// components are non-zero in general); its sign is drawn too. For the objects scene the
  /// target sensor looks at the table's centre and the axis is tilted from its own z axis; the
  /// sign turns the source sensor toward the objects (against its sideways displacement).
  double rotation_deg = 15.0;
  /// Distance between the two sensor positions, metres, in [0, max_translation_m(scene)]. The
  /// direction is drawn from the seed: any horizontal azimuth in the room and the objects scene,
  /// along the road
  /// (within 5 degrees) in the street; elevation within +-3 degrees. The two positions are
  /// placed symmetrically about a seeded point of the scene's free space.
  double translation_m = 1.5;
  /// Which draw of the range noise and the outliers: 0, the seed's own; any other value an
  /// independent draw for the same scene, poses and rays (repeated measurements of one pair).
  std::uint64_t noise_draw = 0;
};

struct ScanPair {
  /// The scan from the source pose, in the source sensor's frame. Its first source_returns
  /// points are surface returns (in scan order: azimuth-major, then beam), the rest outliers.
  PointCloud source;
  /// The scan from the target pose, in the target sensor's frame (same layout).
  PointCloud target;
  /// Exact ground truth: maps source points (source sensor frame) into the target sensor frame,
  /// p_target = T_target_source * p_source. Its rotation angle is rotation_deg and its
  /// translation norm translation_m. Registering source onto target from identity must recover it.
  Eigen::Isometry3d T_target_source = Eigen::Isometry3d::Identity();
  /// Sensor poses in the scene (world) frame, z up; T_world_source = T_world_target *
  /// T_target_source.
  Eigen::Isometry3d T_world_source = Eigen::Isometry3d::Identity();
  Eigen::Isometry3d T_world_target = Eigen::Isometry3d::Identity();
  std::size_t source_returns = 0;  // surface returns at the front of source
  std::size_t target_returns = 0;  // surface returns at the front of target
};

/// Builds the scene of options.scene and options.seed and scans it from the two sensor poses.
/// Fails with kInvalidArgument (message naming the option, e.g. "ScanOptions.noise_sigma = -1
/// must be ...") for an option out of range, or when the clouds would not fit in memory.
Status make_scan_pair(const ScanOptions& options, ScanPair* out);

struct SurfaceSampleOptions {
  SceneKind scene = SceneKind::kRoom;
  std::uint64_t seed = 1;     // the scene layout is that of make_scan_pair with the same seed
  std::size_t count = 50000;  // points to return, [1, 100000000]
};

/// Samples options.count points uniformly (by area) on the surfaces of the scene, noise free, in
/// the scene (world) frame, without sensor: no occlusion or range effect. Points inside or on
/// another solid primitive (e.g. the floor under a box) are discarded and redrawn. Deterministic.
/// Fails with kInvalidArgument for a count out of range.
Status sample_surface(const SurfaceSampleOptions& options, PointCloud* out);

/// A sequence: one sensor swept along a smooth path through the room or the street, scanning at
/// a fixed rate, with the exact pose of every scan (issue #40). The path, the speed profile and
/// the sensor's sway are drawn from the seed:
///  - room: a closed ellipse (semi-axes 1.4 m and 1.2 m, about the room's free middle, driven
///    clockwise or anticlockwise), walked at a speed of speed_mps +-25 % (a sine of period 8 s)
///    by a handheld sensor 1.3 m above the floor that bobs +-3 cm (1.8 Hz), rolls and pitches
///    +-2 degrees and yaws +-3 degrees about the path's heading (slow sines);
///  - street: along the road in either direction, weaving across it (+-1.5 m, a sine of period
///    40 m), at speed_mps +-25 % (period 12 s), 1.8 m above the ground, rolling and pitching
///    +-0.5 degrees. The road gives at most 140 m of path: longer sequences are refused.
/// The sensor's x axis is the direction of travel (plus the yaw sway), z is up (plus the sway).
struct SequenceOptions {
  SceneKind scene = SceneKind::kRoom;  // kRoom or kStreet
  /// Seeds the layout (the same scene as make_scan_pair with this seed), the path, the noise and
  /// the outliers, each from its own stream; scan i's noise does not depend on the other scans.
  std::uint64_t seed = 1;
  SensorModel sensor;
  double noise_sigma = 0.0;         // as ScanOptions::noise_sigma
  double noise_per_metre = 0.0;     // as ScanOptions::noise_per_metre
  double depth_quantisation = 0.0;  // as ScanOptions::depth_quantisation
  double outlier_fraction = 0.0;    // as ScanOptions::outlier_fraction
  std::size_t scans = 200;          // [2, 1000000]
  double rate_hz = 10.0;            // scans per second, (0, 1000]: scan i is taken at i / rate_hz
  /// Mean speed along the path, m/s, (0, 50]; 0 = the scene's: 1 (room, walking), 6 (street).
  double speed_mps = 0.0;
};

/// The scene's default mean speed for a sequence, m/s (see SequenceOptions::speed_mps).
double default_speed_mps(SceneKind kind);

/// The sensor's pose in the scene (world) frame at each scan of the sequence, scan i at time
/// i / rate_hz. Fails with kInvalidArgument naming the option (e.g. "SequenceOptions.scans").
Status make_sequence_trajectory(const SequenceOptions& options,
                                std::vector<Eigen::Isometry3d>* T_world_sensor);

/// Receives scan `index` (in the sensor's frame; surface returns first, then outliers) and its
/// exact pose; a non-ok Status stops the sequence and is returned by make_scan_sequence.
using ScanSink = std::function<Status(std::size_t index, const Eigen::Isometry3d& T_world_sensor,
                                      const PointCloud& scan)>;

/// Builds the scene once and scans it from every pose of make_sequence_trajectory, in order,
/// handing each scan to sink (one scan in memory at a time). Deterministic.
Status make_scan_sequence(const SequenceOptions& options, const ScanSink& sink);

}  // namespace synthetic
}  // namespace PPCR_ABI_NAMESPACE
}  // namespace ppcr
