// KITTI Velodyne scans (.bin): float32 x, y, z, intensity per point, little endian, no header.
// Files are written byte by byte here (not with the library's writer) and read back; the
// writer's bytes are checked against the same layout; a frame registers against a moved copy.
#include <catch2/catch.hpp>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <string>

#include "io_test_util.hpp"
#include "ppcr/io.hpp"
#include "ppcr/metrics.hpp"
#include "ppcr/registration.hpp"

using ppcr::PointCloud;
using ppcr::StatusCode;
using ppcr::io::Format;
using ppcr::io::ReadReport;

namespace {

// One record: x, y, z, intensity as float32, little endian, whatever the host's byte order.
std::string record(float x, float y, float z, float intensity) {
  std::string bytes;
  for (float v : {x, y, z, intensity}) {
    std::uint32_t bits;
    std::memcpy(&bits, &v, sizeof bits);
    for (int i = 0; i < 4; ++i) bytes.push_back(static_cast<char>((bits >> (8 * i)) & 0xff));
  }
  return bytes;
}

}  // namespace

TEST_CASE("KITTI .bin: records read as points, intensity ignored, NaN dropped and counted",
          "[io][kitti]") {
  io_test::TempDir dir;
  const std::string path = dir.file("000000.bin");
  const float nan = std::numeric_limits<float>::quiet_NaN();
  io_test::write_bytes(path, record(1.5f, -2.25f, 0.125f, 0.7f) + record(nan, 0, 0, 0) +
                                 record(-80.0f, 3e-3f, 1.75f, 0.0f));
  PointCloud cloud;
  ReadReport report;
  const ppcr::Status s = ppcr::io::read_cloud(path, &cloud, &report);
  INFO(s.to_string());
  REQUIRE(s.ok());
  CHECK(report.format == Format::kKittiBin);
  CHECK(std::string(ppcr::io::to_string(report.format)) == "kitti_bin");
  CHECK(report.points_in_file == 3u);
  CHECK(report.non_finite_dropped == 1u);
  REQUIRE(cloud.size() == 2u);
  CHECK(cloud[0] == Eigen::Vector3d(1.5, -2.25, 0.125));
  CHECK(cloud[1] == Eigen::Vector3d(-80.0, static_cast<double>(3e-3f), 1.75));
  CHECK(ppcr::io::format_from_extension("scans/000042.BIN") == Format::kKittiBin);
}

TEST_CASE("KITTI .bin: a size that is not whole records is refused, naming the leftover",
          "[io][kitti]") {
  io_test::TempDir dir;
  const std::string path = dir.file("cut.bin");
  io_test::write_bytes(path, record(1, 2, 3, 4) + record(5, 6, 7, 8).substr(0, 7));
  PointCloud cloud;
  const ppcr::Status s = ppcr::io::read_cloud(path, &cloud);
  INFO(s.to_string());
  CHECK(s.code() == StatusCode::kParseError);
  CHECK_THAT(s.message(), Catch::Contains(path) && Catch::Contains("23 bytes") &&
                              Catch::Contains("1 records and 7 bytes left over"));
  CHECK(cloud.empty());
  io_test::write_bytes(path, "");
  CHECK(ppcr::io::read_cloud(path, &cloud).code() == StatusCode::kParseError);
}

TEST_CASE("KITTI .bin: written as float32 records with intensity 0, read back", "[io][kitti]") {
  io_test::TempDir dir;
  const std::string path = dir.file("written.bin");
  const PointCloud cloud = {Eigen::Vector3d(1.5, -2.25, 0.125), Eigen::Vector3d(0.1, 1e6, -3)};
  REQUIRE(ppcr::io::write_cloud(path, cloud).ok());
  const std::string bytes = io_test::read_bytes(path);
  CHECK(bytes == record(1.5f, -2.25f, 0.125f, 0.0f) + record(0.1f, 1e6f, -3.0f, 0.0f));
  PointCloud back;
  REQUIRE(ppcr::io::read_cloud(path, &back).ok());
  REQUIRE(back.size() == 2u);
  CHECK(back[1] == Eigen::Vector3d(static_cast<double>(0.1f), 1e6, -3.0));
  // Beyond float32's range: refused, no file left.
  const ppcr::Status s = ppcr::io::write_cloud(dir.file("huge.bin"), {Eigen::Vector3d(1e39, 0, 0)});
  CHECK(s.code() == StatusCode::kInvalidArgument);
  CHECK_THAT(s.message(), Catch::Contains("float32"));
}

TEST_CASE("KITTI .bin: a frame registers against a moved copy of itself", "[io][kitti]") {
  // A street-like frame, read from a .bin as a user's frame comes.
  const PointCloud frame = io_test::street_frame();
  io_test::TempDir dir;
  REQUIRE(ppcr::io::write_cloud(dir.file("000000.bin"), frame).ok());
  PointCloud target;
  REQUIRE(ppcr::io::read_cloud(dir.file("000000.bin"), &target).ok());
  Eigen::Isometry3d T_true = Eigen::Isometry3d::Identity();  // source -> target
  T_true.rotate(Eigen::AngleAxisd(0.05, Eigen::Vector3d(0.1, 0.2, 1).normalized()));
  T_true.translation() << 0.4, -0.2, 0.05;
  PointCloud source;
  for (const Eigen::Vector3d& p : target) source.push_back(T_true.inverse() * p);
  ppcr::RegistrationOptions options;
  options.radius = 1.0;
  const ppcr::RegistrationResult r = ppcr::align(source, target, options);
  INFO(r.status.to_string() << ", " << r.iterations << " iterations");
  REQUIRE(r.status.ok());
  CHECK(ppcr::rotation_error_deg(r.T_target_source, T_true) < 1e-4);
  CHECK(ppcr::translation_error(r.T_target_source, T_true) < 1e-4);
}
