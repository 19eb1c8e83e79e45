// make_scan_pair(): exactness of the returns and of the ground truth, overlap, determinism,
// noise and outlier statistics, well-posedness of the geometry, and option checks. Surfaces are
// checked with the independent distance functions of scene_reference.hpp.
#include <Eigen/Eigenvalues>
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
using ppcr::synthetic::ScanOptions;
using ppcr::synthetic::ScanPair;
using ppcr::synthetic::SceneKind;
using ppcr::synthetic::internal::make_scene;
using ppcr::synthetic::internal::Scene;

const double kPi = std::acos(-1.0);

ScanPair scan(const ScanOptions& options) {
  ScanPair pair;
  const ppcr::Status status = make_scan_pair(options, &pair);
  INFO(status.to_string());
  REQUIRE(status.ok());
  return pair;
}

ScanOptions options_for(SceneKind kind, std::uint64_t seed) {
  ScanOptions options;
  options.scene = kind;
  options.seed = seed;
  return options;
}

/// Fraction of `source` points (mapped by T) that have a `target` point within radius.
double overlap(const PointCloud& source, const Eigen::Isometry3d& T, const PointCloud& target,
               double radius) {
  const synth_test::RadiusGrid grid(target, radius);
  std::size_t covered = 0;
  for (const Eigen::Vector3d& p : source) covered += grid.has_neighbour(T * p) ? 1 : 0;
  return static_cast<double>(covered) / static_cast<double>(source.size());
}

/// Outward unit normal of the scene surface nearest to p (p on a surface).
Eigen::Vector3d surface_normal(const Scene& scene, const Eigen::Vector3d& p) {
  double best = std::numeric_limits<double>::infinity();
  Eigen::Vector3d normal = Eigen::Vector3d::UnitZ();
  for (const auto& r : scene.rectangles) {
    const double d = synth_test::surface_distance(p, r);
    if (d < best) best = d, normal = r.u.cross(r.v).normalized();
  }
  for (const auto& b : scene.boxes) {
    const double d = synth_test::surface_distance(p, b);
    if (d >= best) continue;
    best = d;
    const Eigen::Vector3d local = b.axes.transpose() * (p - b.center);
    int face = 0;  // the face whose plane p is on: largest |local_i| - h_i
    for (int i = 1; i < 3; ++i) {
      if (std::abs(local[i]) - b.half_extents[i] > std::abs(local[face]) - b.half_extents[face]) {
        face = i;
      }
    }
    normal = (local[face] > 0 ? 1.0 : -1.0) * b.axes.col(face);
  }
  for (const auto& s : scene.spheres) {
    const double d = synth_test::surface_distance(p, s);
    if (d < best) best = d, normal = (p - s.center).normalized();
  }
  for (const auto& c : scene.cylinders) {
    const double d = synth_test::surface_distance(p, c);
    if (d >= best) continue;
    best = d;
    const double s = (p - c.base).dot(c.axis);
    if (std::abs(s) < 1e-9) {
      normal = -c.axis;
    } else if (std::abs(s - c.height) < 1e-9) {
      normal = c.axis;
    } else {
      normal = (p - c.base - s * c.axis).normalized();
    }
  }
  return normal;
}

}  // namespace

TEST_CASE("noise-free returns lie exactly on the scene's surfaces", "[synthetic][scan]") {
  for (const SceneKind kind : {SceneKind::kRoom, SceneKind::kStreet}) {
    for (const std::uint64_t seed : {1u, 2u}) {
      const ScanPair pair = scan(options_for(kind, seed));
      const Scene scene = make_scene(kind, seed);
      const synth_test::SceneDistance distance(scene);
      INFO(ppcr::synthetic::to_string(kind) << " seed " << seed);
      REQUIRE(pair.source_returns == pair.source.size());
      REQUIRE(pair.target_returns == pair.target.size());
      double worst_source = 0.0;
      for (const Eigen::Vector3d& p : pair.source) {
        // Through the ground truth: source frame -> target frame -> scene.
        const Eigen::Vector3d world = pair.T_world_target * (pair.T_target_source * p);
        worst_source = std::max(worst_source, distance(world));
      }
      double worst_target = 0.0;
      for (const Eigen::Vector3d& p : pair.target) {
        worst_target = std::max(worst_target, distance(pair.T_world_target * p));
      }
      CHECK(worst_source < 1e-9);
      CHECK(worst_target < 1e-9);
    }
  }
}

