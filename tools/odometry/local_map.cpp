// local_map.cpp - the last N scans merged in the newest scan's frame.
#include "odometry/local_map.hpp"

#include <string>

#include "ppcr/voxel.hpp"

namespace ppcr_odometry {

ppcr::Status LocalMap::add(const ppcr::PointCloud& scan, const Eigen::Isometry3d& T_first_scan) {
  if (capacity_ <= 1) {
    map_ = scan;
    return ppcr::Status::Ok();
  }
  if (!(voxel_ > 0.0) && !entries_.empty()) {
    return ppcr::Status(ppcr::StatusCode::kInvalidArgument,
                        "local map: no voxel leaf set (--map-voxel)");
  }
  Entry entry;
  entry.pose = T_first_scan;
  ppcr::PointCloud moved(scan.size());
  for (std::size_t i = 0; i < scan.size(); ++i) moved[i] = T_first_scan * scan[i];
  if (voxel_ > 0.0) {
    const ppcr::Status s = ppcr::voxel_downsample(moved, voxel_, &entry.points);
    if (!s.ok()) return ppcr::Status(s.code(), "--map-voxel: " + s.message());
  } else {
    entry.points = std::move(moved);  // the first scan, before the leaf is known
  }
  entries_.push_back(std::move(entry));
  while (entries_.size() > capacity_) entries_.pop_front();

  // Merge in the newest scan's frame, then filter the union so that overlapping scans do not
  // stack their points.
  const Eigen::Isometry3d scan_T_first = T_first_scan.inverse();
  ppcr::PointCloud merged;
  for (const Entry& e : entries_) {
    for (const Eigen::Vector3d& p : e.points) merged.push_back(scan_T_first * p);
  }
  if (entries_.size() == 1 || !(voxel_ > 0.0)) {
    map_ = std::move(merged);
    return ppcr::Status::Ok();
  }
  const ppcr::Status s = ppcr::voxel_downsample(merged, voxel_, &map_);
  return s.ok() ? s : ppcr::Status(s.code(), "--map-voxel: " + s.message());
}

}  // namespace ppcr_odometry
