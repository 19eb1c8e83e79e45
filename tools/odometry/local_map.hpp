// local_map.hpp - the target of scan-to-map odometry: the last N registered scans, merged in the
// frame of the newest one and voxel-filtered. With N = 1 it is the previous scan itself
// (scan-to-scan), unfiltered.
#pragma once

#include <Eigen/Geometry>
#include <deque>

#include "ppcr/status.hpp"
#include "ppcr/types.hpp"

namespace ppcr_odometry {

class LocalMap {
 public:
  /// capacity: the N scans kept (>= 1).
  explicit LocalMap(std::size_t capacity) : capacity_(capacity) {}

  /// The voxel leaf of the merged map (cloud units, > 0); needed before a second scan is added
  /// when capacity > 1.
  void set_voxel(double leaf) { voxel_ = leaf; }
  double voxel() const { return voxel_; }

  /// Adds a registered scan (in its own frame) with its pose T_first_scan, dropping the oldest
  /// beyond the capacity, and rebuilds the map in this scan's frame.
  ppcr::Status add(const ppcr::PointCloud& scan, const Eigen::Isometry3d& T_first_scan);

  /// The map in the frame of the newest scan added.
  const ppcr::PointCloud& cloud() const { return map_; }

 private:
  struct Entry {
    ppcr::PointCloud points;  // in the first scan's frame (voxel-filtered when capacity > 1)
    Eigen::Isometry3d pose;
  };
  std::size_t capacity_;
  double voxel_ = 0.0;
  std::deque<Entry> entries_;
  ppcr::PointCloud map_;
};

}  // namespace ppcr_odometry
