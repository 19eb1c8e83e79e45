// The objects scene, the depth camera (pinhole, limited field of view), range-proportional noise
// and depth quantisation, each against a closed form: returns on the surfaces, pixel directions
// on the image grid, quantised depths on the levels 1 / (q k) within half a disparity step of the
// true depth, and the empirical noise standard deviation a r at known ranges.
#include <algorithm>
#include <catch2/catch.hpp>
#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

#include "ppcr/synthetic.hpp"
#include "scene_reference.hpp"
#include "synthetic/scene.hpp"

namespace {

using ppcr::PointCloud;
using ppcr::StatusCode;
using ppcr::synthetic::make_scan_pair;
using ppcr::synthetic::Projection;
using ppcr::synthetic::ScanOptions;
using ppcr::synthetic::ScanPair;
using ppcr::synthetic::SceneKind;
using ppcr::synthetic::internal::make_scene;
using ppcr::synthetic::internal::Scene;

const double kPi = std::acos(-1.0);
const double kDegree = kPi / 180.0;

ScanPair scan(const ScanOptions& options) {
  ScanPair pair;
  const ppcr::Status status = make_scan_pair(options, &pair);
  INFO(status.to_string());
  REQUIRE(status.ok());
  return pair;
}

ScanOptions objects(std::uint64_t seed) {
  ScanOptions options;
  options.scene = SceneKind::kObjects;
  options.seed = seed;
  options.translation_m = 0.3;
  options.sensor = ppcr::synthetic::depth_camera();
  return options;
}

std::string message(const ScanOptions& options) {
  ScanPair pair;
  const ppcr::Status status = make_scan_pair(options, &pair);
  CHECK(status.code() == StatusCode::kInvalidArgument);
  return status.message();
}

}  // namespace

TEST_CASE("objects scene: a tabletop of objects, seen from 0.6 to 1.8 m, returns exact",
          "[synthetic][objects]") {
  for (const std::uint64_t seed : {1u, 2u, 3u}) {
    INFO("seed " << seed);
    const ScanPair pair = scan(objects(seed));
    const Scene scene = make_scene(SceneKind::kObjects, seed);
    // A 1.2 x 0.9 m table top with objects at most 30 cm tall.
    CHECK(scene.bounds.min().x() >= -0.6 - 1e-12);
    CHECK(scene.bounds.max().x() <= 0.6 + 1e-12);
    CHECK(scene.bounds.max().y() <= 0.45 + 1e-12);
    CHECK(scene.bounds.min().z() >= -1e-12);
    CHECK(scene.bounds.max().z() <= 0.3);
    CHECK(scene.boxes.size() + scene.spheres.size() + scene.cylinders.size() == 7);

    const synth_test::SceneDistance distance(scene);
    std::size_t on_objects = 0;
    double worst = 0.0;
    for (const Eigen::Vector3d& p : pair.target) {
      const Eigen::Vector3d world = pair.T_world_target * p;
      worst = std::max(worst, distance(world));
      if (world.z() > 0.005) ++on_objects;
      CHECK(p.norm() >= 0.4);  // the camera's min_range
      CHECK(p.norm() < 2.5);   // the table's far corner from the farthest camera
    }
    for (const Eigen::Vector3d& p : pair.source) {
      worst = std::max(worst, distance(pair.T_world_target * (pair.T_target_source * p)));
    }
    CHECK(worst < 1e-9);
    CHECK(pair.target.size() > 10000);
    CHECK(on_objects > pair.target.size() / 10);  // not just the table

    // The exact requested motion; the target camera looks at the table's centre, without roll.
    const Eigen::AngleAxisd motion(pair.T_target_source.linear());
    CHECK(motion.angle() / kDegree == Approx(15.0).epsilon(1e-12));
    CHECK(pair.T_target_source.translation().norm() == Approx(0.3).epsilon(1e-12));
    const Eigen::Vector3d centre(0.0, 0.0, 0.05);
    const Eigen::Vector3d in_target = pair.T_world_target.inverse() * centre;
    CHECK(in_target.x() >= 0.6);  // the sensors stand 0.6 to 1.8 m from the table's centre
    CHECK(in_target.x() <= 1.8);
    CHECK(std::abs(in_target.y()) < 1e-12);
    CHECK(std::abs(in_target.z()) < 1e-12);
    CHECK(std::abs(pair.T_world_target.linear().col(1).z()) < 1e-15);
    // The source turns toward the table: the centre stays within the camera's field of view.
    const Eigen::Vector3d in_source = pair.T_world_source.inverse() * centre;
    CHECK(std::abs(std::atan2(in_source.y(), in_source.x())) < 29.0 * kDegree);
  }
}

