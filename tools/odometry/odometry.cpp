// odometry.cpp - the sequence loop.
#include "odometry/odometry.hpp"

#include <chrono>
#include <cstdio>

#include "odometry/local_map.hpp"
#include "odometry/progress.hpp"
#include "ppcr/io.hpp"

namespace ppcr_odometry {
namespace {

ppcr::Status read_scan(const std::vector<std::string>& scans, std::size_t k,
                       const ppcr::io::DepthCamera& camera, ppcr::PointCloud* cloud) {
  const ppcr::Status s = ppcr::io::read_cloud(scans[k], camera, cloud);
  if (s.ok()) return s;
  return ppcr::Status(
      s.code(), "scan " + std::to_string(k) + " (" + scans[k] + ") cannot be read: " + s.message());
}

// Registers `source` onto the map from `guess`; the time covers set_target and align. A map that
// is the previous scan alone was the last align()'s source.
PairOutcome register_scan(PairRegistrar* registrar, const LocalMap& map, bool previous_source,
                          const ppcr::PointCloud& source, const Eigen::Isometry3d& guess,
                          double* time_ms) {
  const auto start = std::chrono::steady_clock::now();
  PairOutcome outcome;
  outcome.result.status = previous_source ? registrar->set_target_to_source(map.cloud())
                                          : registrar->set_target(map.cloud());
  if (outcome.result.status.ok()) outcome = registrar->align(source, guess);
  *time_ms =
      std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
  return outcome;
}

void count_verdict(const PairOutcome& outcome, std::size_t k, const std::string& file, bool quiet,
                   OdometrySummary* summary) {
  if (!outcome.has_measures) return;
  if (outcome.result.quality == ppcr::Quality::kWeak) ++summary->weak;
  if (outcome.result.quality != ppcr::Quality::kFailed) return;
  ++summary->failed;
  if (!quiet) {
    std::fprintf(stderr,
                 "ppcr_odometry: warning: scan %zu (%s): the registration failed its "
                 "quality check: %s\n",
                 k, file.c_str(), outcome.result.quality_reason);
  }
}

}  // namespace

ppcr::Status run_odometry(const std::vector<std::string>& scans, const OdometrySettings& settings,
                          PairRegistrar* registrar, TrajectoryWriter* trajectory, PairLog* log,
                          OdometrySummary* summary) {
  *summary = OdometrySummary();
  Progress progress(scans.size(), settings.quiet);
  LocalMap map(settings.local_map);
  map.set_voxel(settings.map_voxel);
  ppcr::PointCloud scan;
  ppcr::Status s = read_scan(scans, 0, settings.depth_camera, &scan);
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();    // T_first_k
  Eigen::Isometry3d motion = Eigen::Isometry3d::Identity();  // T_{k-1}_k: the last relative motion
  if (s.ok()) s = trajectory->append(settings.times[0], pose);
  if (s.ok()) s = map.add(scan, pose);
  for (std::size_t k = 1; s.ok() && k < scans.size(); ++k) {
    summary->registered = k;
    progress.update(k);
    s = read_scan(scans, k, settings.depth_camera, &scan);
    if (!s.ok()) break;
    double time_ms = 0.0;
    // Constant velocity: the guess for this motion is the previous one.
    const bool previous_source = settings.local_map == 1 && k > 1;
    const PairOutcome outcome =
        register_scan(registrar, map, previous_source, scan, motion, &time_ms);
    const ppcr::Status& registered = outcome.result.status;
    if (!registered.ok()) {
      s = ppcr::Status(registered.code(), "scan " + std::to_string(k) + " (" + scans[k] +
                                              ") cannot be registered: " + registered.message());
      break;
    }
    count_verdict(outcome, k, scans[k], settings.quiet, summary);
    motion = outcome.result.T_target_source;
    pose = pose * motion;
    s = trajectory->append(settings.times[k], pose);
    if (s.ok()) s = log->append(k, scans[k], registrar->name(), outcome, time_ms);
    // The automatic leaf: the target's spacing measured by ppcr, about one scan's density.
    if (!(map.voxel() > 0.0) && outcome.has_measures && outcome.result.target_spacing > 0.0) {
      map.set_voxel(outcome.result.target_spacing);
    }
    if (s.ok()) s = map.add(scan, pose);
  }
  if (s.ok()) summary->registered = scans.size();
  progress.update(summary->registered);
  summary->seconds = progress.seconds();
  summary->scans_per_second = progress.rate(summary->registered);
  return s;
}

}  // namespace ppcr_odometry
