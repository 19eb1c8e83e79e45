// KITTI and TUM trajectory files (tools/odometry/trajectory_format, trajectory_writer): written
// line by line, read back exactly; malformed files refused with file and line.
#include <catch2/catch.hpp>
#include <filesystem>
#include <fstream>
#include <string>

#include "odometry/trajectory_format.hpp"
#include "odometry/trajectory_writer.hpp"

namespace {

std::string path_of(const std::string& name) {
  std::filesystem::create_directories(PPCR_SEQUENCE_TEST_DIR);
  return (std::filesystem::path(PPCR_SEQUENCE_TEST_DIR) / name).string();
}

std::vector<Eigen::Isometry3d> turning_poses(int n) {
  std::vector<Eigen::Isometry3d> poses;
  for (int i = 0; i < n; ++i) {
    Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
    T.linear() = Eigen::AngleAxisd(0.3 * i + 0.1, Eigen::Vector3d(1.0, -2.0, 0.5 * i).normalized())
                     .toRotationMatrix();
    T.translation() = Eigen::Vector3d(0.1 * i, -0.2 * i * i, 1.0 / (i + 1));
    poses.push_back(T);
  }
  return poses;
}

}  // namespace

TEST_CASE("KITTI and TUM files read back the poses written") {
  const std::vector<Eigen::Isometry3d> poses = turning_poses(7);
  ppcr_odometry::TrajectoryWriter writer;
  const std::string kitti = path_of("format.kitti"), tum = path_of("format.tum");
  REQUIRE(writer.open(kitti, tum).ok());
  for (std::size_t i = 0; i < poses.size(); ++i) REQUIRE(writer.append(0.1 * i, poses[i]).ok());
  REQUIRE(writer.close().ok());

  ppcr_odometry::Trajectory k, t;
  REQUIRE(ppcr_odometry::read_trajectory(kitti, &k).ok());
  REQUIRE(ppcr_odometry::read_trajectory(tum, &t).ok());
  REQUIRE(k.poses.size() == poses.size());
  REQUIRE(t.poses.size() == poses.size());
  for (std::size_t i = 0; i < poses.size(); ++i) {
    CHECK((k.poses[i].matrix() - poses[i].matrix()).norm() == 0.0);  // 17 digits: exact
    CHECK((t.poses[i].matrix() - poses[i].matrix()).norm() < 1e-14);
    CHECK(t.times[i] == Approx(0.1 * i));
  }
  // Each TUM line: 8 numbers, unit quaternion; each KITTI line: 12, orthonormal rotation.
  std::ifstream tum_file(tum);
  std::string line;
  while (std::getline(tum_file, line)) {
    std::istringstream fields(line);
    std::vector<double> v;
    for (double x; fields >> x;) v.push_back(x);
    REQUIRE(v.size() == 8);
    CHECK(std::abs(std::sqrt(v[4] * v[4] + v[5] * v[5] + v[6] * v[6] + v[7] * v[7]) - 1.0) < 1e-15);
  }
  for (const Eigen::Isometry3d& T : k.poses) {
    CHECK((T.linear().transpose() * T.linear() - Eigen::Matrix3d::Identity()).norm() < 1e-12);
  }
}

TEST_CASE("a rotation printed with 6 digits is read as the nearest rotation") {
  const std::string rounded = path_of("rounded.kitti");
  const double c = std::cos(0.3), s = std::sin(0.3);
  char line[256];
  std::snprintf(line, sizeof(line), "%.6g %.6g 0 1 %.6g %.6g 0 2 0 0 1 3\n", c, -s, s, c);
  std::ofstream(rounded) << line;
  ppcr_odometry::Trajectory t;
  REQUIRE(ppcr_odometry::read_trajectory(rounded, &t).ok());
  const Eigen::Matrix3d R = t.poses[0].linear();
  CHECK((R.transpose() * R - Eigen::Matrix3d::Identity()).norm() < 1e-14);
  CHECK(std::abs(std::atan2(R(1, 0), R(0, 0)) - 0.3) < 1e-6);
}

TEST_CASE("malformed trajectories are refused naming the file and the line") {
  const std::string bad = path_of("bad.kitti");
  std::ofstream(bad) << "1 0 0 0 0 1 0 0 0 0 1 0\n1 0 0 0 0 1 0 0 0 0 1\n";
  ppcr_odometry::Trajectory t;
  ppcr::Status s = ppcr_odometry::read_trajectory(bad, &t);
  REQUIRE(!s.ok());
  CHECK(s.message().find(bad + ":2:") != std::string::npos);

  const std::string skew = path_of("skew.kitti");
  std::ofstream(skew) << "1 0.01 0 0 0 1 0 0 0 0 1 0\n";
  s = ppcr_odometry::read_trajectory(skew, &t);
  REQUIRE(!s.ok());
  CHECK(s.message().find("orthonormal") != std::string::npos);

  const std::string long_q = path_of("long_q.tum");
  std::ofstream(long_q) << "0 1 2 3 0 0 0 1.001\n";
  s = ppcr_odometry::read_trajectory(long_q, &t);
  REQUIRE(!s.ok());
  CHECK(s.message().find(long_q + ":1:") != std::string::npos);
}
