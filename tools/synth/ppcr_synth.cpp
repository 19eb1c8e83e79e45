// ppcr_synth - renders a synthetic scene (room, street or tabletop objects) scanned by a
// simulated lidar or depth camera from two poses, with the exact ground truth, and a problem file
// in the point clouds registration benchmark's format.
//
//   ppcr_synth OUT_DIR [--scene room|street|objects] [--seed N] [--noise SIGMA]
//              [--noise-per-metre A] [--depth-quantisation Q] [--outliers F]
//              [--rotation DEG] [--translation M] [--sensor lidar|camera] [--beams N] [--steps N]
//              [--fov-up DEG] [--fov-down DEG] [--hfov DEG] [--min-range M] [--max-range M]
//              [--problems N] [--min-problem-rotation DEG] [--max-problem-rotation DEG]
//              [--max-problem-translation M]
//   ppcr_synth OUT_DIR --sequence N [--scene room|street] [--rate HZ] [--speed M/S] [--seed N]
//              [the noise, outlier and sensor flags above]
//
// --sensor camera starts from ppcr::synthetic::depth_camera() (320 x 240 pixels, 58 x 45 degrees,
// 0.4 to 4.5 m); --beams (rows), --steps (columns), --fov-*, --hfov and --*-range override it.
// --translation defaults to 0.3 m for the objects scene.
//
// Writes into OUT_DIR (created if missing):
//   source.ply           the source scan, in the source sensor's frame
//   target.ply           the target scan, in the target sensor's frame
//   ground_truth.txt     4x4 (17 significant digits) mapping source.ply into target.ply's frame
//   source_gt_frame.ply  source.ply mapped by the ground truth (the benchmark's common frame)
//   problems.txt         benchmark problems `id source target overlap t1 ... t12` on
//                        source_gt_frame.ply / target.ply (paths relative to OUT_DIR), each with a
//                        random initial misplacement T0 (see --problems)
// With --sequence N, a sensor swept along a smooth path through the room or the street (see
// ppcr::synthetic::SequenceOptions) takes N scans at --rate; OUT_DIR gets instead:
//   scans/scan_000000.ply ...  the scans, each in its sensor's frame (natural order = scan order)
//   ground_truth_kitti.txt     the exact pose of every scan in the first scan's frame, 3x4 a line
//   ground_truth_tum.txt       the same as "t x y z qx qy qz qw", t = index / rate
// Exit 0 on success; 2 with a one-line error on stderr for a bad argument; 1 when a file cannot
// be written.
#include <CLI/CLI.hpp>
#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <limits>
#include <random>
#include <string>
#include <utility>
#include <vector>

#include "overlap.hpp"
#include "ppcr/io.hpp"
#include "ppcr/synthetic.hpp"
#include "sequence_output.hpp"

namespace {

constexpr double kPi = 3.14159265358979323846;

int fail(int code, const std::string& message) {
  std::fprintf(stderr, "ppcr_synth: error: %s\n", message.c_str());
  return code;
}

/// Replaces every (field, flag) pair's field in message by the flag, in the table's order.
template <std::size_t N>
std::string rename(std::string message, const std::pair<const char*, const char*> (&table)[N]) {
  for (const auto& [field, flag] : table) {
    const std::string name(field);
    for (std::size_t at = message.find(name); at != std::string::npos;
         at = message.find(name, at + std::string(flag).size())) {
      message.replace(at, name.size(), flag);
    }
  }
  return message;
}

/// The library names ScanOptions fields in its messages; say which flags they come from.
std::string with_flag_names(std::string message) {
  static const std::pair<const char*, const char*> kFlags[] = {
      {"ScanOptions.sensor.beams * horizontal_steps", "--beams * --steps"},
      {"ScanOptions.sensor.beams", "--beams"},
      {"ScanOptions.sensor.horizontal_steps", "--steps"},
      {"ScanOptions.sensor.fov_up_deg", "--fov-up"},
      {"ScanOptions.sensor.fov_down_deg", "--fov-down"},
      {"ScanOptions.sensor.min_range", "--min-range"},
      {"ScanOptions.sensor.max_range", "--max-range"},
      {"ScanOptions.sensor.horizontal_fov_deg", "--hfov"},
      {"ScanOptions.noise_sigma", "--noise"},
      {"ScanOptions.noise_per_metre", "--noise-per-metre"},
      {"ScanOptions.depth_quantisation", "--depth-quantisation"},
      {"ScanOptions.outlier_fraction", "--outliers"},
      {"ScanOptions.rotation_deg", "--rotation"},
      {"ScanOptions.translation_m", "--translation"},
      {"fov_up_deg", "--fov-up"},  // in the requirement part ("must be below fov_up_deg = 15")
      {"min_range", "--min-range"},
  };
  return rename(message, kFlags);
}

/// Uniform doubles from std::mt19937_64 (53 bits), as the library does: the same numbers with
/// any standard library.
class Uniform {
 public:
  explicit Uniform(std::uint64_t seed) : engine_(seed) {}
  double operator()(double lo, double hi) {
    return lo + (hi - lo) * static_cast<double>(engine_() >> 11) * 0x1.0p-53;
  }
  Eigen::Vector3d unit_vector() {
    const double z = (*this)(-1.0, 1.0);
    const double azimuth = (*this)(0.0, 2.0 * kPi);
    const double rho = std::sqrt(std::max(0.0, 1.0 - z * z));
    return Eigen::Vector3d(rho * std::cos(azimuth), rho * std::sin(azimuth), z);
  }