TEST_CASE("objects scene: surface samples lie on its surfaces", "[synthetic][objects]") {
  ppcr::synthetic::SurfaceSampleOptions options;
  options.scene = SceneKind::kObjects;
  options.seed = 2;
  options.count = 5000;
  PointCloud samples;
  REQUIRE(ppcr::synthetic::sample_surface(options, &samples).ok());
  REQUIRE(samples.size() == 5000);
  const Scene scene = make_scene(SceneKind::kObjects, 2);  // SceneDistance keeps a reference
  const synth_test::SceneDistance distance(scene);
  double worst = 0.0;
  for (const Eigen::Vector3d& p : samples) worst = std::max(worst, distance(p));
  CHECK(worst < 1e-9);
}

TEST_CASE("depth camera: pixel directions on the image grid, within the field of view",
          "[synthetic][camera]") {
  ScanOptions options = objects(4);
  options.sensor = ppcr::synthetic::depth_camera(64, 48);
  const ScanPair pair = scan(options);
  const double half_width = std::tan(29.0 * kDegree);
  const double low = std::tan(-22.5 * kDegree);
  const double high = std::tan(22.5 * kDegree);
  REQUIRE(pair.target.size() > 500);
  CHECK(pair.target.size() <= 64u * 48u);
  for (const Eigen::Vector3d& p : pair.target) {
    REQUIRE(p.x() > 0.0);
    // Column k at y = (1 - 2 (k + 1/2) / 64) tan(29 deg); row b at z = low + (b + 1/2) / 48 span.
    const double column = (1.0 - p.y() / p.x() / half_width) * 32.0 - 0.5;
    const double row = (p.z() / p.x() - low) / (high - low) * 48.0 - 0.5;
    CHECK(std::abs(column - std::round(column)) < 1e-9);
    CHECK(std::abs(row - std::round(row)) < 1e-9);
    CHECK(std::round(column) >= 0.0);
    CHECK(std::round(column) <= 63.0);
    CHECK(std::round(row) >= 0.0);
    CHECK(std::round(row) <= 47.0);
  }
  // A spinning lidar with a limited field of view spreads its azimuth steps over it: step k of K
  // at (1/2 - (k + 1/2) / K) 90 degrees (every ray returns in the closed room).
  ScanOptions lidar;
  lidar.sensor.horizontal_fov_deg = 90.0;
  const ScanPair partial = scan(lidar);
  REQUIRE(partial.target.size() == 32u * 1024u);
  for (std::size_t i = 0; i < partial.target.size(); i += 97) {
    const Eigen::Vector3d& p = partial.target[i];
    const double k = static_cast<double>(i / 32);
    CHECK(std::atan2(p.y(), p.x()) == Approx((0.5 - (k + 0.5) / 1024.0) * 90.0 * kDegree));
  }
}

TEST_CASE("depth quantisation: depths on the levels 1 / (q k), within half a step of the truth",
          "[synthetic][quantisation]") {
  for (const bool camera : {true, false}) {
    INFO((camera ? "camera" : "lidar"));
    ScanOptions clean = camera ? objects(5) : ScanOptions();
    const double q = camera ? 0.003 : 0.001;
    ScanOptions quantised = clean;
    quantised.depth_quantisation = q;
    const ScanPair exact = scan(clean);
    const ScanPair pair = scan(quantised);
    // Quantisation keeps every return (no depth beyond 2 / q) on its ray.
    REQUIRE(pair.target.size() == exact.target.size());
    std::vector<double> levels;
    double worst_level = 0.0;
    double worst_step = 0.0;
    double worst_direction = 0.0;
    for (std::size_t i = 0; i < pair.target.size(); ++i) {
      const Eigen::Vector3d& p = pair.target[i];
      const Eigen::Vector3d& truth = exact.target[i];
      const double depth = camera ? p.x() : p.norm();
      const double true_depth = camera ? truth.x() : truth.norm();
      const double k = 1.0 / (q * depth);
      worst_level = std::max(worst_level, std::abs(k - std::round(k)));
      // Disparity rounding: |1/d - 1/d_true| <= q / 2, i.e. |d - d_true| <= q d d_true / 2.
      worst_step =
          std::max(worst_step, std::abs(depth - true_depth) / (0.5 * q * depth * true_depth));
      worst_direction = std::max(worst_direction, (p.normalized() - truth.normalized()).norm());
      levels.push_back(depth);
    }
    CHECK(worst_level < 1e-6);
    CHECK(worst_step <= 1.0 + 1e-9);
    CHECK(worst_direction < 1e-12);
    // Adjacent levels near depth d are q d^2 apart: 1/(q k) - 1/(q (k + 1)) = q d_k d_(k+1).
    std::sort(levels.begin(), levels.end());
    std::size_t checked = 0;
    for (std::size_t i = 1; i < levels.size(); ++i) {
      const double a = levels[i - 1];
      const double b = levels[i];
      if (b - a < 1e-12) continue;
      const long ka = std::lround(1.0 / (q * a));
      const long kb = std::lround(1.0 / (q * b));
      if (ka - kb != 1) continue;
      CHECK(b - a == Approx(q * a * b).epsilon(1e-9));
      ++checked;
    }
    CHECK(checked > 20);
  }
}

