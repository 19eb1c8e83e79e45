// sequence_output.cpp - a synthetic sequence written scan by scan.
#include "sequence_output.hpp"

#include <cstdio>
#include <filesystem>
#include <system_error>

#include "odometry/trajectory_writer.hpp"
#include "ppcr/io.hpp"

namespace ppcr_synth {

ppcr::Status write_sequence(const std::string& out_dir,
                            const ppcr::synthetic::SequenceOptions& options) {
  const std::filesystem::path dir(out_dir);
  const std::filesystem::path scans = dir / "scans";
  std::error_code error;
  std::filesystem::create_directories(scans, error);
  if (error) {
    return ppcr::Status(ppcr::StatusCode::kIoError,
                        "cannot create '" + scans.string() + "': " + error.message());
  }
  ppcr_odometry::TrajectoryWriter truth;
  ppcr::Status s = truth.open((dir / "ground_truth_kitti.txt").string(),
                              (dir / "ground_truth_tum.txt").string());
  if (!s.ok()) return s;
  Eigen::Isometry3d first_T_world = Eigen::Isometry3d::Identity();
  s = ppcr::synthetic::make_scan_sequence(options, [&](std::size_t i,
                                                       const Eigen::Isometry3d& T_world_sensor,
                                                       const ppcr::PointCloud& scan) {
    char name[64];
    std::snprintf(name, sizeof(name), "scan_%06zu.ply", i);
    ppcr::Status written = ppcr::io::write_cloud((scans / name).string(), scan);
    if (!written.ok()) return written;
    if (i == 0) first_T_world = T_world_sensor.inverse();
    return truth.append(static_cast<double>(i) / options.rate_hz, first_T_world * T_world_sensor);
  });
  const ppcr::Status closed = truth.close();
  return s.ok() ? closed : s;
}

}  // namespace ppcr_synth