 private:
  std::mt19937_64 engine_;
};

/// The benchmark's local perturbation: rotation of uniform magnitude in [0, max_rotation_deg]
/// about a uniformly random axis through `centroid`, then a translation of uniform magnitude in
/// [0, max_translation] in a uniformly random direction.
Eigen::Isometry3d random_misplacement(Uniform* uniform, const Eigen::Vector3d& centroid,
                                      double min_rotation_deg, double max_rotation_deg,
                                      double max_translation) {
  const Eigen::Vector3d axis = uniform->unit_vector();
  const double angle = (*uniform)(min_rotation_deg, max_rotation_deg) * kPi / 180.0;
  const Eigen::Vector3d direction = uniform->unit_vector();
  const double distance = (*uniform)(0.0, max_translation);
  const Eigen::Matrix3d R = Eigen::AngleAxisd(angle, axis).toRotationMatrix();
  Eigen::Isometry3d T0 = Eigen::Isometry3d::Identity();
  T0.linear() = R;
  T0.translation() = centroid - R * centroid + distance * direction;
  return T0;
}

/// The command line's values. The sensor flags go to `given` and only override the --sensor
/// preset when given (the lidar preset takes them all), so their options are kept to ask.
struct CommandLine {
  std::string out_dir;
  std::string scene = "room";
  std::string sensor = "lidar";
  int problems = 10;
  std::size_t sequence = 0;  // --sequence: scans of a sequence (0: a pair)
  double rate = 10.0;
  double speed = 0.0;
  double min_problem_rotation = 0.0;
  double max_problem_rotation = 30.0;
  double max_problem_translation = 1.0;
  ppcr::synthetic::ScanOptions options;  // the scan flags; scene and sensor set by scan_options()
  ppcr::synthetic::SensorModel given;    // the flags' values, applied over the --sensor preset
  CLI::Option* translation = nullptr;
  CLI::Option* beams = nullptr;
  CLI::Option* steps = nullptr;
  CLI::Option* fov_up = nullptr;
  CLI::Option* fov_down = nullptr;
  CLI::Option* hfov = nullptr;
  CLI::Option* min_range = nullptr;
  CLI::Option* max_range = nullptr;
};

// CLI11 reads a negative number into an unsigned integer as a huge one: refuse it (UINT64).
CLI::Validator unsigned_integer() {
  return CLI::Validator(
      [](std::string& value) -> std::string {
        if (!value.empty() && value[0] == '-') return "value " + value + " is negative";
        return "";
      },
      "UINT64");
}

/// OUT_DIR, --scene, --sensor and the scan's --seed, --noise-draw, noise, outlier and motion flags.
void add_scan_options(CLI::App* app, CommandLine* line) {
  ppcr::synthetic::ScanOptions& options = line->options;
  app->add_option("OUT_DIR", line->out_dir, "output folder (created if missing)")->required();
  app->add_option("--scene", line->scene,
                  "room (12 x 9 x 3 m, indoor), street (160 m, outdoor) or objects (a 1.2 x 0.9 m "
                  "tabletop seen from 0.6-1.8 m)")
      ->check(CLI::IsMember({"room", "street", "objects"}))
      ->capture_default_str();
  app->add_option("--sensor", line->sensor,
                  "lidar (spinning, 360 degrees) or camera (depth camera: pinhole 320 x 240 "
                  "pixels, 58 x 45 degrees, 0.4-4.5 m; the flags below override it)")
      ->check(CLI::IsMember({"lidar", "camera"}))
      ->capture_default_str();
  app->add_option("--noise-draw", options.noise_draw,
                  "another draw of the noise and outliers of the same scans (0: the seed's)")
      ->check(unsigned_integer())
      ->capture_default_str();
  app->add_option("--seed", options.seed, "seeds the layout, the poses, the noise, the outliers")
      ->check(unsigned_integer())
      ->capture_default_str();
  app->add_option("--noise", options.noise_sigma,
                  "std of the Gaussian range noise along each ray, metres")
      ->capture_default_str();
  app->add_option("--noise-per-metre", options.noise_per_metre,
                  "range-proportional noise: std sqrt(noise^2 + (A range)^2) along each ray, "
                  "[0, 1]")
      ->capture_default_str();
  app->add_option("--depth-quantisation", options.depth_quantisation,
                  "depth-camera quantisation Q, 1/metres: depths become 1 / (Q k), k integer "
                  "(steps of about Q depth^2; 0.003 is about a Kinect's; 0 = off)")
      ->capture_default_str();
  app->add_option("--outliers", options.outlier_fraction,
                  "fraction of each cloud made of uniform outliers (added), [0, 0.95]")
      ->capture_default_str();
  app->add_option("--rotation", options.rotation_deg,
                  "rotation angle between the two sensor poses, degrees, [0, 180]")
      ->capture_default_str();
  line->translation =
      app->add_option("--translation", options.translation_m,
                      "distance between the two sensor positions, metres (room <= 3, street <= "
                      "30, objects <= 0.6; default 0.3 for objects)")
          ->capture_default_str();
}

/// The sensor flags (--beams ... --max-range), into line->given.
void add_sensor_options(CLI::App* app, CommandLine* line) {
  ppcr::synthetic::SensorModel& given = line->given;
  line->beams = app->add_option("--beams", given.beams, "lidar vertical channels (camera: rows)")
                    ->capture_default_str();
  line->steps = app->add_option("--steps", given.horizontal_steps,
                                "lidar azimuth steps per revolution (camera: columns)")
                    ->capture_default_str();
  line->fov_up = app->add_option("--fov-up", given.fov_up_deg,
                                 "elevation of the top beam (camera: of the top edge), degrees")
                     ->capture_default_str();
  line->fov_down =
      app->add_option("--fov-down", given.fov_down_deg,
                      "elevation of the bottom beam (camera: of the bottom edge), degrees")
          ->capture_default_str();
  line->hfov = app->add_option("--hfov", given.horizontal_fov_deg,
                               "horizontal field of view, degrees: (0, 360] for the lidar (360 = "
                               "a full turn), (0, 180) for the camera (58)")
                   ->capture_default_str();
  line->min_range = app->add_option("--min-range", given.min_range,
                                    "closer hits are dropped, metres (camera 0.4)")
                        ->capture_default_str();
  line->max_range = app->add_option("--max-range", given.max_range,
                                    "farther hits are not returned, metres (camera 4.5)")
                        ->capture_default_str();
}

/// The flags of problems.txt (--problems, --max-problem-*).
void add_problem_options(CLI::App* app, CommandLine* line) {
  app->add_option("--problems", line->problems, "benchmark problems to write in problems.txt")
      ->check(CLI::Range(0, 1000000))
      ->capture_default_str();
  app->add_option("--min-problem-rotation", line->min_problem_rotation,
                  "smallest initial misplacement rotation of a problem, degrees (at most "
                  "--max-problem-rotation)")
      ->check(CLI::Range(0.0, 180.0))
      ->capture_default_str();
  app->add_option("--max-problem-rotation", line->max_problem_rotation,
                  "largest initial misplacement rotation of a problem, degrees (about a random "
                  "axis through the source centroid)")
      ->check(CLI::Range(0.0, 180.0))
      ->capture_default_str();
  app->add_option("--max-problem-translation", line->max_problem_translation,
                  "largest initial misplacement translation of a problem, metres")
      ->check(CLI::Range(0.0, 1e6))
      ->capture_default_str();
}

/// The flags of a sequence (--sequence, --rate, --speed).
void add_sequence_options(CLI::App* app, CommandLine* line) {
  app->add_option("--sequence", line->sequence,
                  "write a sequence of this many scans along a path (room or street) instead of "
                  "a pair: scans/scan_NNNNNN.ply, ground_truth_kitti.txt, ground_truth_tum.txt")
      ->check(CLI::Range(2, 1000000));
  app->add_option("--rate", line->rate, "--sequence: scans per second")
      ->check(CLI::Range(1e-3, 1000.0))
      ->capture_default_str();
  app->add_option("--speed", line->speed,
                  "--sequence: mean speed along the path, m/s (default: room 1, street 6)")
      ->check(CLI::Range(0.0, 50.0));
}

/// The library's ScanOptions from the parsed flags: the scene, the objects scene's default
/// translation, and the --sensor preset overridden by the sensor flags given (the lidar preset
/// is the flags' defaults, so it takes them all).
ppcr::synthetic::ScanOptions scan_options(const CommandLine& line) {
  using ppcr::synthetic::SceneKind;
  ppcr::synthetic::ScanOptions options = line.options;
  const ppcr::synthetic::SensorModel& given = line.given;
  options.scene = line.scene == "street"    ? SceneKind::kStreet
                  : line.scene == "objects" ? SceneKind::kObjects
                                            : SceneKind::kRoom;
  if (options.scene == SceneKind::kObjects && line.translation->count() == 0) {
    options.translation_m = 0.3;
  }
  const bool lidar = line.sensor == "lidar";
  if (line.sensor == "camera") options.sensor = ppcr::synthetic::depth_camera();
  if (lidar || line.beams->count() > 0) options.sensor.beams = given.beams;
  if (lidar || line.steps->count() > 0) options.sensor.horizontal_steps = given.horizontal_steps;
  if (lidar || line.fov_up->count() > 0) options.sensor.fov_up_deg = given.fov_up_deg;
  if (lidar || line.fov_down->count() > 0) options.sensor.fov_down_deg = given.fov_down_deg;
  if (lidar || line.hfov->count() > 0) {
    options.sensor.horizontal_fov_deg = given.horizontal_fov_deg;
  }
  if (lidar || line.min_range->count() > 0) options.sensor.min_range = given.min_range;
  if (lidar || line.max_range->count() > 0) options.sensor.max_range = given.max_range;
  return options;
}

/// The library names SequenceOptions fields in its messages: the sequence's own with their
/// flags, the others as with_flag_names does for ScanOptions.
std::string sequence_flag_names(std::string message) {
  static const std::pair<const char*, const char*> kFlags[] = {
      {"SequenceOptions.scans", "--sequence"},
      {"SequenceOptions.speed_mps", "--speed"},
      {"SequenceOptions.rate_hz", "--rate"},
      {"SequenceOptions.scene", "--scene"},
      {"speed_mps", "--speed"},
      {"rate_hz", "--rate"},
      {"SequenceOptions.", "ScanOptions."},
  };
  return with_flag_names(rename(message, kFlags));
}

/// --sequence: the sequence's options from the scan flags; writes it. Returns the exit code.
int run_sequence(const CLI::App& app, const CommandLine& line) {
  for (const char* flag : {"--rotation", "--translation", "--problems", "--min-problem-rotation",
                           "--max-problem-rotation", "--max-problem-translation"}) {
    if (app.get_option(flag)->count() > 0) {
      return fail(2, std::string(flag) + " does not apply to --sequence (see --help)");
    }
  }
  const ppcr::synthetic::ScanOptions scan = scan_options(line);
  ppcr::synthetic::SequenceOptions options;
  options.scene = scan.scene;
  options.seed = scan.seed;
  options.sensor = scan.sensor;
  options.noise_sigma = scan.noise_sigma;
  options.noise_per_metre = scan.noise_per_metre;
  options.depth_quantisation = scan.depth_quantisation;
  options.outlier_fraction = scan.outlier_fraction;
  options.scans = line.sequence;
  options.rate_hz = line.rate;
  options.speed_mps = line.speed;
  const ppcr::Status status = ppcr_synth::write_sequence(line.out_dir, options);
  if (!status.ok()) {
    const std::string message = sequence_flag_names(status.message());
    return fail(status.code() == ppcr::StatusCode::kIoError ? 1 : 2, message);
  }
  std::printf(
      "ppcr_synth: %s sequence, seed %llu: %zu scans at %g Hz in %s/scans, ground truth "
      "in ground_truth_kitti.txt and ground_truth_tum.txt\n",
      ppcr::synthetic::to_string(options.scene), static_cast<unsigned long long>(options.seed),
      options.scans, options.rate_hz, line.out_dir.c_str());
  return 0;
}

/// The overlap of the pair and how it was measured.
struct OverlapEstimate {
  double spacing = 0.0;  // the target scan's point spacing, metres
  double radius = 0.0;   // a source point overlaps with a target point within it, metres
  double fraction = 0.0;
};

/// The fraction of source points with a target return within 3 x noise + spacing (plus the
/// range-dependent noise and quantisation at the target's median range when they are on).
OverlapEstimate estimate_overlap(const ppcr::synthetic::ScanPair& pair,
                                 const ppcr::synthetic::ScanOptions& options) {
  OverlapEstimate estimate;
  const ppcr::PointCloud target_returns(
      pair.target.begin(), pair.target.begin() + static_cast<std::ptrdiff_t>(pair.target_returns));
  estimate.spacing = ppcr_synth::scan_spacing(target_returns);
  estimate.radius = 3.0 * options.noise_sigma + estimate.spacing;
  if (options.noise_per_metre > 0.0 || options.depth_quantisation > 0.0) {
    // The range-dependent terms at the target's median range.
    std::vector<double> ranges;
    ranges.reserve(target_returns.size());
    for (const Eigen::Vector3d& p : target_returns) ranges.push_back(p.norm());
    double median = 0.0;
    if (!ranges.empty()) {
      std::nth_element(ranges.begin(), ranges.begin() + ranges.size() / 2, ranges.end());
      median = ranges[ranges.size() / 2];
    }
    estimate.radius +=
        3.0 * options.noise_per_metre * median + options.depth_quantisation * median * median;
  }
  estimate.fraction =
      ppcr_synth::overlap_fraction(pair.source, pair.T_target_source, pair.target, estimate.radius);
  return estimate;
}

/// Creates OUT_DIR and writes the three clouds and ground_truth.txt into it. Returns 0, or the
/// exit code after reporting the error.
int write_scans(const std::string& out_dir, const ppcr::synthetic::ScanPair& pair,
                const ppcr::PointCloud& source_gt_frame) {
  std::error_code error;
  std::filesystem::create_directories(out_dir, error);
  if (error) return fail(1, "cannot create '" + out_dir + "': " + error.message());
  const std::filesystem::path dir(out_dir);
  const std::pair<const char*, const ppcr::PointCloud*> clouds[] = {
      {"source.ply", &pair.source},
      {"target.ply", &pair.target},
      {"source_gt_frame.ply", &source_gt_frame}};
  for (const auto& [name, cloud] : clouds) {
    const ppcr::Status written = ppcr::io::write_cloud((dir / name).string(), *cloud);
    if (!written.ok()) return fail(1, written.message());
  }
  const ppcr::Status gt_written =
      ppcr::io::write_transform((dir / "ground_truth.txt").string(), pair.T_target_source);
  if (!gt_written.ok()) return fail(1, gt_written.message());
  return 0;
}

/// Writes OUT_DIR/problems.txt: line->problems random misplacements about the centroid of
/// source_gt_frame, each with the pair's overlap. Returns 0, or the exit code after reporting
/// the error.
int write_problems(const CommandLine& line, std::uint64_t seed,
                   const ppcr::PointCloud& source_gt_frame, double overlap) {
  Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
  for (const Eigen::Vector3d& p : source_gt_frame) centroid += p;
  if (!source_gt_frame.empty()) centroid /= static_cast<double>(source_gt_frame.size());
  // Its own stream: SplitMix64-style odd constant mixed into the seed.
  Uniform uniform(seed ^ 0x9E3779B97F4A7C15ULL);
  const std::string problems_path = (std::filesystem::path(line.out_dir) / "problems.txt").string();
  std::ofstream file(problems_path);
  file << "id source target overlap t1 t2 t3 t4 t5 t6 t7 t8 t9 t10 t11 t12\n";
  for (int i = 0; i < line.problems; ++i) {
    const Eigen::Isometry3d T0 =
        random_misplacement(&uniform, centroid, line.min_problem_rotation,
                            line.max_problem_rotation, line.max_problem_translation);
    file << i << " source_gt_frame.ply target.ply " << std::fixed << std::setprecision(4) << overlap
         << std::defaultfloat << std::setprecision(17);
    for (int r = 0; r < 3; ++r) {
      for (int c = 0; c < 4; ++c) file << ' ' << T0(r, c);
    }
    file << '\n';
  }
  file.close();
  if (!file) return fail(1, "cannot write '" + problems_path + "'");
  return 0;
}

/// The summary on stdout: the clouds' sizes, the ground-truth motion, the overlap, the files.
void print_summary(const CommandLine& line, const ppcr::synthetic::ScanOptions& options,
                   const ppcr::synthetic::ScanPair& pair, const OverlapEstimate& overlap) {
  std::printf(
      "ppcr_synth: %s scene, seed %llu: source %zu points (%zu outliers), target %zu points (%zu "
      "outliers)\n",
      ppcr::synthetic::to_string(options.scene), static_cast<unsigned long long>(options.seed),
      pair.source.size(), pair.source.size() - pair.source_returns, pair.target.size(),
      pair.target.size() - pair.target_returns);
  const Eigen::AngleAxisd motion(pair.T_target_source.linear());
  std::printf("ppcr_synth: ground truth: rotation %.3f deg, translation %.3f m\n",
              motion.angle() * 180.0 / kPi, pair.T_target_source.translation().norm());
  std::printf(
      "ppcr_synth: overlap %.4f (source points with a target point within %.3f m = 3 x "
      "noise + spacing %.3f m)\n",
      overlap.fraction, overlap.radius, overlap.spacing);
  std::printf(
      "ppcr_synth: wrote source.ply target.ply ground_truth.txt source_gt_frame.ply "
      "problems.txt (%d problems) in %s\n",
      line.problems, line.out_dir.c_str());
}

}  // namespace

