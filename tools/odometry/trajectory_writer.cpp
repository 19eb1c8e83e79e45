// trajectory_writer.cpp - the KITTI and TUM files of a growing trajectory.
#include "odometry/trajectory_writer.hpp"

#include "odometry/trajectory_format.hpp"

namespace ppcr_odometry {

ppcr::Status TrajectoryWriter::open(const std::string& kitti_path, const std::string& tum_path) {
  ppcr::Status s;
  if (!kitti_path.empty()) s = kitti_.open(kitti_path);
  if (s.ok() && !tum_path.empty()) s = tum_.open(tum_path);
  return s;
}

ppcr::Status TrajectoryWriter::append(double time, const Eigen::Isometry3d& pose) {
  ppcr::Status s;
  if (kitti_.is_open()) s = kitti_.write_line(kitti_line(pose));
  if (s.ok() && tum_.is_open()) s = tum_.write_line(tum_line(time, pose));
  return s;
}

ppcr::Status TrajectoryWriter::close() {
  const ppcr::Status s = kitti_.close();
  const ppcr::Status t = tum_.close();
  return s.ok() ? t : s;
}

}  // namespace ppcr_odometry
