// reliability_util.hpp - scenes and checks shared by the reliability tests: seeded point
// sampling of simple surfaces (plane, line, cylinder, a well-constrained box corner scene), poses
// from axis-angle (Eigen only), and the invariants every result must keep (finite rigid pose, a
// stop reason, iterations within the caps, history consistent).
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <random>
#include <sstream>
#include <string>

#include "ppcr/registration.hpp"

namespace rel_test {

using Rng = std::mt19937_64;
using ppcr::PointCloud;

constexpr double kPi = 3.14159265358979323846;

inline double uniform(Rng& rng, double lo, double hi) {
  return std::uniform_real_distribution<double>(lo, hi)(rng);
}

inline Eigen::Isometry3d make_pose(const Eigen::Vector3d& axis, double angle_rad,
                                   const Eigen::Vector3d& t) {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = Eigen::AngleAxisd(angle_rad, axis.normalized()).toRotationMatrix();
  T.translation() = t;
  return T;
}

/// A small motion: 2 degrees about a generic axis, a few centimetres (scene units: metres).
inline Eigen::Isometry3d small_motion() {
  return make_pose(Eigen::Vector3d(0.3, -0.5, 1.0), 2.0 * kPi / 180.0,
                   Eigen::Vector3d(0.03, -0.02, 0.015));
}

inline PointCloud transformed(const PointCloud& cloud, const Eigen::Isometry3d& T) {
  PointCloud out;
  out.reserve(cloud.size());
  for (const Eigen::Vector3d& p : cloud) out.push_back(T * p);
  return out;
}

inline PointCloud scaled(const PointCloud& cloud, double factor) {
  PointCloud out;
  out.reserve(cloud.size());
  for (const Eigen::Vector3d& p : cloud) out.push_back(factor * p);
  return out;
}

/// z = 0, x and y uniform in [-1, 1].
inline PointCloud plane_cloud(Rng& rng, std::size_t n) {
  PointCloud out;
  for (std::size_t i = 0; i < n; ++i) out.emplace_back(uniform(rng, -1, 1), uniform(rng, -1, 1), 0);
  return out;
}

/// The x axis, x uniform in [-1, 1].
inline PointCloud line_cloud(Rng& rng, std::size_t n) {
  PointCloud out;
  for (std::size_t i = 0; i < n; ++i) out.emplace_back(uniform(rng, -1, 1), 0, 0);
  return out;
}

/// A full cylinder of radius 0.5 about the z axis, z in [-1, 1].
inline PointCloud cylinder_cloud(Rng& rng, std::size_t n) {
  PointCloud out;
  for (std::size_t i = 0; i < n; ++i) {
    const double a = uniform(rng, 0.0, 2.0 * kPi);
    out.emplace_back(0.5 * std::cos(a), 0.5 * std::sin(a), uniform(rng, -1, 1));
  }
  return out;
}

/// A well-constrained scene about 2 m across: a floor, two walls (90 and 60 degrees) and a
/// sphere. Every rigid motion changes the point-to-surface distances.
inline PointCloud box_scene(Rng& rng, std::size_t n) {
  PointCloud out;
  const Eigen::Vector3d u(std::cos(-kPi / 6), std::sin(-kPi / 6), 0.0);
  for (std::size_t i = 0; i < n; ++i) {
    const double a = uniform(rng, -1, 1), b = uniform(rng, 0, 1);
    switch (i % 4) {
      case 0:
        out.emplace_back(a, uniform(rng, -1, 1), 0.0);
        break;
      case 1:
        out.emplace_back(-1.0, a, b);
        break;
      case 2:
        out.push_back(Eigen::Vector3d(0.2, 1.0, 0.0) + 0.8 * a * u + b * Eigen::Vector3d::UnitZ());
        break;
      default: {
        Eigen::Vector3d d(uniform(rng, -1, 1), uniform(rng, -1, 1), uniform(rng, -1, 1));
        if (d.norm() < 1e-3) d = Eigen::Vector3d::UnitX();
        out.push_back(Eigen::Vector3d(0.3, -0.2, 0.5) + 0.3 * d.normalized());
      }
    }
  }
  return out;
}

inline double rotation_error_deg(const Eigen::Isometry3d& a, const Eigen::Isometry3d& b) {
  const Eigen::Quaterniond q(a.linear().transpose() * b.linear());
  return 2.0 * std::atan2(q.vec().norm(), std::abs(q.w())) * 180.0 / kPi;
}

/// RMS displacement of the points of `cloud` between the poses A and B.
inline double rms_between(const PointCloud& cloud, const Eigen::Isometry3d& A,
                          const Eigen::Isometry3d& B) {
  double sum = 0.0;
  for (const Eigen::Vector3d& x : cloud) sum += (A * x - B * x).squaredNorm();
  return std::sqrt(sum / static_cast<double>(cloud.size()));
}

inline bool is_rigid(const Eigen::Isometry3d& T, double tol = 1e-9) {
  const Eigen::Matrix4d& M = T.matrix();
  if (!M.allFinite()) return false;
  if (M.row(3) != Eigen::RowVector4d(0, 0, 0, 1)) return false;
  const Eigen::Matrix3d R = T.linear();
  return (R.transpose() * R - Eigen::Matrix3d::Identity()).cwiseAbs().maxCoeff() < tol &&
         std::abs(R.determinant() - 1.0) < tol;
}

inline std::string describe(const ppcr::RegistrationResult& r) {
  std::ostringstream s;
  s << r.status.to_string() << " | stop " << ppcr::to_string(r.stop_reason) << " | " << r.iterations
    << " it, " << r.lm_iterations << " LM | degenerate " << r.degenerate_directions << " | matched "
    << r.matched_source_points << "/" << r.source_points << " | scale " << r.scale << " | T\n"
    << r.T_target_source.matrix();
  return s.str();
}

/// The invariants of every result (see docs/RELIABILITY.md). Returns "" or what is wrong.
inline std::string invariant_violation(const ppcr::RegistrationResult& r,
                                       const ppcr::RegistrationOptions& o) {
  if (!is_rigid(r.T_target_source)) return "pose not finite or not rigid";
  if (r.stop_reason == ppcr::StopReason::kNone) return "no stop reason";
  if (r.iterations > o.max_iterations) return "iterations above the cap";
  if (r.lm_iterations > r.iterations * o.expert.lm_max_iterations)
    return "LM iterations above the cap";
  if (o.record_history && static_cast<int>(r.history.size()) != r.iterations) {
    return "history size != iterations";
  }
  if (r.status.ok()) {
    if (r.stop_reason == ppcr::StopReason::kInvalidInput ||
        r.stop_reason == ppcr::StopReason::kNumericalFailure) {
      return "ok status with a failure stop reason";
    }
    if (!r.information.allFinite()) return "ok status with a non-finite information matrix";
    if (!r.covariance.allFinite()) return "ok status with a non-finite covariance";
    if (!r.covariance.isApprox(r.covariance.transpose()) ||
        r.covariance.diagonal().minCoeff() < 0) {
      std::ostringstream text;
      text << "ok status with a covariance that is not symmetric with a non-negative diagonal:\n"
           << r.covariance;
      return text.str();
    }
    if (!std::isfinite(r.final_cost)) return "ok status with a non-finite cost";
  } else if (r.status.message().empty()) {
    return "failure without a message";
  }
  return "";
}

}  // namespace rel_test
