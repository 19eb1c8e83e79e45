// street.cpp - the outdoor layout: a straight street along the scene's x axis.
//
// Scene frame: the ground is z = 0; the road runs along x over [-80, 80] m. Across the road (y):
// the central lanes |y| < 4.5 are free for the sensors; cars are parked at |y| ~ 5.6-6.1, poles
// and trees stand on the sidewalks at |y| = 8.6, and building blocks (12 m deep, 6-20 m high,
// 8-20 m long, separated by 2-6 m gaps) have their facades at |y| = 10-10.8 with relief:
// vertical pilasters and/or horizontal ledges at every floor (3 m). Facades (normal y), block
// sides and car faces (normal ~x) and the ground (normal z) constrain all six degrees of freedom;
// poles, lamps, trunks and crowns add curved surfaces.
#include <algorithm>
#include <cmath>

#include "footprints.hpp"
#include "random.hpp"
#include "scene.hpp"

namespace ppcr {
inline namespace PPCR_ABI_NAMESPACE {
namespace synthetic {
namespace internal {
namespace {

constexpr double kHalfLength = 80.0;
constexpr double kFacade = 10.0;  // |y| of the frontmost facade line
constexpr double kMaxSetback = 0.8;
constexpr double kDepth = 12.0;
constexpr double kSidewalk = 8.6;
constexpr double kSensorHeight = 1.8;
constexpr double kPi = Rng::kPi;

void add_building_row(double side, Rng* rng, Scene* scene) {
  const Eigen::Matrix3d identity = Eigen::Matrix3d::Identity();
  double x = -kHalfLength + rng->uniform(0.0, 3.0);
  while (x < kHalfLength - 4.0) {
    const double length = std::min(rng->uniform(8.0, 20.0), kHalfLength - x);
    const double setback = rng->uniform(0.0, kMaxSetback);
    const double height = rng->uniform(6.0, 20.0);
    const int relief = static_cast<int>(rng->uniform(0.0, 3.0));  // 0, 1 or 2
    const double gap = rng->uniform(2.0, 6.0);
    const double front = kFacade + setback;  // |y| of this block's facade
    const double center_x = x + 0.5 * length;
    scene->boxes.push_back({Eigen::Vector3d(center_x, side * (front + 0.5 * kDepth), 0.5 * height),
                            identity, Eigen::Vector3d(0.5 * length, 0.5 * kDepth, 0.5 * height)});
    // Relief boxes are sunk 0.1 m into the block so that the union has no seam.
    if (relief != 1) {  // pilasters: 0.4 m wide, protruding 0.3 m, full height
      const int count = std::max(2, static_cast<int>(length / 3.5));
      for (int k = 0; k < count; ++k) {
        const double px = x + (k + 0.5) * length / count;
        scene->boxes.push_back({Eigen::Vector3d(px, side * (front - 0.1), 0.5 * height), identity,
                                Eigen::Vector3d(0.2, 0.2, 0.5 * height)});
      }
    }
    if (relief != 0) {  // ledges: 0.2 m thick, protruding 0.4 m, at every floor
      for (double z = 3.0; z < height - 0.5; z += 3.0) {
        scene->boxes.push_back({Eigen::Vector3d(center_x, side * (front - 0.15), z), identity,
                                Eigen::Vector3d(0.5 * length, 0.25, 0.1)});
      }
    }
    x += length + gap;
  }
}

// A car: body (4.3 x 1.8 x 0.9 m, 0.2 m above the ground) and a cabin (2.4 x 1.6 x 0.5 m) set
// back towards the rear, both at the car's yaw.
void add_parked_cars(double side, Rng* rng, Scene* scene) {
  double x = -kHalfLength + rng->uniform(2.0, 6.0);
  while (x < kHalfLength - 3.0) {
    const bool parked = rng->bernoulli(0.65);
    const double y = side * rng->uniform(5.6, 6.1);
    const double yaw = rng->uniform(-5.0, 5.0) * kPi / 180.0;
    if (parked) {
      const Eigen::Matrix3d axes = yaw_matrix(yaw);
      scene->boxes.push_back({Eigen::Vector3d(x, y, 0.65), axes, Eigen::Vector3d(2.15, 0.9, 0.45)});
      scene->boxes.push_back({Eigen::Vector3d(x, y, 1.35) + axes * Eigen::Vector3d(-0.25, 0, 0),
                              axes, Eigen::Vector3d(1.2, 0.8, 0.25)});
    }
    x += rng->uniform(5.2, 7.0);
  }
}

// Street furniture on the sidewalk: poles (with a lamp ball on top) and trees (a ball crown on a
// trunk), every 8-14 m.
void add_sidewalk(double side, Rng* rng, Scene* scene) {
  const Eigen::Vector3d up = Eigen::Vector3d::UnitZ();
  const double y = side * kSidewalk;
  double x = -kHalfLength + rng->uniform(1.0, 8.0);
  while (x < kHalfLength - 1.0) {
    const bool pole = rng->bernoulli(0.4);
    const double radius = pole ? 0.1 : rng->uniform(0.12, 0.22);
    const double height = pole ? rng->uniform(5.0, 8.0) : rng->uniform(2.0, 3.0);
    const double top_radius = pole ? 0.25 : rng->uniform(1.0, 1.8);
    scene->cylinders.push_back({Eigen::Vector3d(x, y, 0.0), up, height, radius});
    const double top_z = pole ? height : height + 0.7 * top_radius;
    scene->spheres.push_back({Eigen::Vector3d(x, y, top_z), top_radius});
    x += rng->uniform(8.0, 14.0);
  }
}

}  // namespace

Scene make_street(std::uint64_t seed) {
  Rng rng(seed, Stream::kScene);
  Scene scene;
  scene.rectangles.push_back({Eigen::Vector3d::Zero(), Eigen::Vector3d::UnitX(),
                              Eigen::Vector3d::UnitY(), kHalfLength,
                              kFacade + kMaxSetback + kDepth});  // the ground
  for (const double side : {-1.0, 1.0}) add_building_row(side, &rng, &scene);
  for (const double side : {-1.0, 1.0}) add_parked_cars(side, &rng, &scene);
  for (const double side : {-1.0, 1.0}) add_sidewalk(side, &rng, &scene);
  // The sensors ride on the road: |y| <= 1 + 15 sin(5 deg) = 2.3 m, far from the parked cars.
  scene.sensor_zone.midpoint =
      Eigen::Vector3d(rng.uniform(-3.0, 3.0), rng.uniform(-1.0, 1.0), kSensorHeight);
  scene.sensor_zone.max_translation = kStreetMaxTranslation;
  scene.sensor_zone.along_x = true;
  scene.finalize();
  return scene;
}

}  // namespace internal
}  // namespace synthetic
}  // namespace PPCR_ABI_NAMESPACE
}  // namespace ppcr
