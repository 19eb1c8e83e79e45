// Trajectory metrics (tools/odometry/trajectory_metrics): ATE RMSE after rigid alignment and RPE
// per metre against closed forms.
#include <catch2/catch.hpp>
#include <cmath>
#include <string>
#include <vector>

#include "odometry/trajectory_metrics.hpp"

namespace {

using Poses = std::vector<Eigen::Isometry3d>;

// n poses one metre apart along x, identity rotations.
Poses straight_line(int n) {
  Poses poses;
  for (int i = 0; i < n; ++i) {
    Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
    T.translation() = Eigen::Vector3d(i, 0.0, 0.0);
    poses.push_back(T);
  }
  return poses;
}

// A pattern s_i = +1 -1 -1 +1 repeated: sum s_i = 0 and sum i s_i = 0 over every block of 4, so
// no rigid motion of a straight line along x can reduce a perturbation d s_i along z.
double pattern(int i) {
  const int r = i % 4;
  return r == 0 || r == 3 ? 1.0 : -1.0;
}

}  // namespace

TEST_CASE("a trajectory moved rigidly has no ATE and no RPE") {
  Poses truth;
  for (int i = 0; i < 50; ++i) {  // a helix with turning rotations
    Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
    T.linear() = Eigen::AngleAxisd(0.1 * i, Eigen::Vector3d::UnitZ()).toRotationMatrix();
    T.translation() = Eigen::Vector3d(3.0 * std::cos(0.1 * i), 3.0 * std::sin(0.1 * i), 0.05 * i);
    truth.push_back(T);
  }
  Eigen::Isometry3d S = Eigen::Isometry3d::Identity();
  S.linear() = Eigen::AngleAxisd(0.7, Eigen::Vector3d(1, 2, 3).normalized()).toRotationMatrix();
  S.translation() = Eigen::Vector3d(5.0, -2.0, 1.0);
  Poses estimate;
  for (const Eigen::Isometry3d& T : truth) estimate.push_back(S * T);
  ppcr_odometry::TrajectoryErrors e;
  REQUIRE(ppcr_odometry::trajectory_errors(truth, estimate, 1, &e).ok());
  CHECK(e.poses == 50);
  CHECK(e.ate_rmse < 1e-9);
  CHECK(e.rpe_translation < 1e-9);
  CHECK(e.rpe_rotation < 1e-9);
  CHECK((e.alignment.matrix() - S.inverse().matrix()).norm() < 1e-9);
}

TEST_CASE("a perturbation no alignment removes gives ATE = its size and the closed-form RPE") {
  const int n = 40;
  const double d = 0.03;
  const Poses truth = straight_line(n);
  Poses estimate = truth;
  for (int i = 0; i < n; ++i) estimate[i].translation().z() += d * pattern(i);
  ppcr_odometry::TrajectoryErrors e;
  REQUIRE(ppcr_odometry::trajectory_errors(truth, estimate, 1, &e).ok());
  CHECK(e.ate_rmse == Approx(d).epsilon(1e-9));
  // Steps i -> i+1 err by d (s_{i+1} - s_i): 2d on the even steps (20 of the 39), 0 on the odd.
  CHECK(e.distance == Approx(n - 1).epsilon(1e-12));
  CHECK(e.rpe_translation == Approx(2.0 * d * 20 / (n - 1)).epsilon(1e-9));
  CHECK(e.rpe_rotation == Approx(0.0).margin(1e-12));
}

TEST_CASE("a scale drift gives RPE = the drift and ATE = drift x the positions' spread") {
  const int n = 21;
  const double drift = 0.02;
  const Poses truth = straight_line(n);
  Poses estimate = truth;
  for (int i = 0; i < n; ++i) estimate[i].translation().x() *= 1.0 + drift;
  ppcr_odometry::TrajectoryErrors e;
  REQUIRE(ppcr_odometry::trajectory_errors(truth, estimate, 1, &e).ok());
  CHECK(e.rpe_translation == Approx(drift).epsilon(1e-9));
  // Aligned by the centroids (no rotation helps): residual drift (x_i - mean); std of 0..20.
  const double spread = std::sqrt((n * n - 1) / 12.0);
  CHECK(e.ate_rmse == Approx(drift * spread).epsilon(1e-9));
  // Over steps of 5 scans the drift per metre is the same.
  REQUIRE(ppcr_odometry::trajectory_errors(truth, estimate, 5, &e).ok());
  CHECK(e.rpe_translation == Approx(drift).epsilon(1e-9));
}

