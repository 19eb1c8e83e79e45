// ppcr_synth - renders a synthetic scene (room or street) scanned by a simulated lidar from two
// poses, with the exact ground truth, and a problem file in the point clouds registration
// benchmark's format.
//
//   ppcr_synth OUT_DIR [--scene room|street] [--seed N] [--noise SIGMA] [--outliers F]
//              [--rotation DEG] [--translation M] [--beams N] [--steps N] [--fov-up DEG]
//              [--fov-down DEG] [--min-range M] [--max-range M] [--problems N]
//              [--max-problem-rotation DEG] [--max-problem-translation M]
//
// Writes into OUT_DIR (created if missing):
//   source.ply           the source scan, in the source sensor's frame
//   target.ply           the target scan, in the target sensor's frame
//   ground_truth.txt     4x4 (17 significant digits) mapping source.ply into target.ply's frame
//   source_gt_frame.ply  source.ply mapped by the ground truth (the benchmark's common frame)
//   problems.txt         benchmark problems `id source target overlap t1 ... t12` on
//                        source_gt_frame.ply / target.ply (paths relative to OUT_DIR), each with a
//                        random initial misplacement T0 (see --problems)
// Exit 0 on success; 2 with a one-line error on stderr for a bad argument; 1 when a file cannot
// be written.
#include <CLI/CLI.hpp>
#include <Eigen/Geometry>
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

namespace {

constexpr double kPi = 3.14159265358979323846;

int fail(int code, const std::string& message) {
  std::fprintf(stderr, "ppcr_synth: error: %s\n", message.c_str());
  return code;
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
      {"ScanOptions.noise_sigma", "--noise"},
      {"ScanOptions.outlier_fraction", "--outliers"},
      {"ScanOptions.rotation_deg", "--rotation"},
      {"ScanOptions.translation_m", "--translation"},
      {"fov_up_deg", "--fov-up"},  // in the requirement part ("must be below fov_up_deg = 15")
      {"min_range", "--min-range"},
  };
  for (const auto& [field, flag] : kFlags) {
    const std::string name(field);
    for (std::size_t at = message.find(name); at != std::string::npos;
         at = message.find(name, at + std::string(flag).size())) {
      message.replace(at, name.size(), flag);
    }
  }
  return message;
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
                                      double max_rotation_deg, double max_translation) {
  const Eigen::Vector3d axis = uniform->unit_vector();
  const double angle = (*uniform)(0.0, max_rotation_deg) * kPi / 180.0;
  const Eigen::Vector3d direction = uniform->unit_vector();
  const double distance = (*uniform)(0.0, max_translation);
  const Eigen::Matrix3d R = Eigen::AngleAxisd(angle, axis).toRotationMatrix();
  Eigen::Isometry3d T0 = Eigen::Isometry3d::Identity();
  T0.linear() = R;
  T0.translation() = centroid - R * centroid + distance * direction;
  return T0;
}

}  // namespace