TEST_CASE("range-proportional noise: standard deviation a r at range r", "[synthetic][noise]") {
  // Noise moves each point along its ray and never changes which rays return, so the noisy and
  // the noise-free scans pair up point by point.
  for (const double a : {0.002, 0.01}) {
    for (const double sigma0 : {0.0, 0.01}) {
      INFO("a " << a << ", sigma " << sigma0);
      ScanOptions clean;  // the room, a spinning lidar: ranges from 0.3 to about 7 m
      clean.seed = 6;
      clean.sensor.horizontal_steps = 2048;
      ScanOptions noisy = clean;
      noisy.noise_per_metre = a;
      noisy.noise_sigma = sigma0;
      const ScanPair exact = scan(clean);
      const ScanPair pair = scan(noisy);
      REQUIRE(pair.source.size() == exact.source.size());
      // Bins of true range: [1, 2), [2, 4), [4, 8) metres.
      const double edges[] = {1.0, 2.0, 4.0, 8.0};
      for (int bin = 0; bin < 3; ++bin) {
        double sum = 0.0;
        double sum2 = 0.0;
        double expected2 = 0.0;
        std::size_t n = 0;
        for (std::size_t i = 0; i < pair.source.size(); ++i) {
          const double r = exact.source[i].norm();
          if (r < edges[bin] || r >= edges[bin + 1]) continue;
          const double error = pair.source[i].norm() - r;
          sum += error;
          sum2 += error * error;
          expected2 += sigma0 * sigma0 + a * a * r * r;
          ++n;
          CHECK((pair.source[i].normalized() - exact.source[i].normalized()).norm() < 1e-12);
        }
        if (n < 2000) continue;
        const double mean = sum / static_cast<double>(n);
        const double rms = std::sqrt(sum2 / static_cast<double>(n));
        const double expected = std::sqrt(expected2 / static_cast<double>(n));
        INFO("bin [" << edges[bin] << ", " << edges[bin + 1] << "): " << n << " points, rms " << rms
                     << ", expected " << expected);
        CHECK(rms == Approx(expected).epsilon(0.05));
        CHECK(std::abs(mean) < 4.0 * expected / std::sqrt(static_cast<double>(n)));
      }
    }
  }
}

TEST_CASE("the new options at their defaults change nothing", "[synthetic][noise]") {
  for (const SceneKind kind : {SceneKind::kRoom, SceneKind::kStreet}) {
    ScanOptions plain;
    plain.scene = kind;
    plain.noise_sigma = 0.01;
    ScanOptions spelled = plain;
    spelled.noise_per_metre = 0.0;
    spelled.depth_quantisation = 0.0;
    spelled.sensor.projection = Projection::kSpinning;
    spelled.sensor.horizontal_fov_deg = 360.0;
    CHECK(scan(plain).source == scan(spelled).source);
  }
}

TEST_CASE("bad sensor and noise options are rejected with the option and its value",
          "[synthetic][noise]") {
  ScanOptions o;
  o.noise_per_metre = -0.1;
  CHECK(message(o) == "ScanOptions.noise_per_metre = -0.1: must be in [0, 1]");
  o = ScanOptions();
  o.depth_quantisation = -1.0;
  CHECK(message(o) == "ScanOptions.depth_quantisation = -1: must be in [0, 1000] (1/metres)");
  o = ScanOptions();
  o.sensor.horizontal_fov_deg = 0.0;
  CHECK(message(o) ==
        "ScanOptions.sensor.horizontal_fov_deg = 0: must be in (0, 360] degrees for a spinning "
        "sensor");
  o = objects(1);
  o.sensor.horizontal_fov_deg = 180.0;
  CHECK(message(o) ==
        "ScanOptions.sensor.horizontal_fov_deg = 180: must be in (0, 180) degrees for a depth "
        "camera (Projection::kPinhole)");
  o = objects(1);
  o.sensor.fov_up_deg = 90.0;
  CHECK(message(o) ==
        "ScanOptions.sensor.fov_up_deg = 90: must be in (-90, 90) degrees for a depth camera "
        "(Projection::kPinhole)");
  o = objects(1);
  o.translation_m = 0.7;
  CHECK(message(o) ==
        "ScanOptions.translation_m = 0.7: must be in [0, 0.6] metres for the objects scene");
}