TEST_CASE("the ground truth is exact and has the requested motion", "[synthetic][scan]") {
  for (const SceneKind kind : {SceneKind::kRoom, SceneKind::kStreet}) {
    ScanOptions options = options_for(kind, 5);
    options.rotation_deg = 17.0;
    options.translation_m = 2.5;
    const ScanPair pair = scan(options);
    const Eigen::Matrix3d R = pair.T_target_source.linear();
    CHECK((R.transpose() * R - Eigen::Matrix3d::Identity()).norm() < 1e-14);
    CHECK(R.determinant() == Approx(1.0).margin(1e-14));
    const Eigen::AngleAxisd angle_axis(R);
    CHECK(angle_axis.angle() * 180.0 / kPi == Approx(17.0).epsilon(1e-12));
    CHECK(pair.T_target_source.translation().norm() == Approx(2.5).epsilon(1e-14));
    // The axis is tilted from the vertical by at most 10 degrees (and not exactly vertical).
    CHECK(std::abs(angle_axis.axis().z()) >= std::cos(10.0 * kPi / 180.0) - 1e-12);
    CHECK(std::abs(angle_axis.axis().z()) < 1.0 - 1e-9);
    const Eigen::Isometry3d composed = pair.T_world_target * pair.T_target_source;
    CHECK((composed.matrix() - pair.T_world_source.matrix()).norm() < 1e-12);
    // The target sensor is level (spin axis vertical).
    CHECK((pair.T_world_target.linear().col(2) - Eigen::Vector3d::UnitZ()).norm() < 1e-15);
  }
}

TEST_CASE("without motion the two scans coincide", "[synthetic][scan]") {
  ScanOptions options = options_for(SceneKind::kRoom, 3);
  options.rotation_deg = 0.0;
  options.translation_m = 0.0;
  const ScanPair pair = scan(options);
  CHECK(pair.T_target_source.matrix() == Eigen::Matrix4d::Identity());
  CHECK(pair.source == pair.target);
}

TEST_CASE("default scans have realistic sizes and ranges", "[synthetic][scan]") {
  for (const SceneKind kind : {SceneKind::kRoom, SceneKind::kStreet}) {
    const ScanOptions options = options_for(kind, 1);
    const ScanPair pair = scan(options);
    INFO(ppcr::synthetic::to_string(kind));
    for (const PointCloud* cloud : {&pair.source, &pair.target}) {
      CHECK(cloud->size() >= 10000);
      CHECK(cloud->size() <= 60000);
      double nearest = 1e300;
      double farthest = 0.0;
      for (const Eigen::Vector3d& p : *cloud) {
        nearest = std::min(nearest, p.norm());
        farthest = std::max(farthest, p.norm());
      }
      CHECK(nearest >= options.sensor.min_range);
      CHECK(farthest < options.sensor.max_range);
    }
  }
  // Range-dependent density: a scan of the same room with twice the beams has ~twice the points.
  ScanOptions dense = options_for(SceneKind::kRoom, 1);
  dense.sensor.beams = 64;
  CHECK(scan(dense).target.size() == 2 * scan(options_for(SceneKind::kRoom, 1)).target.size());
}

