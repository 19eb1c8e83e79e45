// scene.hpp - a synthetic scene: the union of its analytic primitives, and where the sensors
// may stand (internal to ppcr_synthetic; tests include it through src/).
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cstdint>
#include <vector>

#include "bvh.hpp"
#include "ppcr/abi.hpp"
#include "ppcr/synthetic.hpp"
#include "primitives.hpp"

namespace ppcr {
inline namespace PPCR_ABI_NAMESPACE {
namespace synthetic {
namespace internal {

/// Free space kept for the two sensor positions by a layout.
struct SensorZone {
  Eigen::Vector3d midpoint = Eigen::Vector3d::Zero();  // halfway between the two positions
  double max_translation = 0.0;  // metres: the positions stay in free space up to this distance
  bool along_x = false;          // true: move along the scene's x axis (a road), else any azimuth
  /// true: the target sensor looks at look_at (x toward it, y horizontal), else it is level at a
  /// seeded yaw.
  bool looks_at = false;
  Eigen::Vector3d look_at = Eigen::Vector3d::Zero();
};

struct Scene {
  std::vector<Rectangle> rectangles;  // surfaces without volume (room shell, ground)
  std::vector<Box> boxes;             // solids
  std::vector<Sphere> spheres;
  std::vector<Cylinder> cylinders;
  Eigen::AlignedBox3d bounds;  // axis-aligned bounds of all primitives (set by finalize)
  SensorZone sensor_zone;
  Bvh bvh;  // over all primitives (built by finalize)

  /// Distance t in (0, t_max) along the ray to the first surface it meets, or kNoHit.
  /// Needs finalize() after the last change to the primitives.
  double cast(const Ray& ray, double t_max) const;

  /// Computes bounds and builds bvh from the primitives.
  void finalize();
};

/// The layout of a scene kind for a seed (see SceneKind). Deterministic.
Scene make_scene(SceneKind kind, std::uint64_t seed);
Scene make_room(std::uint64_t seed);
Scene make_street(std::uint64_t seed);
Scene make_objects(std::uint64_t seed);

/// Limits shared by the layouts and the option checks.
constexpr double kRoomMaxTranslation = 3.0;     // metres
constexpr double kStreetMaxTranslation = 30.0;  // metres
constexpr double kObjectsMaxTranslation = 0.6;  // metres

}  // namespace internal
}  // namespace synthetic
}  // namespace PPCR_ABI_NAMESPACE
}  // namespace ppcr
