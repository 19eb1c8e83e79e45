// trajectory_format.hpp - trajectories as text, one pose per line:
//   KITTI: the top 3 rows of the 4x4 pose, row by row (12 numbers: r11 r12 r13 tx r21 ... tz);
//   TUM:   "t tx ty tz qx qy qz qw" (time in seconds, unit quaternion of the rotation).
// A pose is T_first_i: it maps points of scan i into the first scan's frame. Numbers are written
// with 17 significant digits (an exact round trip of the double).
#pragma once

#include <Eigen/Geometry>
#include <string>
#include <vector>

#include "ppcr/status.hpp"

namespace ppcr_odometry {

struct Trajectory {
  std::vector<double> times;  // seconds (TUM); KITTI: the line index (no times in the format)
  std::vector<Eigen::Isometry3d> poses;
  bool timed = false;  // the times are the file's (TUM), not line indices
};

std::string kitti_line(const Eigen::Isometry3d& pose);
std::string tum_line(double time, const Eigen::Isometry3d& pose);

/// Reads a KITTI (12 numbers a line) or TUM (8 numbers a line) trajectory, told apart by the
/// first data line; blank lines and '#' comments are skipped. A KITTI rotation must be
/// orthonormal within 1e-4 (|R^T R - I|, files printed with 6 digits or from float code) and is
/// then replaced by the nearest rotation when it deviates by more than 1e-12; a TUM quaternion
/// must have unit norm within 1e-4 and is normalised. The message names the file, the line and
/// what is wrong.
ppcr::Status read_trajectory(const std::string& path, Trajectory* trajectory);

}  // namespace ppcr_odometry
