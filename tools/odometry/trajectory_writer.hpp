// trajectory_writer.hpp - a trajectory written as it grows, to a KITTI and a TUM file at once,
// one complete line per pose in each (LineFile): after any stop both hold exactly the poses
// appended so far.
#pragma once

#include <Eigen/Geometry>
#include <string>

#include "odometry/line_file.hpp"
#include "ppcr/status.hpp"

namespace ppcr_odometry {

class TrajectoryWriter {
 public:
  /// Creates both files (an empty path leaves that format out).
  ppcr::Status open(const std::string& kitti_path, const std::string& tum_path);
  /// Appends pose (T_first_i) at `time` seconds to both files.
  ppcr::Status append(double time, const Eigen::Isometry3d& pose);
  ppcr::Status close();

 private:
  LineFile kitti_, tum_;
};

}  // namespace ppcr_odometry