TEST_CASE("the scans overlap partially, less when the sensor moves farther", "[synthetic][scan]") {
  const double radius = 0.2;  // about twice the gap between scan lines at 5 m
  for (const SceneKind kind : {SceneKind::kRoom, SceneKind::kStreet}) {
    const ScanPair pair = scan(options_for(kind, 1));
    const double o = overlap(pair.source, pair.T_target_source, pair.target, radius);
    INFO(ppcr::synthetic::to_string(kind) << " overlap " << o);
    CHECK(o > 0.3);
    CHECK(o < 0.95);
    // With a wrong transform (identity) the overlap collapses: the check can fail.
    CHECK(overlap(pair.source, Eigen::Isometry3d::Identity(), pair.target, radius) < o - 0.2);
  }
  ScanOptions near = options_for(SceneKind::kStreet, 1);
  ScanOptions far = near;
  far.translation_m = 25.0;
  const ScanPair a = scan(near);
  const ScanPair b = scan(far);
  const double overlap_near = overlap(a.source, a.T_target_source, a.target, radius);
  const double overlap_far = overlap(b.source, b.T_target_source, b.target, radius);
  INFO("street overlap at 1.5 m: " << overlap_near << ", at 25 m: " << overlap_far);
  CHECK(overlap_far < overlap_near - 0.2);
  CHECK(overlap_far > 0.05);
}

TEST_CASE("scans are deterministic per seed", "[synthetic][scan]") {
  ScanOptions options = options_for(SceneKind::kStreet, 11);
  options.noise_sigma = 0.01;
  options.outlier_fraction = 0.2;
  const ScanPair a = scan(options);
  const ScanPair b = scan(options);
  CHECK(a.source == b.source);  // bit-identical (operator== compares doubles exactly)
  CHECK(a.target == b.target);
  CHECK(a.T_target_source.matrix() == b.T_target_source.matrix());

  ScanOptions other = options;
  other.seed = 12;
  const ScanPair c = scan(other);
  CHECK(c.source != a.source);
  CHECK(c.T_target_source.matrix() != a.T_target_source.matrix());

  // Noise and outliers have their own streams: the poses, the rays that return and the returns'
  // directions do not change with them.
  ScanOptions clean = options;
  clean.noise_sigma = 0.0;
  clean.outlier_fraction = 0.0;
  const ScanPair d = scan(clean);
  CHECK(d.T_target_source.matrix() == a.T_target_source.matrix());
  REQUIRE(d.source_returns == a.source_returns);
  REQUIRE(d.target_returns == a.target_returns);
  for (std::size_t i = 0; i < d.source_returns; i += 97) {
    CHECK(d.source[i].normalized().isApprox(a.source[i].normalized(), 1e-12));
  }
}

TEST_CASE("noise_draw: the same scans, rays and poses with new noise, 0 the seed's own draw",
          "[synthetic][scan]") {
  ScanOptions options = options_for(SceneKind::kRoom, 5);
  options.noise_sigma = 0.01;
  options.outlier_fraction = 0.1;
  const ScanPair seed_draw = scan(options);
  options.noise_draw = 0;
  CHECK(scan(options).source == seed_draw.source);
  options.noise_draw = 1;
  const ScanPair first = scan(options);
  options.noise_draw = 2;
  const ScanPair second = scan(options);
  CHECK(first.T_target_source.matrix() == seed_draw.T_target_source.matrix());
  REQUIRE(first.source_returns == seed_draw.source_returns);
  REQUIRE(second.target_returns == seed_draw.target_returns);
  std::size_t moved = 0;
  for (std::size_t i = 0; i < first.source_returns; ++i) {
    // Each return stays on its ray, at another range.
    CHECK(first.source[i].normalized().isApprox(seed_draw.source[i].normalized(), 1e-12));
    moved += first.source[i] != second.source[i] && first.source[i] != seed_draw.source[i];
  }
  CHECK(moved == first.source_returns);
  REQUIRE(first.target.size() > first.target_returns);  // outliers follow the returns
  CHECK(first.target[first.target_returns] != second.target[second.target_returns]);
}

