// primitives.hpp - the analytic surfaces of the synthetic scenes, and rays against them
// (internal to ppcr_synthetic; tests include it through src/).
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <limits>

#include "ppcr/abi.hpp"

namespace ppcr {
inline namespace PPCR_ABI_NAMESPACE {
namespace synthetic {
namespace internal {

constexpr double kNoHit = std::numeric_limits<double>::infinity();

/// The points origin + t direction, t >= 0. direction must be of unit length.
struct Ray {
  Eigen::Vector3d origin;
  Eigen::Vector3d direction;
};

/// A planar rectangle (a surface, seen from both sides): the points center + a u + b v with
/// |a| <= half_u and |b| <= half_v. u and v are orthonormal; the normal is u x v.
struct Rectangle {
  Eigen::Vector3d center;
  Eigen::Vector3d u;
  Eigen::Vector3d v;
  double half_u = 0.0;
  double half_v = 0.0;
};

/// A solid oriented box: the points center + axes * q with |q_i| <= half_extents_i.
/// The columns of axes are the box's orthonormal axes in the scene frame.
struct Box {
  Eigen::Vector3d center;
  Eigen::Matrix3d axes;
  Eigen::Vector3d half_extents;
};

/// A solid ball.
struct Sphere {
  Eigen::Vector3d center;
  double radius = 0.0;
};

/// A solid capped cylinder: the points base + s axis + w with 0 <= s <= height, w orthogonal to
/// axis and |w| <= radius. axis is of unit length.
struct Cylinder {
  Eigen::Vector3d base;
  Eigen::Vector3d axis;
  double height = 0.0;
  double radius = 0.0;
};

/// Each returns the smallest t with t_min < t < t_max at which the ray meets the primitive's
/// surface, or kNoHit. For a solid, a ray starting inside it meets the surface on its way out.
double intersect(const Ray& ray, const Rectangle& rectangle, double t_min, double t_max);
double intersect(const Ray& ray, const Box& box, double t_min, double t_max);
double intersect(const Ray& ray, const Sphere& sphere, double t_min, double t_max);
double intersect(const Ray& ray, const Cylinder& cylinder, double t_min, double t_max);

/// Signed distance from p to the solid's surface: negative inside, exact (Euclidean).
double signed_distance(const Eigen::Vector3d& p, const Box& box);
double signed_distance(const Eigen::Vector3d& p, const Sphere& sphere);
double signed_distance(const Eigen::Vector3d& p, const Cylinder& cylinder);

/// Axis-aligned bounding boxes.
Eigen::AlignedBox3d bounding_box(const Rectangle& rectangle);
Eigen::AlignedBox3d bounding_box(const Box& box);
Eigen::AlignedBox3d bounding_box(const Sphere& sphere);
Eigen::AlignedBox3d bounding_box(const Cylinder& cylinder);

/// Surface areas (both faces of a rectangle count once).
double area(const Rectangle& rectangle);
double area(const Box& box);
double area(const Sphere& sphere);
double area(const Cylinder& cylinder);

}  // namespace internal
}  // namespace synthetic
}  // namespace PPCR_ABI_NAMESPACE
}  // namespace ppcr
