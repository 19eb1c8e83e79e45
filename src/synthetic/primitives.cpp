// primitives.cpp - ray intersection, signed distance and area of the analytic primitives.
#include "primitives.hpp"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <utility>

namespace ppcr {
inline namespace PPCR_ABI_NAMESPACE {
namespace synthetic {
namespace internal {
namespace {

constexpr double kPi = 3.14159265358979323846;

/// Hits this close (metres) outside a rectangle's or a cylinder cap's border still count, so that
/// rays through the shared edge of two adjacent surfaces (the corner of a room) cannot slip
/// through a crack opened by rounding.
constexpr double kEdgeTolerance = 1e-10;

/// The smaller of the two roots t0 <= t1 inside (t_min, t_max), else the larger, else kNoHit.
double first_root_in_range(double t0, double t1, double t_min, double t_max) {
  if (t0 > t1) std::swap(t0, t1);
  if (t0 > t_min && t0 < t_max) return t0;
  if (t1 > t_min && t1 < t_max) return t1;
  return kNoHit;
}

}  // namespace

// Plane of the rectangle: n . (x - center) = 0 with n = u x v. On the ray x = o + t d this is
// linear in t: t = n . (center - o) / (n . d) (no hit when the ray is parallel, n . d = 0). The
// point must then lie within the rectangle's extent along u and v.
double intersect(const Ray& ray, const Rectangle& rectangle, double t_min, double t_max) {
  const Eigen::Vector3d normal = rectangle.u.cross(rectangle.v);
  const double denominator = normal.dot(ray.direction);
  if (denominator == 0.0) return kNoHit;
  const double t = normal.dot(rectangle.center - ray.origin) / denominator;
  if (!(t > t_min && t < t_max)) return kNoHit;
  const Eigen::Vector3d offset = ray.origin + t * ray.direction - rectangle.center;
  if (std::abs(rectangle.u.dot(offset)) > rectangle.half_u + kEdgeTolerance) return kNoHit;
  if (std::abs(rectangle.v.dot(offset)) > rectangle.half_v + kEdgeTolerance) return kNoHit;
  return t;
}

// Slab method in the box's own frame (o' = A^T (o - c), d' = A^T d): along axis i the ray is
// between the two face planes q_i = -h_i and q_i = +h_i for t between (-h_i - o'_i) / d'_i and
// (h_i - o'_i) / d'_i. The ray is inside the box on the intersection [t_enter, t_exit] of these
// three intervals; it enters the surface at t_enter and leaves it at t_exit. A ray parallel to
// a pair of faces (d'_i = 0) is inside that slab for all t or for none.
double intersect(const Ray& ray, const Box& box, double t_min, double t_max) {
  const Eigen::Vector3d origin = box.axes.transpose() * (ray.origin - box.center);
  const Eigen::Vector3d direction = box.axes.transpose() * ray.direction;
  double t_enter = -kNoHit;
  double t_exit = kNoHit;
  for (int i = 0; i < 3; ++i) {
    const double h = box.half_extents[i];
    if (direction[i] == 0.0) {
      if (std::abs(origin[i]) > h) return kNoHit;
      continue;
    }
    double t_near = (-h - origin[i]) / direction[i];
    double t_far = (h - origin[i]) / direction[i];
    if (t_near > t_far) std::swap(t_near, t_far);
    t_enter = std::max(t_enter, t_near);
    t_exit = std::min(t_exit, t_far);
  }
  if (t_enter > t_exit) return kNoHit;
  if (t_enter > t_min) return t_enter < t_max ? t_enter : kNoHit;
  return (t_exit > t_min && t_exit < t_max) ? t_exit : kNoHit;  // the origin is inside
}

// |o + t d - c|^2 = r^2 with |d| = 1 and f = o - c is t^2 + 2 b t + c' = 0, b = f . d,
// c' = f . f - r^2, with roots t = -b -+ sqrt(b^2 - c'). The discriminant is evaluated as
// b^2 - c' = r^2 - |f - b d|^2 (f - b d is the vector from the centre to the point of the ray
// closest to it), which does not cancel catastrophically when the sphere is small and far away.
// The roots are q = -(b + sign(b) sqrt(disc)) and c' / q (their product is c'), which avoids
// subtracting nearly equal numbers (Numerical Recipes, section 5.6).
double intersect(const Ray& ray, const Sphere& sphere, double t_min, double t_max) {
  const Eigen::Vector3d f = ray.origin - sphere.center;
  const double b = f.dot(ray.direction);
  const Eigen::Vector3d closest = f - b * ray.direction;
  const double discriminant = sphere.radius * sphere.radius - closest.squaredNorm();
  if (discriminant < 0.0) return kNoHit;
  const double q = -(b + std::copysign(std::sqrt(discriminant), b));
  if (q == 0.0) return kNoHit;  // b = 0 and tangent: the double root is t = 0
  const double c = f.squaredNorm() - sphere.radius * sphere.radius;
  return first_root_in_range(q, c / q, t_min, t_max);
}

// Lateral surface: with w = o - base and the components of w and d orthogonal to the axis a,
// w_p = w - (w . a) a and d_p = d - (d . a) a, the ray is at distance r from the axis where
// |w_p + t d_p|^2 = r^2, i.e. A t^2 + 2 B t + C = 0 with A = d_p . d_p, B = d_p . w_p,
// C = w_p . w_p - r^2 (no lateral hit when A = 0: the ray is parallel to the axis). As for the
// sphere, B^2 - A C = A (r^2 - |w_p - (B / A) d_p|^2), the roots are q / A and C / q with
// q = -(B + sign(B) sqrt(B^2 - A C)), and a root counts when its axial coordinate
// s = w . a + t (d . a) is within [0, height]. Caps: the planes s = 0 and s = height, at
// t = (s - w . a) / (d . a), hit when the point is within r of the axis.
double intersect(const Ray& ray, const Cylinder& cylinder, double t_min, double t_max) {
  const Eigen::Vector3d& axis = cylinder.axis;
  const Eigen::Vector3d w = ray.origin - cylinder.base;
  const double w_axial = w.dot(axis);
  const double d_axial = ray.direction.dot(axis);
  const Eigen::Vector3d w_perp = w - w_axial * axis;
  const Eigen::Vector3d d_perp = ray.direction - d_axial * axis;
  const double r2 = cylinder.radius * cylinder.radius;
  double best = kNoHit;
  auto consider_lateral = [&](double t) {
    if (!(t > t_min && t < t_max && t < best)) return;
    const double s = w_axial + t * d_axial;
    if (s >= -kEdgeTolerance && s <= cylinder.height + kEdgeTolerance) best = t;
  };
  const double a = d_perp.squaredNorm();
  if (a > 0.0) {
    const double b = d_perp.dot(w_perp);
    const double discriminant = r2 - (w_perp - (b / a) * d_perp).squaredNorm();
    if (discriminant >= 0.0) {
      const double q = -(b + std::copysign(std::sqrt(a * discriminant), b));
      consider_lateral(q / a);
      if (q != 0.0) consider_lateral((w_perp.squaredNorm() - r2) / q);
    }
  }
  if (d_axial != 0.0) {
    const double r_tolerant = cylinder.radius + kEdgeTolerance;
    for (const double s : {0.0, cylinder.height}) {
      const double t = (s - w_axial) / d_axial;
      if (!(t > t_min && t < t_max && t < best)) continue;
      if ((w_perp + t * d_perp).squaredNorm() <= r_tolerant * r_tolerant) best = t;
    }
  }
  return best;
}

// Exact box distance: with q = |A^T (p - c)| - h (per axis), outside points are at |max(q, 0)|,
// inside points at max_i q_i (negative).
double signed_distance(const Eigen::Vector3d& p, const Box& box) {
  const Eigen::Vector3d q = (box.axes.transpose() * (p - box.center)).cwiseAbs() - box.half_extents;
  return q.cwiseMax(0.0).norm() + std::min(q.maxCoeff(), 0.0);
}

double signed_distance(const Eigen::Vector3d& p, const Sphere& sphere) {
  return (p - sphere.center).norm() - sphere.radius;
}

// In the cylinder's (radial, axial) half plane the solid is the rectangle [0, r] x [0, height]:
// the same formula as the box, in two dimensions, about the rectangle's centre.
double signed_distance(const Eigen::Vector3d& p, const Cylinder& cylinder) {
  const Eigen::Vector3d w = p - cylinder.base;
  const double s = w.dot(cylinder.axis);
  const double radial = (w - s * cylinder.axis).norm();
  const Eigen::Vector2d q(radial - cylinder.radius,
                          std::abs(s - 0.5 * cylinder.height) - 0.5 * cylinder.height);
  return q.cwiseMax(0.0).norm() + std::min(q.maxCoeff(), 0.0);
}

Eigen::AlignedBox3d bounding_box(const Rectangle& r) {
  // Half extent along axis i: half_u |u_i| + half_v |v_i|.
  const Eigen::Vector3d reach = r.half_u * r.u.cwiseAbs() + r.half_v * r.v.cwiseAbs();
  return Eigen::AlignedBox3d(r.center - reach, r.center + reach);
}

Eigen::AlignedBox3d bounding_box(const Box& box) {
  const Eigen::Vector3d reach = box.axes.cwiseAbs() * box.half_extents;
  return Eigen::AlignedBox3d(box.center - reach, box.center + reach);
}

Eigen::AlignedBox3d bounding_box(const Sphere& sphere) {
  const Eigen::Vector3d reach = Eigen::Vector3d::Constant(sphere.radius);
  return Eigen::AlignedBox3d(sphere.center - reach, sphere.center + reach);
}

// The end discs: a disc of radius r orthogonal to the unit axis a reaches r sqrt(1 - a_i^2)
// along axis i.
Eigen::AlignedBox3d bounding_box(const Cylinder& c) {
  const Eigen::Vector3d reach =
      c.radius * (Eigen::Vector3d::Ones() - c.axis.cwiseProduct(c.axis)).cwiseMax(0.0).cwiseSqrt();
  const Eigen::Vector3d top = c.base + c.height * c.axis;
  Eigen::AlignedBox3d box(c.base - reach, c.base + reach);
  box.extend(top - reach);
  box.extend(top + reach);
  return box;
}

double area(const Rectangle& rectangle) { return 4.0 * rectangle.half_u * rectangle.half_v; }

double area(const Box& box) {
  const Eigen::Vector3d& h = box.half_extents;
  return 8.0 * (h.x() * h.y() + h.y() * h.z() + h.z() * h.x());
}

double area(const Sphere& sphere) { return 4.0 * kPi * sphere.radius * sphere.radius; }

double area(const Cylinder& cylinder) {
  return 2.0 * kPi * cylinder.radius * (cylinder.height + cylinder.radius);
}

}  // namespace internal
}  // namespace synthetic
}  // namespace PPCR_ABI_NAMESPACE
}  // namespace ppcr
