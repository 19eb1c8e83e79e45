// ppcr_odometry - registers a sequence of scans into a trajectory (scan-to-scan, or scan-to-map
// with --local-map N), and evaluates trajectories against a ground truth (--evaluate).
//
//   ppcr_odometry SCAN... [--kitti F] [--tum F] [--pairs F.csv] [--local-map N]
//                 [--map-voxel L] [--rate HZ | --timestamps F] [--method NAME]
//                 [registration flags of ppcr_cli]
//   ppcr_odometry --evaluate GROUND_TRUTH ESTIMATE [--rpe-delta D]
//
// SCAN...: cloud files in the order given, or folders (their cloud files in natural order:
// scan_2 before scan_10; a TUM RGB-D folder's depth/ images). Depth images (.png) are
// back-projected through --depth-intrinsics and --depth-scale. Scan k (k >= 1) is registered onto
// the local map of the last N scans (merged in scan k-1's frame and voxel-filtered; N = 5 by
// default, 1 with a peer method; with N = 1, scan k-1 itself) from the constant-velocity guess (the
// motion found between scans k-2 and k-1), and its pose T_0k = T_0(k-1) T_(k-1)k is written at
// once, one complete line per scan, to the KITTI and TUM files; one row per pair goes to the CSV.
// Exit 0 on success; 1 when a scan cannot be read or registered (the message names it; the files
// hold the poses of the scans before it) or an output cannot be written; 2 for bad usage.
#include <CLI/CLI.hpp>
#include <algorithm>
#include <cstdio>
#include <fstream>
#include <memory>
#include <string>
#include <vector>

#include "common/depth_camera_flags.hpp"
#include "common/openmp_environment.hpp"
#include "common/registration_flags.hpp"
#include "common/usage_error.hpp"
#include "odometry/odometry.hpp"
#include "odometry/pair_registrar.hpp"
#include "odometry/scan_list.hpp"
#include "odometry/trajectory_format.hpp"
#include "odometry/trajectory_metrics.hpp"
#include "ppcr/version.hpp"

