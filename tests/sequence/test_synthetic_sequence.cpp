// Synthetic sequences (ppcr::synthetic::make_scan_sequence): deterministic, a realistic smooth
// motion in the scene's free space, and the scans are what the scanner sees from the poses.
#include <catch2/catch.hpp>
#include <cmath>
#include <vector>

#include "ppcr/synthetic.hpp"

namespace {

using ppcr::synthetic::SceneKind;
using ppcr::synthetic::SequenceOptions;

std::vector<Eigen::Isometry3d> trajectory(const SequenceOptions& options) {
  std::vector<Eigen::Isometry3d> poses;
  const ppcr::Status s = ppcr::synthetic::make_sequence_trajectory(options, &poses);
  INFO(s.to_string());
  REQUIRE(s.ok());
  return poses;
}

double angle_between(const Eigen::Isometry3d& a, const Eigen::Isometry3d& b) {
  return Eigen::AngleAxisd(a.rotation().transpose() * b.rotation()).angle();
}

}  // namespace

TEST_CASE("the room and street paths move at walking and driving speeds, smoothly") {
  for (const SceneKind scene : {SceneKind::kRoom, SceneKind::kStreet}) {
    SequenceOptions options;
    options.scene = scene;
    options.seed = 7;
    options.scans = 200;
    const std::vector<Eigen::Isometry3d> poses = trajectory(options);
    REQUIRE(poses.size() == 200);
    const double mean = ppcr::synthetic::default_speed_mps(scene);
    const double dt = 1.0 / options.rate_hz;
    for (std::size_t i = 1; i < poses.size(); ++i) {
      INFO(ppcr::synthetic::to_string(scene) << " scan " << i);
      const double speed = (poses[i].translation() - poses[i - 1].translation()).norm() / dt;
      // The speed's sine is +-25 % of the mean; the sways add a little.
      CHECK(speed > 0.7 * mean);
      CHECK(speed < 1.3 * mean);
      // At most 0.15 rad (8.6 degrees) per scan: 86 degrees/s, a brisk turn, no jump.
      CHECK(angle_between(poses[i - 1], poses[i]) < 0.15);
      // z stays up within the sways (2 degrees of roll and pitch at most).
      CHECK(poses[i].linear().col(2).z() > std::cos(0.05));
      if (scene == SceneKind::kRoom) {  // inside the furniture-free disc of the room
        CHECK(poses[i].translation().head<2>().norm() < 2.0);
      } else {  // on the road, between the parked cars
        CHECK(std::abs(poses[i].translation().y()) < 3.0);
        CHECK(std::abs(poses[i].translation().x()) < 75.0);
      }
    }
  }
}

TEST_CASE("a sequence is deterministic and a scan does not depend on the others") {
  SequenceOptions options;
  options.scans = 4;
  options.noise_sigma = 0.01;
  options.outlier_fraction = 0.05;
  options.sensor.beams = 8;
  options.sensor.horizontal_steps = 256;
  std::vector<ppcr::PointCloud> first, second;
  auto keep = [](std::vector<ppcr::PointCloud>* scans) {
    return [scans](std::size_t, const Eigen::Isometry3d&, const ppcr::PointCloud& scan) {
      scans->push_back(scan);
      return ppcr::Status::Ok();
    };
  };
  REQUIRE(ppcr::synthetic::make_scan_sequence(options, keep(&first)).ok());
  options.scans = 6;
  REQUIRE(ppcr::synthetic::make_scan_sequence(options, keep(&second)).ok());
  REQUIRE(first.size() == 4);
  REQUIRE(second.size() == 6);
  for (std::size_t i = 0; i < first.size(); ++i) CHECK(first[i] == second[i]);
  CHECK(first[0] != first[1]);
}

TEST_CASE("noise-free scans lie on the scene where the trajectory says") {
  // Scan 0 and scan 5, mapped to the world by their poses, see the same floor (z = 0) and the
  // same walls: their lowest points are on the floor within rounding.
  SequenceOptions options;
  options.scans = 6;
  options.sensor.beams = 16;
  options.sensor.horizontal_steps = 360;
  std::vector<double> lowest;
  const ppcr::Status s = ppcr::synthetic::make_scan_sequence(
      options,
      [&](std::size_t, const Eigen::Isometry3d& T_world_sensor, const ppcr::PointCloud& scan) {
        double z = 1e9;
        for (const Eigen::Vector3d& p : scan) z = std::min(z, (T_world_sensor * p).z());
        lowest.push_back(z);
        return ppcr::Status::Ok();
      });
  REQUIRE(s.ok());
  for (const double z : lowest) CHECK(std::abs(z) < 1e-9);
}

TEST_CASE("bad sequence options are refused naming the option") {
  SequenceOptions options;
  std::vector<Eigen::Isometry3d> poses;
  options.scene = SceneKind::kObjects;
  ppcr::Status s = ppcr::synthetic::make_sequence_trajectory(options, &poses);
  CHECK(s.message().find("SequenceOptions.scene = objects") != std::string::npos);
  options.scene = SceneKind::kStreet;
  options.scans = 400;  // 400 m at 6 m/s and 10 Hz: longer than the road
  s = ppcr::synthetic::make_sequence_trajectory(options, &poses);
  CHECK(s.message().find("SequenceOptions.scans = 400") != std::string::npos);
  options.scans = 1;
  s = ppcr::synthetic::make_sequence_trajectory(options, &poses);
  CHECK(s.message().find("SequenceOptions.scans = 1") != std::string::npos);
  options.scans = 10;
  options.rate_hz = 0.0;
  s = ppcr::synthetic::make_sequence_trajectory(options, &poses);
  CHECK(s.message().find("SequenceOptions.rate_hz = 0") != std::string::npos);
  options.rate_hz = 10.0;
  options.noise_sigma = -1.0;
  s = ppcr::synthetic::make_sequence_trajectory(options, &poses);
  CHECK(s.message().find("SequenceOptions.noise_sigma = -1") != std::string::npos);
}
