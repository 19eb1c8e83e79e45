// ppcr_cli on scans as sensors write them: a real TUM depth image (16-bit PNG, with the camera's
// intrinsics) and a KITTI .bin frame, each registered against a moved copy of itself, the error
// read from the JSON's ground-truth fields.
#include <catch2/catch.hpp>
#include <cmath>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>

#include "io/io_test_util.hpp"
#include "ppcr/io.hpp"
#include "test_data.hpp"
#include "tools/cli_run.hpp"

using cli_test::kDir;
using cli_test::run_cli;

namespace {

const Eigen::Isometry3d& T_true() {  // source -> target
  static const Eigen::Isometry3d T = [] {
    Eigen::Isometry3d M = Eigen::Isometry3d::Identity();
    M.rotate(Eigen::AngleAxisd(0.05, Eigen::Vector3d(0.3, -1, 0.2).normalized()));
    M.translation() << 0.02, -0.01, 0.03;
    return M;
  }();
  return T;
}

// Writes `points` moved by T_true()^-1 to `path`, and T_true() to gt.txt; returns ppcr_cli's
// JSON for `source` onto `target` with `flags` and the ground truth.
nlohmann::json register_moved_copy(const ppcr::PointCloud& points, const std::string& source,
                                   const std::string& target, const std::string& flags) {
  ppcr::PointCloud moved;
  for (const Eigen::Vector3d& p : points) moved.push_back(T_true().inverse() * p);
  REQUIRE(ppcr::io::write_cloud(source, moved).ok());
  REQUIRE(ppcr::io::write_transform(kDir + "/gt.txt", T_true()).ok());
  const cli_test::Run r = run_cli("'" + source + "' '" + target + "' " + flags +
                                  " --json --quiet --ground-truth '" + kDir + "/gt.txt'");
  INFO(r.err);
  REQUIRE(r.status == 0);
  return nlohmann::json::parse(r.out);
}

}  // namespace

TEST_CASE("ppcr_cli: a TUM depth image registers against a moved copy to 1e-4 degrees",
          "[cli][depth]") {
  std::string frame;
  for (const auto& e :
       std::filesystem::directory_iterator(ppcr_test::data_path("tum_fr1_rpy/depth"))) {
    if (frame.empty() || e.path().string() < frame) frame = e.path().string();
  }
  REQUIRE_FALSE(frame.empty());
  const std::string intrinsics = " --depth-intrinsics 517.3 516.5 318.6 255.3";
  ppcr::io::DepthCamera camera;
  camera.fx = 517.3, camera.fy = 516.5, camera.cx = 318.6, camera.cy = 255.3;
  ppcr::PointCloud points, every_fourth;
  REQUIRE(ppcr::io::read_cloud(frame, camera, &points).ok());
  for (std::size_t i = 0; i < points.size(); i += 4) every_fourth.push_back(points[i]);
  std::filesystem::create_directories(kDir);
  // The paper's point model: its optimum is the exact copy (tests/io/test_depth_png_real.cpp).
  const nlohmann::json j = register_moved_copy(every_fourth, kDir + "/moved.ply", frame,
                                               intrinsics + " --error-model point");
  CHECK(j["rotation_error_deg"].get<double>() < 1e-4);
  CHECK(j["translation_error"].get<double>() < 1e-5);
  CHECK(j["quality"] == "good");
  // Three intrinsics instead of four: a usage error naming the flag.
  const cli_test::Run bad = run_cli("'" + frame + "' '" + frame + "' --depth-intrinsics 1 2 3");
  CHECK(bad.status == 2);
  CHECK_THAT(bad.err, Catch::Contains("--depth-intrinsics"));
  const cli_test::Run nan_scale = run_cli("'" + frame + "' '" + frame + "' --depth-scale nan");
  CHECK(nan_scale.status == 2);
  CHECK_THAT(nan_scale.err, Catch::Contains("--depth-scale: must be finite and > 0, got nan"));
}

TEST_CASE("ppcr_cli: a KITTI .bin frame registers against a moved copy to 1e-4 degrees",
          "[cli][kitti]") {
  const ppcr::PointCloud frame = io_test::street_frame();
  std::filesystem::create_directories(kDir);
  const std::string target = kDir + "/000001.bin";
  REQUIRE(ppcr::io::write_cloud(target, frame).ok());
  ppcr::PointCloud stored;  // as float32, what the file holds
  REQUIRE(ppcr::io::read_cloud(target, &stored).ok());
  const nlohmann::json j = register_moved_copy(stored, kDir + "/000000.bin", target, "--radius 1");
  CHECK(j["rotation_error_deg"].get<double>() < 1e-4);
  CHECK(j["translation_error"].get<double>() < 1e-4);
}
