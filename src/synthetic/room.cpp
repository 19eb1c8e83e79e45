// room.cpp - the indoor layout: a closed room with furniture-like solids.
//
// Scene frame: the floor is z = 0, the room spans [-6, 6] x [-4.5, 4.5] x [0, 3] metres. Planes
// in three orientations (floor/ceiling, two pairs of walls) plus boxes at random yaw and curved
// solids constrain all six degrees of freedom of a registration. A disc of radius kClearRadius
// about the room's vertical axis is kept free of furniture for the sensors.
#include <cmath>
#include <vector>

#include "footprints.hpp"
#include "random.hpp"
#include "scene.hpp"

namespace ppcr {
inline namespace PPCR_ABI_NAMESPACE {
namespace synthetic {
namespace internal {
namespace {

constexpr double kHalfX = 6.0;
constexpr double kHalfY = 4.5;
constexpr double kHeight = 3.0;
constexpr double kSensorHeight = 1.3;
constexpr double kMidpointJitter = 0.3;  // the sensors' midpoint is within +-0.3 m of the axis
// Sensors are at most kMidpointJitter * sqrt(2) + kRoomMaxTranslation / 2 = 1.92 m from the axis.
constexpr double kClearRadius = 2.3;
constexpr double kPi = Rng::kPi;

/// Places footprints (discs on the floor) inside the room, outside the clear disc, avoiding the
/// footprints already placed when it can.
class FloorPlanner {
 public:
  explicit FloorPlanner(Rng* rng) : rng_(rng) {}

  Eigen::Vector2d place(double radius) {
    // The fallback is always valid: a corner of the room is far from the clear disc.
    return planner_.place(radius, Eigen::Vector2d(kHalfX - radius, kHalfY - radius),
                          [&](Eigen::Vector2d* p) {
                            *p = Eigen::Vector2d(rng_->uniform(-kHalfX + radius, kHalfX - radius),
                                                 rng_->uniform(-kHalfY + radius, kHalfY - radius));
                            return !(p->norm() < kClearRadius + radius);
                          });
  }

 private:
  Rng* rng_;
  FootprintPlanner planner_{0.1};
};

}  // namespace

Scene make_room(std::uint64_t seed) {
  Rng rng(seed, Stream::kScene);
  Scene scene;
  const Eigen::Vector3d ex = Eigen::Vector3d::UnitX();
  const Eigen::Vector3d ey = Eigen::Vector3d::UnitY();
  const Eigen::Vector3d ez = Eigen::Vector3d::UnitZ();
  const double half_h = 0.5 * kHeight;
  scene.rectangles = {
      {Eigen::Vector3d(0, 0, 0), ex, ey, kHalfX, kHalfY},             // floor
      {Eigen::Vector3d(0, 0, kHeight), ex, ey, kHalfX, kHalfY},       // ceiling
      {Eigen::Vector3d(-kHalfX, 0, half_h), ey, ez, kHalfY, half_h},  // walls x = -+6
      {Eigen::Vector3d(kHalfX, 0, half_h), ey, ez, kHalfY, half_h},
      {Eigen::Vector3d(0, -kHalfY, half_h), ex, ez, kHalfX, half_h},  // walls y = -+4.5
      {Eigen::Vector3d(0, kHalfY, half_h), ex, ez, kHalfX, half_h},
  };

  FloorPlanner planner(&rng);
  // Furniture: boxes standing on the floor at random yaw.
  for (int i = 0; i < 7; ++i) {
    const Eigen::Vector3d half(rng.uniform(0.3, 1.0), rng.uniform(0.25, 0.6),
                               rng.uniform(0.2, 0.9));
    const double yaw = rng.uniform(0.0, kPi);
    const Eigen::Vector2d p = planner.place(std::hypot(half.x(), half.y()));
    scene.boxes.push_back({Eigen::Vector3d(p.x(), p.y(), half.z()), yaw_matrix(yaw), half});
  }
  // Balls: every other one on the floor, the others hanging below the ceiling.
  for (int i = 0; i < 4; ++i) {
    const double radius = rng.uniform(0.2, 0.5);
    const double hanging_z = rng.uniform(1.6, kHeight - 0.1 - radius);
    const Eigen::Vector2d p = planner.place(radius);
    const double z = (i % 2 == 0) ? radius : hanging_z;
    scene.spheres.push_back({Eigen::Vector3d(p.x(), p.y(), z), radius});
  }
  // Two floor-to-ceiling columns.
  for (int i = 0; i < 2; ++i) {
    const double radius = rng.uniform(0.15, 0.3);
    const Eigen::Vector2d p = planner.place(radius);
    scene.cylinders.push_back({Eigen::Vector3d(p.x(), p.y(), 0.0), ez, kHeight, radius});
  }
  // A barrel lying on the floor (a horizontal cylinder).
  {
    const double radius = rng.uniform(0.25, 0.4);
    const double length = rng.uniform(0.8, 1.4);
    const double yaw = rng.uniform(0.0, kPi);
    const Eigen::Vector3d axis(std::cos(yaw), std::sin(yaw), 0.0);
    const Eigen::Vector2d p = planner.place(std::hypot(0.5 * length, radius));
    scene.cylinders.push_back(
        {Eigen::Vector3d(p.x(), p.y(), radius) - 0.5 * length * axis, axis, length, radius});
  }
  // A pipe under the ceiling from wall to wall, along x or y.
  {
    const bool along_x = rng.bernoulli(0.5);
    const double offset = rng.uniform(-kHalfY + 0.5, kHalfY - 0.5);
    const double z = rng.uniform(2.45, 2.75);
    if (along_x) {
      scene.cylinders.push_back({Eigen::Vector3d(-kHalfX, offset, z), ex, 2.0 * kHalfX, 0.08});
    } else {
      scene.cylinders.push_back({Eigen::Vector3d(offset, -kHalfY, z), ey, 2.0 * kHalfY, 0.08});
    }
  }

  scene.sensor_zone.midpoint =
      Eigen::Vector3d(rng.uniform(-kMidpointJitter, kMidpointJitter),
                      rng.uniform(-kMidpointJitter, kMidpointJitter), kSensorHeight);
  scene.sensor_zone.max_translation = kRoomMaxTranslation;
  scene.sensor_zone.along_x = false;
  scene.finalize();
  return scene;
}

}  // namespace internal
}  // namespace synthetic
}  // namespace PPCR_ABI_NAMESPACE
}  // namespace ppcr