TEST_CASE("range noise has the requested standard deviation", "[synthetic][scan]") {
  // A sensor looking down to 60 degrees sees the floor of the room's free middle, where nothing
  // but the floor is (the furniture keeps 2.3 m away from the room's axis).
  for (const double sigma : {0.005, 0.02}) {
    ScanOptions options = options_for(SceneKind::kRoom, 4);
    options.noise_sigma = sigma;
    options.translation_m = 1.0;
    options.sensor.fov_down_deg = -60.0;
    const ScanPair pair = scan(options);
    for (const bool source : {true, false}) {
      const PointCloud& cloud = source ? pair.source : pair.target;
      const Eigen::Isometry3d& world_T_sensor = source ? pair.T_world_source : pair.T_world_target;
      const Eigen::Vector3d origin = world_T_sensor.translation();
      double sum = 0.0;
      double sum2 = 0.0;
      std::size_t n = 0;
      for (const Eigen::Vector3d& p : cloud) {
        const Eigen::Vector3d world = world_T_sensor * p;
        if (std::abs(world.z()) > 0.3 || world.head<2>().norm() > 1.9) continue;
        // Error along the ray: measured range minus the range of the floor along that ray.
        const Eigen::Vector3d direction = (world - origin).normalized();
        const double true_range = -origin.z() / direction.z();
        const double error = p.norm() - true_range;
        sum += error;
        sum2 += error * error;
        ++n;
      }
      REQUIRE(n > 1000);
      const double mean = sum / static_cast<double>(n);
      const double stddev = std::sqrt(sum2 / static_cast<double>(n) - mean * mean);
      INFO("sigma " << sigma << ": measured " << stddev << " over " << n << " floor points");
      CHECK(stddev == Approx(sigma).epsilon(0.1));
      CHECK(std::abs(mean) < 0.1 * sigma);
    }
  }
}

TEST_CASE("outliers make up the requested fraction of each cloud", "[synthetic][scan]") {
  for (const SceneKind kind : {SceneKind::kRoom, SceneKind::kStreet}) {
    for (const double fraction : {0.3, 0.5}) {
      ScanOptions options = options_for(kind, 6);
      options.outlier_fraction = fraction;
      const ScanPair pair = scan(options);
      const Scene scene = make_scene(kind, 6);
      const synth_test::SceneDistance distance(scene);
      for (const bool source : {true, false}) {
        const PointCloud& cloud = source ? pair.source : pair.target;
        const std::size_t returns = source ? pair.source_returns : pair.target_returns;
        const Eigen::Isometry3d& world_T_sensor =
            source ? pair.T_world_source : pair.T_world_target;
        const auto expected_outliers = static_cast<std::size_t>(
            std::llround(static_cast<double>(returns) * fraction / (1.0 - fraction)));
        REQUIRE(cloud.size() == returns + expected_outliers);
        std::size_t off_surface = 0;
        std::size_t off_surface_in_returns = 0;
        std::size_t outside_bounds = 0;
        for (std::size_t i = 0; i < cloud.size(); ++i) {
          const Eigen::Vector3d world = world_T_sensor * cloud[i];
          const bool off = distance(world) > 1e-6;
          off_surface += off ? 1 : 0;
          if (i < returns) off_surface_in_returns += off ? 1 : 0;
          if (scene.bounds.exteriorDistance(world) > 1e-9) ++outside_bounds;
        }
        const double measured =
            static_cast<double>(off_surface) / static_cast<double>(cloud.size());
        INFO(ppcr::synthetic::to_string(kind)
             << " requested " << fraction << " measured " << measured);
        CHECK(measured == Approx(fraction).margin(0.005));
        CHECK(off_surface_in_returns == 0);
        CHECK(outside_bounds == 0);
      }
    }
  }
}

TEST_CASE("the default scenes constrain all six degrees of freedom", "[synthetic][scan]") {
  // Point-to-plane information matrix H = sum J J^T, J = [p x n; n] (points centred and scaled
  // to unit RMS radius so that rotations and translations are comparable): a direction of motion
  // that the geometry does not constrain (a corridor's axis, a plane's in-plane motion) is an
  // eigenvector of H with eigenvalue ~0.
  for (const SceneKind kind : {SceneKind::kRoom, SceneKind::kStreet}) {
    const ScanPair pair = scan(options_for(kind, 1));
    const Scene scene = make_scene(kind, 1);
    PointCloud world;
    for (const Eigen::Vector3d& p : pair.target) world.push_back(pair.T_world_target * p);
    Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
    for (const Eigen::Vector3d& p : world) centroid += p;
    centroid /= static_cast<double>(world.size());
    double rms = 0.0;
    for (const Eigen::Vector3d& p : world) rms += (p - centroid).squaredNorm();
    rms = std::sqrt(rms / static_cast<double>(world.size()));
    Eigen::Matrix<double, 6, 6> H = Eigen::Matrix<double, 6, 6>::Zero();
    for (const Eigen::Vector3d& p : world) {
      const Eigen::Vector3d n = surface_normal(scene, p);
      Eigen::Matrix<double, 6, 1> J;
      J << ((p - centroid) / rms).cross(n), n;
      H += J * J.transpose();
    }
    const Eigen::SelfAdjointEigenSolver<Eigen::Matrix<double, 6, 6>> solver(H);
    const double ratio = solver.eigenvalues()(0) / solver.eigenvalues()(5);
    INFO(ppcr::synthetic::to_string(kind) << " eigenvalue ratio " << ratio);
    CHECK(ratio > 0.01);
  }
}