int main(int argc, char** argv) {
  CommandLine line;
  CLI::App app{
      "ppcr_synth: a synthetic scene scanned by a simulated lidar or depth camera from two poses, "
      "with the exact ground truth (source.ply, target.ply, ground_truth.txt, "
      "source_gt_frame.ply, problems.txt in OUT_DIR)",
      "ppcr_synth"};
  add_scan_options(&app, &line);
  add_sensor_options(&app, &line);
  add_problem_options(&app, &line);
  add_sequence_options(&app, &line);
  try {
    app.parse(argc, argv);
  } catch (const CLI::CallForHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForAllHelp& e) {
    return app.exit(e);
  } catch (const CLI::ParseError& e) {
    return fail(2, std::string(e.what()) + " (see --help)");
  }
  if (line.min_problem_rotation > line.max_problem_rotation) {
    return fail(2, "--min-problem-rotation " + std::to_string(line.min_problem_rotation) +
                       " exceeds --max-problem-rotation " +
                       std::to_string(line.max_problem_rotation));
  }

  if (line.sequence > 0) return run_sequence(app, line);

  const ppcr::synthetic::ScanOptions options = scan_options(line);
  ppcr::synthetic::ScanPair pair;
  const ppcr::Status status = ppcr::synthetic::make_scan_pair(options, &pair);
  if (!status.ok()) return fail(2, with_flag_names(status.message()));

  // Benchmark view: the source in the common (target) frame, and the overlap of the pair.
  ppcr::PointCloud source_gt_frame;
  source_gt_frame.reserve(pair.source.size());
  for (const Eigen::Vector3d& p : pair.source) source_gt_frame.push_back(pair.T_target_source * p);
  const OverlapEstimate overlap = estimate_overlap(pair, options);

  if (const int code = write_scans(line.out_dir, pair, source_gt_frame); code != 0) return code;
  if (const int code = write_problems(line, options.seed, source_gt_frame, overlap.fraction);
      code != 0) {
    return code;
  }
  print_summary(line, options, pair, overlap);
  return 0;
}