TEST_CASE("a rotation error per step gives RPE rotation = angle / step length") {
  const Poses truth = straight_line(11);
  Poses estimate = truth;
  // Each estimated step turns by 0.01 rad about z more than the truth, in place.
  for (int i = 1; i < 11; ++i) {
    estimate[i] = estimate[i - 1] * (truth[i - 1].inverse() * truth[i]) *
                  Eigen::Isometry3d(Eigen::AngleAxisd(0.01, Eigen::Vector3d::UnitZ()));
  }
  ppcr_odometry::TrajectoryErrors e;
  REQUIRE(ppcr_odometry::trajectory_errors(truth, estimate, 1, &e).ok());
  CHECK(e.rpe_rotation == Approx(0.01).epsilon(1e-9));
  CHECK(e.rpe_rotation_per_step == Approx(0.01).epsilon(1e-9));
  CHECK(e.rpe_translation == Approx(0.0).margin(1e-12));
  // Over steps of 2 scans: twice the angle per step, the same per metre.
  REQUIRE(ppcr_odometry::trajectory_errors(truth, estimate, 2, &e).ok());
  CHECK(e.rpe_rotation_per_step == Approx(0.02).epsilon(1e-9));
  CHECK(e.rpe_rotation == Approx(0.01).epsilon(1e-9));
}

TEST_CASE("too few poses, or a truth that does not move, are refused") {
  ppcr_odometry::TrajectoryErrors e;
  CHECK(!ppcr_odometry::trajectory_errors(straight_line(1), straight_line(1), 1, &e).ok());
  CHECK(!ppcr_odometry::trajectory_errors(straight_line(5), straight_line(5), 5, &e).ok());
  const Poses still(5, Eigen::Isometry3d::Identity());
  CHECK(!ppcr_odometry::trajectory_errors(still, still, 1, &e).ok());
}

namespace {

// A motion whose samples slerp and linear interpolation reproduce exactly: constant velocity and
// constant angular velocity about a fixed axis.
Eigen::Isometry3d motion_at(double t) {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = Eigen::AngleAxisd(0.5 * t, Eigen::Vector3d(1, 2, 2).normalized()).toRotationMatrix();
  T.translation() = Eigen::Vector3d(1.0, 2.0, -0.5) * t + Eigen::Vector3d(3, 0, 1);
  return T;
}

}  // namespace

TEST_CASE("poses_at_times: the truth interpolated at the estimate's times, outside ones left out") {
  std::vector<double> truth_times, times;
  Poses truth, estimate;
  for (int k = 0; k <= 20; ++k) {  // 10 Hz over 2 s
    truth_times.push_back(0.1 * k);
    truth.push_back(motion_at(0.1 * k));
  }
  for (double t : {-1.0, 0.0, 0.05, 0.37, 1.0, 1.999, 2.0, 2.5}) {
    times.push_back(t);
    estimate.push_back(motion_at(t));
  }
  Poses matched_truth, matched_estimate;
  std::size_t outside = 99;
  REQUIRE(ppcr_odometry::poses_at_times(truth_times, truth, times, estimate, &matched_truth,
                                        &matched_estimate, &outside)
              .ok());
  CHECK(outside == 2);  // -1 and 2.5
  REQUIRE(matched_truth.size() == 6);
  REQUIRE(matched_estimate.size() == 6);
  for (std::size_t i = 0; i < matched_truth.size(); ++i) {
    INFO("pose " << i);
    CHECK((matched_truth[i].matrix() - matched_estimate[i].matrix()).norm() < 1e-12);
  }
  truth_times[5] = truth_times[4];  // not increasing
  const ppcr::Status s = ppcr_odometry::poses_at_times(truth_times, truth, times, estimate,
                                                       &matched_truth, &matched_estimate, &outside);
  CHECK(s.code() == ppcr::StatusCode::kInvalidArgument);
  CHECK(s.message().find("pose 6") != std::string::npos);
}
