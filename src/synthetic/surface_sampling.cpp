// surface_sampling.cpp - points drawn uniformly on a scene's surfaces: sample_surface().
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <exception>
#include <string>
#include <vector>

#include "ppcr/synthetic.hpp"
#include "random.hpp"
#include "scene.hpp"

namespace ppcr {
inline namespace PPCR_ABI_NAMESPACE {
namespace synthetic {
namespace {

using internal::Box;
using internal::Cylinder;
using internal::Rectangle;
using internal::Rng;
using internal::Scene;
using internal::Sphere;

constexpr std::size_t kMaxCount = 100000000;
/// Points closer than this to another solid (or inside it) are redrawn.
constexpr double kContactTolerance = 1e-9;

enum class Kind { kRectangle, kBox, kSphere, kCylinder };

struct Surface {
  Kind kind;
  std::size_t index;  // into the scene's vector of that kind
};

Eigen::Vector3d on_rectangle(const Rectangle& r, Rng* rng) {
  return r.center + rng->uniform(-r.half_u, r.half_u) * r.u +
         rng->uniform(-r.half_v, r.half_v) * r.v;
}

// A face is chosen by area (the two faces normal to axis i have area 4 h_j h_k each), then a
// point uniformly on it.
Eigen::Vector3d on_box(const Box& box, Rng* rng) {
  const Eigen::Vector3d& h = box.half_extents;
  const Eigen::Vector3d face_area(h.y() * h.z(), h.z() * h.x(), h.x() * h.y());
  double pick = rng->uniform(0.0, face_area.sum());
  int axis = 0;
  while (axis < 2 && pick >= face_area[axis]) pick -= face_area[axis++];
  Eigen::Vector3d q;
  for (int i = 0; i < 3; ++i) q[i] = rng->uniform(-h[i], h[i]);
  q[axis] = rng->bernoulli(0.5) ? h[axis] : -h[axis];
  return box.center + box.axes * q;
}

Eigen::Vector3d on_sphere(const Sphere& sphere, Rng* rng) {
  return sphere.center + sphere.radius * rng->unit_vector();
}

// Side (area 2 pi r h) or caps (pi r^2 each) by area; on the side, the axial coordinate and the
// angle are uniform; on a cap, the radius is r sqrt(u) (uniform by area).
Eigen::Vector3d on_cylinder(const Cylinder& c, Rng* rng) {
  const Eigen::Vector3d& a = c.axis;
  const Eigen::Vector3d helper =
      std::abs(a.x()) < 0.9 ? Eigen::Vector3d::UnitX() : Eigen::Vector3d::UnitY();
  const Eigen::Vector3d e1 = a.cross(helper).normalized();
  const Eigen::Vector3d e2 = a.cross(e1);
  const double side_area = c.height;  // 2 pi r h, over 2 pi r
  const double caps_area = c.radius;  // 2 pi r^2, over 2 pi r
  const double angle = rng->uniform(0.0, 2.0 * Rng::kPi);
  const Eigen::Vector3d radial = std::cos(angle) * e1 + std::sin(angle) * e2;
  if (rng->uniform(0.0, side_area + caps_area) < side_area) {
    return c.base + rng->uniform(0.0, c.height) * a + c.radius * radial;
  }
  const double s = rng->bernoulli(0.5) ? c.height : 0.0;
  return c.base + s * a + c.radius * std::sqrt(rng->uniform()) * radial;
}

/// True when p is inside or on a solid other than the one it was drawn on.
bool touches_other_solid(const Scene& scene, const Eigen::Vector3d& p, const Surface& own) {
  for (std::size_t i = 0; i < scene.boxes.size(); ++i) {
    if (own.kind == Kind::kBox && own.index == i) continue;
    if (internal::signed_distance(p, scene.boxes[i]) < kContactTolerance) return true;
  }
  for (std::size_t i = 0; i < scene.spheres.size(); ++i) {
    if (own.kind == Kind::kSphere && own.index == i) continue;
    if (internal::signed_distance(p, scene.spheres[i]) < kContactTolerance) return true;
  }
  for (std::size_t i = 0; i < scene.cylinders.size(); ++i) {
    if (own.kind == Kind::kCylinder && own.index == i) continue;
    if (internal::signed_distance(p, scene.cylinders[i]) < kContactTolerance) return true;
  }
  return false;
}

}  // namespace

Status sample_surface(const SurfaceSampleOptions& options, PointCloud* out) {
  if (out == nullptr) return Status(StatusCode::kInvalidArgument, "sample_surface: out is null");
  if (options.scene != SceneKind::kRoom && options.scene != SceneKind::kStreet &&
      options.scene != SceneKind::kObjects) {
    return Status(
        StatusCode::kInvalidArgument,
        "SurfaceSampleOptions.scene = " + std::to_string(static_cast<int>(options.scene)) +
            ": must be SceneKind::kRoom, kStreet or kObjects");
  }
  if (options.count < 1 || options.count > kMaxCount) {
    return Status(StatusCode::kInvalidArgument,
                  "SurfaceSampleOptions.count = " + std::to_string(options.count) +
                      ": must be in [1, 100000000]");
  }
  try {
    const Scene scene = internal::make_scene(options.scene, options.seed);
    std::vector<Surface> surfaces;
    std::vector<double> cumulative_area;  // running sum, for picking a surface by area
    double total = 0.0;
    auto add = [&](Kind kind, std::size_t index, double surface_area) {
      surfaces.push_back({kind, index});
      total += surface_area;
      cumulative_area.push_back(total);
    };
    for (std::size_t i = 0; i < scene.rectangles.size(); ++i) {
      add(Kind::kRectangle, i, internal::area(scene.rectangles[i]));
    }
    for (std::size_t i = 0; i < scene.boxes.size(); ++i) {
      add(Kind::kBox, i, internal::area(scene.boxes[i]));
    }
    for (std::size_t i = 0; i < scene.spheres.size(); ++i) {
      add(Kind::kSphere, i, internal::area(scene.spheres[i]));
    }
    for (std::size_t i = 0; i < scene.cylinders.size(); ++i) {
      add(Kind::kCylinder, i, internal::area(scene.cylinders[i]));
    }

    Rng rng(options.seed, internal::Stream::kSurfaceSamples);
    PointCloud points;
    points.reserve(options.count);
    // Hidden parts are a small fraction of the area; the cap only guards against a broken layout.
    const std::size_t max_draws = 100 * options.count + 1000;
    for (std::size_t draw = 0; draw < max_draws && points.size() < options.count; ++draw) {
      const double pick = rng.uniform(0.0, total);
      const auto found = std::upper_bound(cumulative_area.begin(), cumulative_area.end(), pick);
      const Surface& surface = surfaces[std::min<std::size_t>(
          static_cast<std::size_t>(found - cumulative_area.begin()), surfaces.size() - 1)];
      Eigen::Vector3d p;
      switch (surface.kind) {
        case Kind::kRectangle:
          p = on_rectangle(scene.rectangles[surface.index], &rng);
          break;
        case Kind::kBox:
          p = on_box(scene.boxes[surface.index], &rng);
          break;
        case Kind::kSphere:
          p = on_sphere(scene.spheres[surface.index], &rng);
          break;
        case Kind::kCylinder:
          p = on_cylinder(scene.cylinders[surface.index], &rng);
          break;
      }
      if (!touches_other_solid(scene, p, surface)) points.push_back(p);
    }
    if (points.size() < options.count) {
      return Status(StatusCode::kNumericalFailure,
                    "sample_surface: too many samples fell inside solids (" +
                        std::to_string(points.size()) + " of " + std::to_string(options.count) +
                        " drawn)");
    }
    *out = std::move(points);
  } catch (const std::exception& e) {  // std::bad_alloc
    return Status(StatusCode::kInvalidArgument,
                  std::string("SurfaceSampleOptions.count = ") + std::to_string(options.count) +
                      ": the samples do not fit in memory (" + e.what() + ")");
  }
  return Status::Ok();
}

}  // namespace synthetic
}  // namespace PPCR_ABI_NAMESPACE
}  // namespace ppcr
