// odometry.hpp - a sequence of scans into a trajectory: each scan registered onto the previous
// one (or onto a local map of the last N), from a constant-velocity guess, its pose chained onto
// the previous pose and written at once.
#pragma once

#include <string>
#include <vector>

#include "odometry/pair_log.hpp"
#include "odometry/pair_registrar.hpp"
#include "odometry/trajectory_writer.hpp"
#include "ppcr/io.hpp"
#include "ppcr/status.hpp"

namespace ppcr_odometry {

struct OdometrySettings {
  std::size_t local_map = 1;  // N: scans merged into the target (1 = the previous scan)
  double map_voxel = 0.0;     // the local map's leaf; 0 = the target's spacing (ppcr's measure)
  std::vector<double> times;  // time of each scan, seconds (TUM's first column)
  ppcr::io::DepthCamera depth_camera;  // how depth images (.png) become clouds
  bool quiet = false;
};

struct OdometrySummary {
  std::size_t registered = 0;  // scans with a pose written (the first one included)
  double seconds = 0.0;        // wall time of the whole run
  double scans_per_second = 0.0;
  std::size_t weak = 0, failed = 0;  // ppcr verdicts that were not good
};

/// Runs the sequence `scans` (paths, in order) through `registrar`, writing a pose to
/// `trajectory` and a row to `log` after each scan. Stops at the first scan that cannot be read
/// or registered, with a message naming it; what was written before stays on disk.
ppcr::Status run_odometry(const std::vector<std::string>& scans, const OdometrySettings& settings,
                          PairRegistrar* registrar, TrajectoryWriter* trajectory, PairLog* log,
                          OdometrySummary* summary);

}  // namespace ppcr_odometry