namespace {

constexpr const char* kSequenceGroup = "Sequence";
constexpr const char* kOutputGroup = "Input and output";
constexpr double kPi = 3.14159265358979323846;

int fail(int code, const std::string& message) {
  std::fprintf(stderr, "ppcr_odometry: error: %s\n", message.c_str());
  return code;
}

// Scan-to-map by default (docs/BENCHMARK.md, "Sequences": 12-15x lower ATE than scan-to-scan
// for ppcr); a peer scan-to-scan unless asked, as its map needs --map-voxel (ppcr measures the
// point spacing for the leaf).
constexpr int kDefaultLocalMap = 5;

struct Arguments {
  std::vector<std::string> inputs;
  std::string kitti, tum, pairs, timestamps, method = "ppcr";
  std::vector<std::string> evaluate;
  int local_map = kDefaultLocalMap, rpe_delta = 1;
  double map_voxel = 0.0, rate = 10.0;
  bool quiet = false, rate_given = false;
  ppcr::io::DepthCamera depth_camera;
  ppcr_tools::RegistrationFlags flags;
};

void add_arguments(CLI::App& app, Arguments* a) {
  app.add_option("SCAN", a->inputs, "scans: cloud files in order, or folders (natural order)");
  app.add_option("--local-map", a->local_map,
                 "register onto the last N registered scans merged in the previous scan's frame "
                 "(1 = scan-to-scan; default " +
                     std::to_string(kDefaultLocalMap) + " with ppcr, 1 with a peer method)")
      ->check(CLI::Range(1, 1000))
      ->group(kSequenceGroup);
  app.add_option(
         "--map-voxel", a->map_voxel,
         "voxel leaf of the local map, cloud units (default: the target's point spacing "
         "that ppcr measures on the first pair; a peer method with --local-map > 1 needs it)")
      ->check(CLI::PositiveNumber)
      ->group(kSequenceGroup);
  app.add_option("--method", a->method, "registration method: ppcr, or a peer of this build")
      ->check(CLI::IsMember(ppcr_odometry::registrar_names()))
      ->group(kSequenceGroup);
  app.add_option("--kitti", a->kitti, "write the trajectory here, KITTI format (3x4 per line)")
      ->check(ppcr_tools::non_empty())
      ->group(kOutputGroup);
  app.add_option("--tum", a->tum, "write the trajectory here, TUM format (t x y z qx qy qz qw)")
      ->check(ppcr_tools::non_empty())
      ->group(kOutputGroup);
  app.add_option("--pairs", a->pairs, "write the per-pair quality CSV here")
      ->check(ppcr_tools::non_empty())
      ->group(kOutputGroup);
  auto* rate = app.add_option("--rate", a->rate,
                              "scans per second: TUM time = scan index / rate (default 10, unless "
                              "every scan's name is its time, as TUM's 1305031229.528784.png)")
                   ->check(CLI::PositiveNumber)
                   ->group(kOutputGroup);
  app.add_option("--timestamps", a->timestamps,
                 "TUM times from this file instead: one number (seconds) per line, per scan")
      ->check(ppcr_tools::non_empty())
      ->excludes(rate)
      ->group(kOutputGroup);
  app.add_flag("--quiet", a->quiet, "nothing on stderr but errors and warnings")
      ->group(kOutputGroup);
  app.add_option("--evaluate", a->evaluate,
                 "GROUND_TRUTH ESTIMATE: print ATE RMSE and RPE of ESTIMATE (KITTI or TUM; poses "
                 "paired by timestamp when both are TUM files, else by index over the shorter) and "
                 "exit; no scans are registered")
      ->expected(2)
      ->group("Evaluation");
  app.add_option("--rpe-delta", a->rpe_delta, "RPE step, scans (default 1)")
      ->check(CLI::Range(1, 1000000))
      ->group("Evaluation");
  ppcr_tools::add_registration_flags(app, &a->flags);
  ppcr_tools::add_depth_camera_flags(app, &a->depth_camera);
}

// Prints "poses N ate_rmse A rpe_percent P rpe_deg_per_m R distance D rpe_deg_per_step S" on
// stdout.
int evaluate(const Arguments& a) {
  ppcr_odometry::Trajectory truth, estimate;
  ppcr::Status s = ppcr_odometry::read_trajectory(a.evaluate[0], &truth);
  if (s.ok()) s = ppcr_odometry::read_trajectory(a.evaluate[1], &estimate);
  if (!s.ok()) return fail(1, s.message());
  // Both with times (TUM): each estimated pose against the truth at its time; otherwise pose i
  // against pose i, saying so when the lengths differ.
  std::vector<Eigen::Isometry3d> truth_poses = truth.poses, estimate_poses = estimate.poses;
  if (truth.timed && estimate.timed) {
    std::size_t outside = 0;
    s = ppcr_odometry::poses_at_times(truth.times, truth.poses, estimate.times, estimate.poses,
                                      &truth_poses, &estimate_poses, &outside);
    if (!s.ok()) return fail(1, a.evaluate[0] + ": " + s.message());
    std::fprintf(stderr,
                 "ppcr_odometry: paired by timestamp: %zu of %zu estimated poses, the truth "
                 "interpolated at their times (%zu outside its time span left out)\n",
                 estimate_poses.size(), estimate.poses.size(), outside);
  } else if (truth.poses.size() != estimate.poses.size()) {
    std::fprintf(stderr,
                 "ppcr_odometry: the ground truth has %zu poses and the estimate %zu: compared "
                 "the first %zu, pose i with pose i (give both as TUM files to pair them by "
                 "time)\n",
                 truth.poses.size(), estimate.poses.size(),
                 std::min(truth.poses.size(), estimate.poses.size()));
  }
  ppcr_odometry::TrajectoryErrors errors;
  s = ppcr_odometry::trajectory_errors(truth_poses, estimate_poses, a.rpe_delta, &errors);
  if (!s.ok()) return fail(1, s.message());
  std::printf(
      "poses %zu ate_rmse %.6g rpe_percent %.6g rpe_deg_per_m %.6g distance %.6g "
      "rpe_deg_per_step %.6g\n",
      errors.poses, errors.ate_rmse, 100.0 * errors.rpe_translation,
      errors.rpe_rotation * 180.0 / kPi, errors.distance,
      errors.rpe_rotation_per_step * 180.0 / kPi);
  return 0;
}

// The time of each scan: the --timestamps file's numbers; else the scans' names when they are
// times (TUM) and --rate is not given; else index / rate.
ppcr::Status scan_times(const Arguments& a, const std::vector<std::string>& scans,
                        std::vector<double>* times) {
  const std::size_t count = scans.size();
  times->clear();
  if (a.timestamps.empty() && !a.rate_given && ppcr_odometry::times_from_names(scans, times)) {
    if (!a.quiet) std::fprintf(stderr, "ppcr_odometry: times from the scans' names\n");
    return ppcr::Status::Ok();
  }
  if (a.timestamps.empty()) {
    for (std::size_t i = 0; i < count; ++i) times->push_back(static_cast<double>(i) / a.rate);
    return ppcr::Status::Ok();
  }
  std::ifstream file(a.timestamps);
  if (!file) return ppcr::Status(ppcr::StatusCode::kIoError, a.timestamps + ": cannot read");
  std::string line;
  for (int number = 1; std::getline(file, line) && times->size() < count; ++number) {
    if (line.find_first_not_of(" \t\r") == std::string::npos) continue;
    char* end = nullptr;
    const double t = std::strtod(line.c_str(), &end);
    if (end == line.c_str() ||
        line.find_first_not_of(" \t\r", end - line.c_str()) != std::string::npos) {
      return ppcr::Status(ppcr::StatusCode::kParseError, "--timestamps " + a.timestamps + ":" +
                                                             std::to_string(number) + ": '" + line +
                                                             "' is not one number");
    }
    times->push_back(t);
  }
  if (times->size() < count) {
    return ppcr::Status(ppcr::StatusCode::kParseError,
                        "--timestamps " + a.timestamps + ": " + std::to_string(times->size()) +
                            " times for " + std::to_string(count) + " scans");
  }
  return ppcr::Status::Ok();
}

// The method of --method, with its options; the message names the flag at fault.
ppcr::Status make_registrar(const Arguments& a, const ppcr::RegistrationOptions& options,
                            std::unique_ptr<ppcr_odometry::PairRegistrar>* registrar) {
  if (a.method == "ppcr") {
    *registrar = ppcr_odometry::make_ppcr_registrar(options);
    return ppcr::Status::Ok();
  }
  if (options.radius == ppcr::RegistrationOptions::kAutomaticRadius) {
    return ppcr::Status(
        ppcr::StatusCode::kInvalidArgument,
        "--method " + a.method + " needs --radius (only ppcr has an automatic one)");
  }
  if (options.source_voxel == ppcr::RegistrationOptions::kAutomaticVoxel ||
      options.target_voxel == ppcr::RegistrationOptions::kAutomaticVoxel) {
    return ppcr::Status(ppcr::StatusCode::kInvalidArgument,
                        "--method " + a.method + ": --voxel auto is ppcr's; give a leaf");
  }
  if (a.local_map > 1 && !(a.map_voxel > 0.0)) {
    return ppcr::Status(ppcr::StatusCode::kInvalidArgument,
                        "--method " + a.method + " with --local-map " +
                            std::to_string(a.local_map) + " needs --map-voxel");
  }
  *registrar = ppcr_odometry::make_peer_registrar(a.method, options);
  return ppcr::Status::Ok();
}

int run(const Arguments& a, const ppcr::RegistrationOptions& options) {
  std::vector<std::string> scans, skipped;
  ppcr::Status s = ppcr_odometry::list_scans(a.inputs, &scans, &skipped);
  if (!s.ok()) return fail(1, s.message());
  for (const std::string& line : skipped) {
    if (!a.quiet) std::fprintf(stderr, "ppcr_odometry: %s\n", line.c_str());
  }
  if (scans.size() < 2)
    return fail(2, "a sequence needs at least 2 scans; got " + std::to_string(scans.size()));
  ppcr_odometry::OdometrySettings settings;
  settings.local_map = static_cast<std::size_t>(a.local_map);
  settings.map_voxel = a.map_voxel;
  settings.quiet = a.quiet;
  settings.depth_camera = a.depth_camera;
  s = scan_times(a, scans, &settings.times);
  if (!s.ok()) return fail(2, s.message());
  std::unique_ptr<ppcr_odometry::PairRegistrar> registrar;
  s = make_registrar(a, options, &registrar);
  if (!s.ok()) return fail(2, s.message());
  ppcr_odometry::TrajectoryWriter trajectory;
  ppcr_odometry::PairLog log;
  s = trajectory.open(a.kitti, a.tum);
  if (s.ok() && !a.pairs.empty()) s = log.open(a.pairs);
  if (!s.ok()) return fail(1, s.message());

  ppcr_odometry::OdometrySummary summary;
  s = ppcr_odometry::run_odometry(scans, settings, registrar.get(), &trajectory, &log, &summary);
  const ppcr::Status closed = trajectory.close();
  const ppcr::Status log_closed = log.close();
  if (!s.ok() && summary.registered == 0) {  // a failed start leaves no output behind
    for (const std::string* path : {&a.kitti, &a.tum, &a.pairs}) {
      if (!path->empty()) std::remove(path->c_str());
    }
    return fail(1, s.message() + " (no output written)");
  }
  if (!s.ok()) {
    return fail(1, s.message() + " (trajectory of the " + std::to_string(summary.registered) +
                       " scans before it written)");
  }
  if (!closed.ok()) return fail(1, closed.message());
  if (!log_closed.ok()) return fail(1, log_closed.message());
  if (!a.quiet) {
    std::fprintf(stderr,
                 "ppcr_odometry: %zu scans registered by %s in %.1f s: %.2f scans/s (%zu weak, "
                 "%zu failed verdicts)\n",
                 summary.registered, registrar->name().c_str(), summary.seconds,
                 summary.scans_per_second, summary.weak, summary.failed);
  }
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  ppcr_tools::use_passive_openmp_threads(argv);  // idle OpenMP threads sleep
  Arguments a;
  CLI::App app{
      "Registers a sequence of scans into a trajectory (each scan onto the previous one or a "
      "local map, from a constant-velocity guess), or evaluates a trajectory (--evaluate).",
      "ppcr_odometry"};
  add_arguments(app, &a);
  app.set_version_flag("--version", std::string("ppcr_odometry ") + PPCR_VERSION_STRING);
  try {
    app.parse(argc, argv);
  } catch (const CLI::Success& e) {  // --help
    return app.exit(e);
  } catch (const CLI::ParseError& e) {
    return fail(2, ppcr_tools::usage_error(app, e, argc, argv) + " (see --help)");
  }
  if (!a.evaluate.empty()) return evaluate(a);
  a.rate_given = app.get_option("--rate")->count() > 0;
  if (app.get_option("--local-map")->count() == 0 && a.method != "ppcr") a.local_map = 1;
  if (a.kitti.empty() && a.tum.empty()) {
    return fail(2, "no output: give --kitti and/or --tum (see --help)");
  }
  ppcr::RegistrationOptions options;
  const ppcr::Status s = ppcr_tools::to_options(a.flags, &options);
  if (!s.ok()) return fail(2, s.message());
  options.record_history = false;
  return run(a, options);
}
