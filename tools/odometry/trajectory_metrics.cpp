// trajectory_metrics.cpp - ATE after rigid alignment, RPE per metre.
#include "odometry/trajectory_metrics.hpp"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <string>

namespace ppcr_odometry {
namespace {

// The ATE RMSE of the first n poses, and the rigid motion aligning the estimate to the truth.
double ate_rmse(const std::vector<Eigen::Isometry3d>& truth,
                const std::vector<Eigen::Isometry3d>& estimate, std::size_t n,
                Eigen::Isometry3d* alignment) {
  Eigen::Matrix3Xd from(3, static_cast<Eigen::Index>(n));
  Eigen::Matrix3Xd to(3, static_cast<Eigen::Index>(n));
  for (std::size_t i = 0; i < n; ++i) {
    from.col(static_cast<Eigen::Index>(i)) = estimate[i].translation();
    to.col(static_cast<Eigen::Index>(i)) = truth[i].translation();
  }
  alignment->matrix() = Eigen::umeyama(from, to, false);
  double sum = 0.0;
  for (std::size_t i = 0; i < n; ++i) {
    sum += ((*alignment) * estimate[i].translation() - truth[i].translation()).squaredNorm();
  }
  return std::sqrt(sum / static_cast<double>(n));
}

}  // namespace

ppcr::Status trajectory_errors(const std::vector<Eigen::Isometry3d>& truth,
                               const std::vector<Eigen::Isometry3d>& estimate, int delta,
                               TrajectoryErrors* errors) {
  const std::size_t n = std::min(truth.size(), estimate.size());
  const auto step = static_cast<std::size_t>(std::max(delta, 0));
  if (delta < 1 || n < 2 || n <= step) {
    return ppcr::Status(ppcr::StatusCode::kInvalidArgument,
                        "trajectory errors need at least 2 poses and more than delta = " +
                            std::to_string(delta) + " >= 1 of them; got " + std::to_string(n));
  }
  *errors = TrajectoryErrors();
  errors->poses = n;
  errors->ate_rmse = ate_rmse(truth, estimate, n, &errors->alignment);
  double translation = 0.0, rotation = 0.0;
  for (std::size_t i = 0; i + step < n; ++i) {
    const Eigen::Isometry3d true_motion = truth[i].inverse() * truth[i + step];
    const Eigen::Isometry3d estimated_motion = estimate[i].inverse() * estimate[i + step];
    const Eigen::Isometry3d error = true_motion.inverse() * estimated_motion;
    translation += error.translation().norm();
    rotation += Eigen::AngleAxisd(error.rotation()).angle();
    errors->distance += true_motion.translation().norm();
  }
  if (!(errors->distance > 0.0)) {
    return ppcr::Status(ppcr::StatusCode::kInvalidArgument,
                        "the true trajectory does not move: RPE per metre is undefined");
  }
  errors->rpe_translation = translation / errors->distance;
  errors->rpe_rotation = rotation / errors->distance;
  errors->rpe_rotation_per_step = rotation / static_cast<double>(n - step);
  return ppcr::Status::Ok();
}

ppcr::Status poses_at_times(const std::vector<double>& truth_times,
                            const std::vector<Eigen::Isometry3d>& truth_poses,
                            const std::vector<double>& times,
                            const std::vector<Eigen::Isometry3d>& poses,
                            std::vector<Eigen::Isometry3d>* matched_truth,
                            std::vector<Eigen::Isometry3d>* matched_estimate,
                            std::size_t* outside) {
  for (std::size_t i = 1; i < truth_times.size(); ++i) {
    if (!(truth_times[i] > truth_times[i - 1])) {
      return ppcr::Status(ppcr::StatusCode::kInvalidArgument,
                          "the ground truth's times must increase: pose " + std::to_string(i + 1) +
                              " is not later than pose " + std::to_string(i));
    }
  }
  matched_truth->clear();
  matched_estimate->clear();
  *outside = 0;
  for (std::size_t j = 0; j < poses.size(); ++j) {
    const double t = times[j];
    if (truth_times.empty() || !(t >= truth_times.front() && t <= truth_times.back())) {
      ++*outside;
      continue;
    }
    // The first true pose later than t (or the last one), and the one before it.
    const std::size_t after = static_cast<std::size_t>(
        std::upper_bound(truth_times.begin(), truth_times.end(), t) - truth_times.begin());
    const std::size_t b = std::min(after, truth_times.size() - 1);
    const std::size_t a = b == 0 ? 0 : b - 1;
    const double span = truth_times[b] - truth_times[a];
    const double f = span > 0.0 ? (t - truth_times[a]) / span : 0.0;
    const Eigen::Quaterniond qa(truth_poses[a].linear()), qb(truth_poses[b].linear());
    Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
    pose.linear() = qa.slerp(f, qb).toRotationMatrix();
    pose.translation() =
        (1.0 - f) * truth_poses[a].translation() + f * truth_poses[b].translation();
    matched_truth->push_back(pose);
    matched_estimate->push_back(poses[j]);
  }
  return ppcr::Status::Ok();
}

}  // namespace ppcr_odometry
