// scene_reference.hpp - independent references for the synthetic-scene tests: distances to the
// primitives' surfaces and point-in-solid tests, written from the geometric definitions (they do
// not call the library's intersection or distance code), and a brute-force-checked grid for
// nearest-neighbour queries.
#pragma once

#include <Eigen/Core>
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <unordered_map>
#include <vector>

#include "ppcr/types.hpp"
#include "synthetic/scene.hpp"

namespace synth_test {

using ppcr::synthetic::internal::Box;
using ppcr::synthetic::internal::Cylinder;
using ppcr::synthetic::internal::Rectangle;
using ppcr::synthetic::internal::Scene;
using ppcr::synthetic::internal::Sphere;

// Distance from p to the rectangle: components of p - c along u, v and the normal; the excess
// beyond the half sizes in the plane, and the height above it, are orthogonal.
inline double surface_distance(const Eigen::Vector3d& p, const Rectangle& r) {
  const Eigen::Vector3d d = p - r.center;
  const Eigen::Vector3d n = r.u.cross(r.v).normalized();
  const double eu = std::max(std::abs(d.dot(r.u)) - r.half_u, 0.0);
  const double ev = std::max(std::abs(d.dot(r.v)) - r.half_v, 0.0);
  const double h = d.dot(n);
  return std::sqrt(eu * eu + ev * ev + h * h);
}

// Box surface: inside, the distance to the nearest face plane; outside, the distance to the
// nearest point of the solid (clamping the local coordinates to the box).
inline double surface_distance(const Eigen::Vector3d& p, const Box& b) {
  Eigen::Vector3d local;
  for (int i = 0; i < 3; ++i) local[i] = b.axes.col(i).dot(p - b.center);
  bool inside = true;
  for (int i = 0; i < 3; ++i) inside = inside && std::abs(local[i]) <= b.half_extents[i];
  if (inside) {
    double best = std::numeric_limits<double>::infinity();
    for (int i = 0; i < 3; ++i) best = std::min(best, b.half_extents[i] - std::abs(local[i]));
    return best;
  }
  Eigen::Vector3d clamped;
  for (int i = 0; i < 3; ++i) {
    clamped[i] = std::clamp(local[i], -b.half_extents[i], b.half_extents[i]);
  }
  return (local - clamped).norm();
}

inline double surface_distance(const Eigen::Vector3d& p, const Sphere& s) {
  return std::abs((p - s.center).norm() - s.radius);
}

// Capped cylinder in (radial rho, axial s) coordinates: a rectangle [0, r] x [0, h].
inline double surface_distance(const Eigen::Vector3d& p, const Cylinder& c) {
  const Eigen::Vector3d w = p - c.base;
  const double s = w.dot(c.axis);
  const double rho = (w - s * c.axis).norm();
  if (s >= 0.0 && s <= c.height && rho <= c.radius) {
    return std::min({c.radius - rho, s, c.height - s});
  }
  const double ds = s - std::clamp(s, 0.0, c.height);
  const double dr = rho - std::min(rho, c.radius);
  return std::sqrt(ds * ds + dr * dr);
}

inline bool inside(const Eigen::Vector3d& p, const Box& b) {
  for (int i = 0; i < 3; ++i) {
    if (std::abs(b.axes.col(i).dot(p - b.center)) >= b.half_extents[i]) return false;
  }
  return true;
}
inline bool inside(const Eigen::Vector3d& p, const Sphere& s) {
  return (p - s.center).squaredNorm() < s.radius * s.radius;
}
inline bool inside(const Eigen::Vector3d& p, const Cylinder& c) {
  const Eigen::Vector3d w = p - c.base;
  const double s = w.dot(c.axis);
  return s > 0.0 && s < c.height && (w - s * c.axis).squaredNorm() < c.radius * c.radius;
}

/// Distance from p to the nearest surface of the scene. Primitives whose bounding sphere is
/// farther than the best distance so far are skipped (this only saves time: a surface is never
/// nearer than its bounding sphere).
class SceneDistance {
 public:
  explicit SceneDistance(const Scene& scene) : scene_(scene) {
    for (const auto& r : scene.rectangles) add(r.center, std::hypot(r.half_u, r.half_v));
    for (const auto& b : scene.boxes) add(b.center, b.half_extents.norm());
    for (const auto& s : scene.spheres) add(s.center, s.radius);
    for (const auto& c : scene.cylinders) {
      add(c.base + 0.5 * c.height * c.axis, std::hypot(0.5 * c.height, c.radius));
    }
  }

  double operator()(const Eigen::Vector3d& p) const {
    double best = std::numeric_limits<double>::infinity();
    std::size_t i = 0;
    auto visit = [&](const auto& primitive) {
      if ((p - centers_[i]).norm() - radii_[i] <= best) {
        best = std::min(best, surface_distance(p, primitive));
      }
      ++i;
    };
    for (const auto& r : scene_.rectangles) visit(r);
    for (const auto& b : scene_.boxes) visit(b);
    for (const auto& s : scene_.spheres) visit(s);
    for (const auto& c : scene_.cylinders) visit(c);
    return best;
  }

 private:
  void add(const Eigen::Vector3d& center, double radius) {
    centers_.push_back(center);
    radii_.push_back(radius + 1e-9);
  }
  const Scene& scene_;
  std::vector<Eigen::Vector3d> centers_;
  std::vector<double> radii_;
};

inline double scene_distance(const Scene& scene, const Eigen::Vector3d& p) {
  return SceneDistance(scene)(p);
}

/// Uniform hash grid of cell size `radius`: "has a point within radius" in the 27 cells around.
class RadiusGrid {
 public:
  RadiusGrid(const ppcr::PointCloud& cloud, double radius) : cloud_(cloud), radius_(radius) {
    for (std::size_t i = 0; i < cloud.size(); ++i) cells_[key(cell(cloud[i]))].push_back(i);
  }

  bool has_neighbour(const Eigen::Vector3d& p) const {
    const Eigen::Vector3i c = cell(p);
    for (int dx = -1; dx <= 1; ++dx) {
      for (int dy = -1; dy <= 1; ++dy) {
        for (int dz = -1; dz <= 1; ++dz) {
          const auto found = cells_.find(key(c + Eigen::Vector3i(dx, dy, dz)));
          if (found == cells_.end()) continue;
          for (const std::size_t i : found->second) {
            if ((cloud_[i] - p).squaredNorm() <= radius_ * radius_) return true;
          }
        }
      }
    }
    return false;
  }

 private:
  Eigen::Vector3i cell(const Eigen::Vector3d& p) const {
    return (p / radius_).array().floor().cast<int>();
  }
  static std::int64_t key(const Eigen::Vector3i& c) {
    return (static_cast<std::int64_t>(c.x()) * 73856093) ^
           (static_cast<std::int64_t>(c.y()) * 19349663) ^
           (static_cast<std::int64_t>(c.z()) * 83492791);
  }
  const ppcr::PointCloud& cloud_;
  double radius_;
  std::unordered_map<std::int64_t, std::vector<std::size_t>> cells_;
};

}  // namespace synth_test