TEST_CASE("bad options are rejected with the option and its value", "[synthetic][scan]") {
  struct Case {
    std::string name;
    ScanOptions options;
    std::string expected;  // substring of the message
  };
  std::vector<Case> cases;
  auto add = [&](const std::string& name, const std::string& expected, auto edit) {
    ScanOptions options;
    edit(options);
    cases.push_back({name, options, expected});
  };
  add("negative noise", "noise_sigma = -0.5", [](ScanOptions& o) { o.noise_sigma = -0.5; });
  add("nan noise", "noise_sigma = nan", [](ScanOptions& o) { o.noise_sigma = std::nan(""); });
  add("outliers 1", "outlier_fraction = 1", [](ScanOptions& o) { o.outlier_fraction = 1.0; });
  add("outliers < 0", "outlier_fraction = -0.1", [](ScanOptions& o) { o.outlier_fraction = -0.1; });
  add("rotation", "rotation_deg = 200", [](ScanOptions& o) { o.rotation_deg = 200; });
  add("room translation", "translation_m = 5", [](ScanOptions& o) { o.translation_m = 5; });
  add("street translation", "translation_m = 31", [](ScanOptions& o) {
    o.scene = SceneKind::kStreet;
    o.translation_m = 31;
  });
  add("zero beams", "beams = 0", [](ScanOptions& o) { o.sensor.beams = 0; });
  add("zero steps", "horizontal_steps = 0", [](ScanOptions& o) { o.sensor.horizontal_steps = 0; });
  add("too many rays", "beams * horizontal_steps", [](ScanOptions& o) {
    o.sensor.beams = 1024;
    o.sensor.horizontal_steps = 36000;
  });
  add("fov order", "fov_down_deg = 20", [](ScanOptions& o) { o.sensor.fov_down_deg = 20; });
  add("fov range", "fov_up_deg = 95", [](ScanOptions& o) { o.sensor.fov_up_deg = 95; });
  add("min range", "min_range = -1", [](ScanOptions& o) { o.sensor.min_range = -1; });
  add("max range", "max_range = 0.1", [](ScanOptions& o) { o.sensor.max_range = 0.1; });
  add("scene kind", "scene = 7", [](ScanOptions& o) { o.scene = static_cast<SceneKind>(7); });
  for (const Case& c : cases) {
    INFO(c.name);
    ScanPair pair;
    pair.source.push_back(Eigen::Vector3d(1, 2, 3));
    const ppcr::Status status = make_scan_pair(c.options, &pair);
    CHECK(status.code() == StatusCode::kInvalidArgument);
    INFO(status.message());
    CHECK(status.message().find(c.expected) != std::string::npos);
    CHECK(pair.source.size() == 1);  // the output is left untouched
  }
  CHECK(make_scan_pair(ScanOptions(), nullptr).code() == StatusCode::kInvalidArgument);
  // Limits are inclusive.
  ScanOptions edge;
  edge.outlier_fraction = 0.95;
  edge.rotation_deg = 180.0;
  edge.translation_m = ppcr::synthetic::max_translation_m(SceneKind::kRoom);
  edge.sensor.beams = 1;
  edge.sensor.horizontal_steps = 360;
  ScanPair pair;
  CHECK(make_scan_pair(edge, &pair).ok());
}
