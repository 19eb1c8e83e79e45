// objects.cpp - the tabletop layout: a few objects on a table, seen from 0.6 to 1.8 m.
//
// Scene frame: the table top is the rectangle z = 0, [-0.6, 0.6] x [-0.45, 0.45] metres (a
// surface: the legs are not modelled). Seven solids stand or lie on it within 0.4 m of its
// centre: boxes at random yaw (planes in many orientations), an upright can, a lying cylinder
// and two balls (curved surfaces), so the registration is constrained in all six degrees of
// freedom. The sensors stand on a seeded azimuth around the table, 0.9 to 1.3 m from its centre
// horizontally and 0.4 to 0.7 m above it, and look at its centre (SensorZone::looks_at).
#include <algorithm>
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

constexpr double kHalfX = 0.6;
constexpr double kHalfY = 0.45;
constexpr double kPlacementRadius = 0.4;  // object footprints stay within this of the centre
constexpr double kPi = Rng::kPi;

/// Places footprints (discs on the table) within kPlacementRadius of its centre, avoiding the
/// footprints already placed when it can.
class TablePlanner {
 public:
  explicit TablePlanner(Rng* rng) : rng_(rng) {}

  Eigen::Vector2d place(double radius) {
    const double reach = std::max(0.0, kPlacementRadius - radius);
    // The fallback is always valid: the centre.
    return planner_.place(radius, Eigen::Vector2d::Zero(), [&](Eigen::Vector2d* p) {
      *p = Eigen::Vector2d(rng_->uniform(-reach, reach), rng_->uniform(-reach, reach));
      return !(p->norm() > reach);
    });
  }

 private:
  Rng* rng_;
  FootprintPlanner planner_{0.02};
};

}  // namespace

Scene make_objects(std::uint64_t seed) {
  Rng rng(seed, Stream::kScene);
  Scene scene;
  const Eigen::Vector3d ex = Eigen::Vector3d::UnitX();
  const Eigen::Vector3d ey = Eigen::Vector3d::UnitY();
  const Eigen::Vector3d ez = Eigen::Vector3d::UnitZ();
  scene.rectangles = {{Eigen::Vector3d(0, 0, 0), ex, ey, kHalfX, kHalfY}};  // the table top

  TablePlanner planner(&rng);
  // Boxes standing on the table at random yaw: two small ones and a tall one (a cereal box).
  for (int i = 0; i < 3; ++i) {
    const Eigen::Vector3d half =
        i < 2 ? Eigen::Vector3d(rng.uniform(0.03, 0.1), rng.uniform(0.03, 0.08),
                                rng.uniform(0.02, 0.08))
              : Eigen::Vector3d(rng.uniform(0.08, 0.12), rng.uniform(0.03, 0.05),
                                rng.uniform(0.1, 0.15));
    const double yaw = rng.uniform(0.0, kPi);
    const Eigen::Vector2d p = planner.place(std::hypot(half.x(), half.y()));
    scene.boxes.push_back({Eigen::Vector3d(p.x(), p.y(), half.z()), yaw_matrix(yaw), half});
  }
  // An upright can.
  {
    const double radius = rng.uniform(0.03, 0.05);
    const double height = rng.uniform(0.08, 0.2);
    const Eigen::Vector2d p = planner.place(radius);
    scene.cylinders.push_back({Eigen::Vector3d(p.x(), p.y(), 0.0), ez, height, radius});
  }
  // A cylinder lying on the table (a bottle, a rolling pin).
  {
    const double radius = rng.uniform(0.025, 0.045);
    const double length = rng.uniform(0.15, 0.3);
    const double yaw = rng.uniform(0.0, kPi);
    const Eigen::Vector3d axis(std::cos(yaw), std::sin(yaw), 0.0);
    const Eigen::Vector2d p = planner.place(std::hypot(0.5 * length, radius));
    scene.cylinders.push_back(
        {Eigen::Vector3d(p.x(), p.y(), radius) - 0.5 * length * axis, axis, length, radius});
  }
  // Two balls on the table.
  for (int i = 0; i < 2; ++i) {
    const double radius = rng.uniform(0.03, 0.08);
    const Eigen::Vector2d p = planner.place(radius);
    scene.spheres.push_back({Eigen::Vector3d(p.x(), p.y(), radius), radius});
  }

  const double azimuth = rng.uniform(0.0, 2.0 * kPi);
  const double distance = rng.uniform(0.9, 1.3);
  const double height = rng.uniform(0.4, 0.7);
  scene.sensor_zone.midpoint =
      Eigen::Vector3d(distance * std::cos(azimuth), distance * std::sin(azimuth), height);
  scene.sensor_zone.max_translation = kObjectsMaxTranslation;
  scene.sensor_zone.along_x = false;
  scene.sensor_zone.looks_at = true;
  scene.sensor_zone.look_at = Eigen::Vector3d(0.0, 0.0, 0.05);
  scene.finalize();
  return scene;
}

}  // namespace internal
}  // namespace synthetic
}  // namespace PPCR_ABI_NAMESPACE
}  // namespace ppcr
