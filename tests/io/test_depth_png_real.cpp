// The real TUM fr1/rpy depth frames (../shared/data/tum_fr1_rpy, read in place) read as libpng's
// simplified decoder reads them (an independent decoding of the same files); a frame registers
// against a moved copy of itself.
#include <png.h>

#include <algorithm>
#include <catch2/catch.hpp>
#include <filesystem>
#include <string>
#include <vector>

#include "depth_png_util.hpp"
#include "ppcr/io.hpp"
#include "ppcr/metrics.hpp"
#include "ppcr/registration.hpp"
#include "test_data.hpp"

using depth_png_test::check_close;
using depth_png_test::expected_cloud;
using ppcr::PointCloud;
using ppcr::io::DepthCamera;
using ppcr::io::ReadReport;

namespace {

// The 100 frames, in timestamp order (their names).
std::vector<std::string> tum_frames() {
  std::vector<std::string> frames;
  const std::string folder = ppcr_test::data_path("tum_fr1_rpy/depth");
  for (const auto& entry : std::filesystem::directory_iterator(folder)) {
    frames.push_back(entry.path().string());
  }
  std::sort(frames.begin(), frames.end());
  return frames;
}

DepthCamera freiburg1() {  // the folder's README
  DepthCamera camera;
  camera.fx = 517.3;
  camera.fy = 516.5;
  camera.cx = 318.6;
  camera.cy = 255.3;
  return camera;
}

}  // namespace

TEST_CASE("Depth PNG: the real TUM frames read as libpng's simplified decoder reads them",
          "[io][depth][real]") {
  const std::vector<std::string> frames = tum_frames();
  REQUIRE(frames.size() == 100u);
  const DepthCamera camera = freiburg1();
  for (const std::string& path : {frames.front(), frames[50], frames.back()}) {
    INFO(path);
    PointCloud cloud;
    ReadReport report;
    REQUIRE(ppcr::io::read_cloud(path, camera, &cloud, &report).ok());
    // The reference: libpng's simplified API, 16-bit linear gray. It converts no gamma for
    // 16-bit data without a gAMA or sRGB chunk, which these frames lack: were that not so, the
    // point-by-point comparison below would fail.
    png_image image{};
    image.version = PNG_IMAGE_VERSION;
    REQUIRE(png_image_begin_read_from_file(&image, path.c_str()) != 0);
    REQUIRE(image.width == 640u);
    REQUIRE(image.height == 480u);
    image.format = PNG_FORMAT_LINEAR_Y;
    std::vector<png_uint_16> pixels(640 * 480);
    REQUIRE(png_image_finish_read(&image, nullptr, pixels.data(), 0, nullptr) != 0);
    const PointCloud want = [&] {
      std::vector<unsigned> d(pixels.begin(), pixels.end());
      return expected_cloud(d, 640, camera);
    }();
    check_close(cloud, want);
    CHECK(report.points_in_file == cloud.size());
    const double valid = static_cast<double>(cloud.size()) / (640 * 480);
    CHECK(valid > 0.65);
    CHECK(valid < 0.85);
    double z_min = 1e9, z_max = 0;
    for (const Eigen::Vector3d& p : cloud)
      z_min = std::min(z_min, p.z()), z_max = std::max(z_max, p.z());
    CHECK(z_min > 0.6);  // the README: 0.68-9.8 m over the 100 frames
    CHECK(z_max < 10.0);
  }
}

TEST_CASE("Depth PNG: a real frame registers against a moved copy of itself to 1e-4 degrees",
          "[io][depth][real]") {
  PointCloud frame, target;
  REQUIRE(ppcr::io::read_cloud(tum_frames().front(), freiburg1(), &frame).ok());
  for (std::size_t i = 0; i < frame.size(); i += 4) target.push_back(frame[i]);  // test time
  Eigen::Isometry3d T_true = Eigen::Isometry3d::Identity();                      // source -> target
  T_true.rotate(Eigen::AngleAxisd(0.05, Eigen::Vector3d(0.3, -1, 0.2).normalized()));
  T_true.translation() << 0.02, -0.01, 0.03;
  PointCloud source;
  for (const Eigen::Vector3d& p : target) source.push_back(T_true.inverse() * p);
  // The paper's point-to-point model has its optimum at the exact copy. The default plane model's
  // lies a little off it on a real frame: its residuals to the k - 1 other neighbours, along
  // normals fitted to depth quantised in steps, do not cancel (about 1.4e-3 degrees here).
  ppcr::RegistrationOptions options;
  options.error_model = ppcr::ErrorModel::kPoint;
  for (const bool plane : {false, true}) {
    if (plane) options = ppcr::RegistrationOptions();
    const ppcr::RegistrationResult r = ppcr::align(source, target, options);
    INFO((plane ? "plane: " : "point: ")
         << r.status.to_string() << ", " << r.iterations << " iterations");
    REQUIRE(r.status.ok());
    CHECK(ppcr::rotation_error_deg(r.T_target_source, T_true) < (plane ? 3e-3 : 1e-4));
    CHECK(ppcr::translation_error(r.T_target_source, T_true) < (plane ? 1e-4 : 1e-5));
    CHECK(r.quality == ppcr::Quality::kGood);
  }
}