int main(int argc, char** argv) {
  using ppcr::synthetic::SceneKind;
  ppcr::synthetic::ScanOptions options;
  std::string out_dir;
  int problems = 10;
  double max_problem_rotation = 30.0;
  double max_problem_translation = 1.0;

  CLI::App app{
      "ppcr_synth: a synthetic scene scanned by a simulated spinning lidar from two poses, with "
      "the exact ground truth (source.ply, target.ply, ground_truth.txt, source_gt_frame.ply, "
      "problems.txt in OUT_DIR)",
      "ppcr_synth"};
  app.add_option("OUT_DIR", out_dir, "output folder (created if missing)")->required();
  std::string scene = "room";
  app.add_option("--scene", scene, "room (12 x 9 x 3 m, indoor) or street (160 m, outdoor)")
      ->check(CLI::IsMember({"room", "street"}))
      ->capture_default_str();
  app.add_option("--seed", options.seed, "seeds the layout, the poses, the noise, the outliers")
      ->check(CLI::Validator(
          [](std::string& value) -> std::string {
            if (!value.empty() && value[0] == '-') return "value " + value + " is negative";
            return "";
          },
          "UINT64"))
      ->capture_default_str();
  app.add_option("--noise", options.noise_sigma,
                 "std of the Gaussian range noise along each ray, metres")
      ->capture_default_str();
  app.add_option("--outliers", options.outlier_fraction,
                 "fraction of each cloud made of uniform outliers (added), [0, 0.95]")
      ->capture_default_str();
  app.add_option("--rotation", options.rotation_deg,
                 "rotation angle between the two sensor poses, degrees, [0, 180]")
      ->capture_default_str();
  app.add_option("--translation", options.translation_m,
                 "distance between the two sensor positions, metres (room <= 3, street <= 30)")
      ->capture_default_str();
  app.add_option("--beams", options.sensor.beams, "lidar vertical channels")->capture_default_str();
  app.add_option("--steps", options.sensor.horizontal_steps, "lidar azimuth steps per revolution")
      ->capture_default_str();
  app.add_option("--fov-up", options.sensor.fov_up_deg, "elevation of the top beam, degrees")
      ->capture_default_str();
  app.add_option("--fov-down", options.sensor.fov_down_deg, "elevation of the bottom beam, degrees")
      ->capture_default_str();
  app.add_option("--min-range", options.sensor.min_range, "closer hits are dropped, metres")
      ->capture_default_str();
  app.add_option("--max-range", options.sensor.max_range, "farther hits are not returned, metres")
      ->capture_default_str();
  app.add_option("--problems", problems, "benchmark problems to write in problems.txt")
      ->check(CLI::Range(0, 1000000))
      ->capture_default_str();
  app.add_option("--max-problem-rotation", max_problem_rotation,
                 "largest initial misplacement rotation of a problem, degrees (about a random "
                 "axis through the source centroid)")
      ->check(CLI::Range(0.0, 180.0))
      ->capture_default_str();
  app.add_option("--max-problem-translation", max_problem_translation,
                 "largest initial misplacement translation of a problem, metres")
      ->check(CLI::Range(0.0, 1e6))
      ->capture_default_str();
  try {
    app.parse(argc, argv);
  } catch (const CLI::CallForHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForAllHelp& e) {
    return app.exit(e);
  } catch (const CLI::ParseError& e) {
    return fail(2, std::string(e.what()) + " (see --help)");
  }

  options.scene = scene == "street" ? SceneKind::kStreet : SceneKind::kRoom;
  ppcr::synthetic::ScanPair pair;
  const ppcr::Status status = ppcr::synthetic::make_scan_pair(options, &pair);
  if (!status.ok()) return fail(2, with_flag_names(status.message()));

  // Benchmark view: the source in the common (target) frame, and the overlap of the pair.
  ppcr::PointCloud source_gt_frame;
  source_gt_frame.reserve(pair.source.size());
  for (const Eigen::Vector3d& p : pair.source) source_gt_frame.push_back(pair.T_target_source * p);
  const ppcr::PointCloud target_returns(
      pair.target.begin(), pair.target.begin() + static_cast<std::ptrdiff_t>(pair.target_returns));
  const double spacing = ppcr_synth::scan_spacing(target_returns);
  const double radius = 3.0 * options.noise_sigma + spacing;
  const double overlap =
      ppcr_synth::overlap_fraction(pair.source, pair.T_target_source, pair.target, radius);

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

  Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
  for (const Eigen::Vector3d& p : source_gt_frame) centroid += p;
  if (!source_gt_frame.empty()) centroid /= static_cast<double>(source_gt_frame.size());
  // Its own stream: SplitMix64-style odd constant mixed into the seed.
  Uniform uniform(options.seed ^ 0x9E3779B97F4A7C15ULL);
  const std::string problems_path = (dir / "problems.txt").string();
  std::ofstream file(problems_path);
  file << "id source target overlap t1 t2 t3 t4 t5 t6 t7 t8 t9 t10 t11 t12\n";
  for (int i = 0; i < problems; ++i) {
    const Eigen::Isometry3d T0 =
        random_misplacement(&uniform, centroid, max_problem_rotation, max_problem_translation);
    file << i << " source_gt_frame.ply target.ply " << std::fixed << std::setprecision(4) << overlap
         << std::defaultfloat << std::setprecision(17);
    for (int r = 0; r < 3; ++r) {
      for (int c = 0; c < 4; ++c) file << ' ' << T0(r, c);
    }
    file << '\n';
  }
  file.close();
  if (!file) return fail(1, "cannot write '" + problems_path + "'");

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
      overlap, radius, spacing);
  std::printf(
      "ppcr_synth: wrote source.ply target.ply ground_truth.txt source_gt_frame.ply "
      "problems.txt (%d problems) in %s\n",
      problems, out_dir.c_str());
  return 0;
}
