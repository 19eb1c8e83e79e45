// trajectory_metrics.hpp - how far an estimated trajectory is from the ground truth. Poses are
// paired by index (pose i of each); both are T_first_i (scan i into the first scan's frame).
//
// ATE RMSE (absolute trajectory error): the estimated positions are first aligned to the true
// ones by the rigid motion (rotation and translation, no scale) minimising the sum of squared
// distances (Horn 1987 / Umeyama 1991, Eigen::umeyama without scaling); then the root mean
// square of the remaining distances, in metres (cloud units).
//
// RPE (relative pose error) for a step of `delta` scans: E_i = (G_i^-1 G_{i+delta})^-1
// (P_i^-1 P_{i+delta}) compares each estimated relative motion P with the true one G. It is
// normalised by the distance travelled: rpe_translation = sum_i |t(E_i)| / sum_i
// |t(G_i^-1 G_{i+delta})| (a fraction; x 100 = the drift in % of distance, comparable to KITTI's
// translational error) and rpe_rotation = sum_i angle(E_i) / the same distance (radians per
// metre); rpe_rotation_per_step = the mean angle(E_i) (radians per step of delta scans: the
// figure for a camera that mostly turns, whose path is short). Sums, not means of ratios, so that
// near-zero motions (a pause) do not blow it up; no alignment is needed, relative motions are
// frame-free.
#pragma once

#include <Eigen/Geometry>
#include <vector>

#include "ppcr/status.hpp"

namespace ppcr_odometry {

struct TrajectoryErrors {
  std::size_t poses = 0;         // pairs compared: the shorter trajectory's length
  double ate_rmse = 0.0;         // metres
  double rpe_translation = 0.0;  // fraction of the distance travelled
  double rpe_rotation = 0.0;     // radians per metre
  double rpe_rotation_per_step = 0.0;  // radians per step of delta scans
  double distance = 0.0;         // the true path length over the steps, metres
  Eigen::Isometry3d alignment = Eigen::Isometry3d::Identity();  // maps estimate into truth
};

/// The errors of `estimate` against `truth` over their first min(sizes) poses (at least 2, and
/// more than delta >= 1); kInvalidArgument otherwise, or when the truth does not move.
ppcr::Status trajectory_errors(const std::vector<Eigen::Isometry3d>& truth,
                               const std::vector<Eigen::Isometry3d>& estimate, int delta,
                               TrajectoryErrors* errors);

/// The poses of `truth` at the times of `estimate`'s, for trajectories that both carry times
/// (TUM): each estimated pose at time t with the truth interpolated at t between the two true
/// poses around it (translation linearly, rotation by slerp; TUM's associate.py takes the nearest
/// instead). Estimated poses outside the truth's time span (or at a NaN time) are left out and
/// counted in *outside. The truth's times must increase; kInvalidArgument otherwise, naming the
/// pose (its place in the trajectory).
ppcr::Status poses_at_times(const std::vector<double>& truth_times,
                            const std::vector<Eigen::Isometry3d>& truth_poses,
                            const std::vector<double>& times,
                            const std::vector<Eigen::Isometry3d>& poses,
                            std::vector<Eigen::Isometry3d>* matched_truth,
                            std::vector<Eigen::Isometry3d>* matched_estimate, std::size_t* outside);

}  // namespace ppcr_odometry
