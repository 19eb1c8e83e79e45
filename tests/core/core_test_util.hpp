// core_test_util.hpp - small helpers shared by the core tests: seeded random draws, poses built
// from axis-angle (through Eigen, independently of ppcr::se3), and a synthetic scene of analytic
// surfaces for the registration tests.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <random>
#include <utility>
#include <vector>

#include "common/parallel.hpp"
#include "ppcr/types.hpp"

namespace core_test {

// The threads of a test's parallel loops: `threads` threads (at most 8), or null (the calling
// thread alone) for 1. One Parallel per count, kept for the test program's life.
inline const ppcr::detail::Parallel* parallel(int threads) {
  static std::unique_ptr<ppcr::detail::Parallel> by_count[9];
  if (threads <= 1) return nullptr;
  std::unique_ptr<ppcr::detail::Parallel>& p = by_count[std::min(threads, 8)];
  if (!p) p.reset(new ppcr::detail::Parallel(std::min(threads, 8)));
  return p.get();
}

using Rng = std::mt19937_64;

constexpr double kPi = 3.14159265358979323846;

inline double deg2rad(double deg) { return deg * kPi / 180.0; }

inline double uniform(Rng& rng, double lo, double hi) {
  return std::uniform_real_distribution<double>(lo, hi)(rng);
}

inline double gaussian(Rng& rng, double sigma) {
  return std::normal_distribution<double>(0.0, sigma)(rng);
}

/// A direction drawn uniformly on the unit sphere.
inline Eigen::Vector3d random_unit_vector(Rng& rng) {
  for (;;) {
    const Eigen::Vector3d v(gaussian(rng, 1.0), gaussian(rng, 1.0), gaussian(rng, 1.0));
    const double n = v.norm();
    if (n > 1e-6) return v / n;
  }
}

/// A pose made with Eigen's AngleAxis (not ppcr::se3): rotation by angle_rad about axis (any
/// length, normalised here), then translation t.
inline Eigen::Isometry3d make_pose(const Eigen::Vector3d& axis, double angle_rad,
                                   const Eigen::Vector3d& t) {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = Eigen::AngleAxisd(angle_rad, axis.normalized()).toRotationMatrix();
  T.translation() = t;
  return T;
}

/// Angle of the rotation R_a^T R_b in degrees, from the quaternion (independent of ppcr::se3).
inline double angle_between_deg(const Eigen::Matrix3d& Ra, const Eigen::Matrix3d& Rb) {
  const Eigen::Quaterniond q(Ra.transpose() * Rb);
  const double s = q.vec().norm();
  return 2.0 * std::atan2(s, std::abs(q.w())) * 180.0 / kPi;
}

inline ppcr::PointCloud transformed(const ppcr::PointCloud& cloud, const Eigen::Isometry3d& T) {
  ppcr::PointCloud out;
  out.reserve(cloud.size());
  for (const Eigen::Vector3d& p : cloud) out.push_back(T * p);
  return out;
}

/// The k points of cloud nearest to cloud[i] by brute force (itself first, unless duplicated), as
/// (squared distance, index) in increasing order (ties by index): an independent reference for the
/// k-d tree's queries and the normal fits. k is clamped to the cloud's size.
inline std::vector<std::pair<double, std::size_t>> brute_force_nearest(
    const ppcr::PointCloud& cloud, std::size_t i, std::size_t k) {
  std::vector<std::pair<double, std::size_t>> by_distance(cloud.size());
  for (std::size_t m = 0; m < cloud.size(); ++m) {
    by_distance[m] = {(cloud[m] - cloud[i]).squaredNorm(), m};
  }
  k = std::min(k, by_distance.size());
  const auto kth = by_distance.begin() + static_cast<std::ptrdiff_t>(k);
  std::partial_sort(by_distance.begin(), kth, by_distance.end());
  by_distance.erase(kth, by_distance.end());
  return by_distance;
}

/// The upper median over points[0], points[stride], ... of the distance to the nearest other point
/// at a non-zero distance (duplicates skipped), by brute force: the reference for median_spacing()
/// (point_spacing.hpp). 0 when no sampled point has such a neighbour.
inline double brute_force_spacing(const ppcr::PointCloud& points, std::size_t stride = 1) {
  std::vector<double> nearest;
  for (std::size_t i = 0; i < points.size(); i += stride) {
    double best = HUGE_VAL;
    for (const Eigen::Vector3d& q : points) {
      const double d = (q - points[i]).squaredNorm();
      if (d > 0.0) best = std::min(best, d);
    }
    if (best < HUGE_VAL) nearest.push_back(std::sqrt(best));
  }
  if (nearest.empty()) return 0.0;
  std::sort(nearest.begin(), nearest.end());
  return nearest[nearest.size() / 2];
}

/// Uniform random points in the box [lo, hi]^3.
inline ppcr::PointCloud uniform_cloud(Rng& rng, std::size_t n, double lo, double hi) {
  ppcr::PointCloud out(n);
  for (Eigen::Vector3d& p : out)
    p = Eigen::Vector3d(uniform(rng, lo, hi), uniform(rng, lo, hi), uniform(rng, lo, hi));
  return out;
}

/// Points on a union of analytic surfaces, scene about 2 m across, centred near the origin:
/// three mutually non-parallel planar patches (a floor, two walls at 90 and 60 degrees), a
/// sphere, and a vertical cylinder patch. Every rigid motion changes the point-to-surface
/// distances, so the registration problem is well constrained. `count` points in total,
/// distributed over the surfaces in fixed proportions.
inline ppcr::PointCloud analytic_scene(Rng& rng, std::size_t count) {
  ppcr::PointCloud out;
  out.reserve(count);
  const std::size_t n_floor = count * 3 / 10;
  const std::size_t n_wall1 = count * 2 / 10;
  const std::size_t n_wall2 = count * 15 / 100;
  const std::size_t n_sphere = count * 2 / 10;
  const std::size_t n_cyl = count - n_floor - n_wall1 - n_wall2 - n_sphere;
  // Floor z = 0, x, y in [-1, 1].
  for (std::size_t i = 0; i < n_floor; ++i) {
    out.emplace_back(uniform(rng, -1.0, 1.0), uniform(rng, -1.0, 1.0), 0.0);
  }
  // Wall x = -1, y in [-1, 1], z in [0, 1].
  for (std::size_t i = 0; i < n_wall1; ++i) {
    out.emplace_back(-1.0, uniform(rng, -1.0, 1.0), uniform(rng, 0.0, 1.0));
  }
  // Wall through (0, 1, 0) with its normal at 60 degrees from the y axis, tilted 10 degrees.
  {
    const Eigen::Vector3d u = Eigen::Vector3d(std::cos(deg2rad(-30.0)), std::sin(deg2rad(-30.0)),
                                              0.0);  // in-plane horizontal direction
    const Eigen::Vector3d v =
        Eigen::AngleAxisd(deg2rad(10.0), u) * Eigen::Vector3d::UnitZ();  // in-plane, tilted
    for (std::size_t i = 0; i < n_wall2; ++i) {
      out.push_back(Eigen::Vector3d(0.2, 1.0, 0.0) + uniform(rng, -0.8, 0.8) * u +
                    uniform(rng, 0.0, 1.0) * v);
    }
  }
  // Sphere of radius 0.3 centred at (0.3, -0.2, 0.5).
  for (std::size_t i = 0; i < n_sphere; ++i) {
    out.push_back(Eigen::Vector3d(0.3, -0.2, 0.5) + 0.3 * random_unit_vector(rng));
  }
  // Vertical cylinder patch, axis (0.6, 0.5, z), radius 0.25, angles in [0, 200] degrees.
  for (std::size_t i = 0; i < n_cyl; ++i) {
    const double a = deg2rad(uniform(rng, 0.0, 200.0));
    out.emplace_back(0.6 + 0.25 * std::cos(a), 0.5 + 0.25 * std::sin(a), uniform(rng, 0.0, 0.8));
  }
  return out;
}

}  // namespace core_test
