// Depth images (16-bit grayscale PNG) read as clouds. Images are written here with libpng's own
// writer and checked pixel by pixel against the pinhole back-projection; damaged and foreign PNGs
// are refused with a message. The real TUM frames: test_depth_png_real.cpp.
#include <png.h>

#include <catch2/catch.hpp>
#include <filesystem>
#include <limits>
#include <string>
#include <vector>

#include "ppcr/io.hpp"

using ppcr::PointCloud;
using ppcr::StatusCode;
using ppcr::io::DepthCamera;
using ppcr::io::Format;
using ppcr::io::ReadReport;

#include "depth_png_util.hpp"

using depth_png_test::check_close;
using depth_png_test::expected_cloud;
using depth_png_test::test_depths;
using depth_png_test::write_png;

TEST_CASE("Depth PNG: every pixel with depth back-projected through the camera, holes skipped",
          "[io][depth]") {
  io_test::TempDir dir;
  const std::string path = dir.file("frame.PNG");
  const std::vector<unsigned> depths = test_depths();
  REQUIRE(write_png(path, 7, 5, 16, PNG_COLOR_TYPE_GRAY, depths));
  CHECK(ppcr::io::format_from_extension(path) == Format::kDepthPng);

  SECTION("TUM's default camera") {
    PointCloud cloud;
    ReadReport report;
    const ppcr::Status s = ppcr::io::read_cloud(path, &cloud, &report);
    INFO(s.to_string());
    REQUIRE(s.ok());
    CHECK(report.format == Format::kDepthPng);
    CHECK(std::string(ppcr::io::to_string(report.format)) == "depth_png");
    CHECK(report.points_in_file == 33u);
    check_close(cloud, expected_cloud(depths, 7, DepthCamera()));
    CHECK(cloud.back().z() == Approx(65535 / 5000.0));
  }
  SECTION("a camera of the user's, millimetres") {
    DepthCamera camera;
    camera.fx = 600.5;
    camera.fy = 580.25;
    camera.cx = 3.2;
    camera.cy = 2.1;
    camera.depth_scale = 1000.0;
    PointCloud cloud;
    REQUIRE(ppcr::io::read_cloud(path, camera, &cloud).ok());
    check_close(cloud, expected_cloud(depths, 7, camera));
  }
  SECTION("found by its signature when the name has no extension") {
    const std::string bare = dir.file("frame_without_extension");
    std::filesystem::copy_file(path, bare);
    PointCloud cloud;
    ReadReport report;
    REQUIRE(ppcr::io::read_cloud(bare, &cloud, &report).ok());
    CHECK(report.format == Format::kDepthPng);
    CHECK(cloud.size() == 33u);
  }
}

TEST_CASE("Depth PNG: other images, damaged files and bad cameras are refused with a message",
          "[io][depth]") {
  io_test::TempDir dir;
  PointCloud cloud;
  SECTION("an 8-bit grayscale image") {
    const std::string path = dir.file("gray8.png");
    REQUIRE(write_png(path, 4, 3, 8, PNG_COLOR_TYPE_GRAY, std::vector<unsigned>(12, 7)));
    const ppcr::Status s = ppcr::io::read_cloud(path, &cloud);
    CHECK(s.code() == StatusCode::kParseError);
    CHECK_THAT(s.message(), Catch::Contains(path) && Catch::Contains("16-bit grayscale") &&
                                Catch::Contains("8-bit grayscale"));
  }
  SECTION("a colour image") {
    const std::string path = dir.file("rgb.png");
    REQUIRE(write_png(path, 4, 3, 8, PNG_COLOR_TYPE_RGB, std::vector<unsigned>(36, 9)));
    const ppcr::Status s = ppcr::io::read_cloud(path, &cloud);
    CHECK(s.code() == StatusCode::kParseError);
    CHECK_THAT(s.message(), Catch::Contains("8-bit RGB"));
  }
  SECTION("an image without any depth") {
    const std::string path = dir.file("empty.png");
    REQUIRE(write_png(path, 4, 3, 16, PNG_COLOR_TYPE_GRAY, std::vector<unsigned>(12, 0)));
    const ppcr::Status s = ppcr::io::read_cloud(path, &cloud);
    CHECK(s.code() == StatusCode::kEmptyCloud);
    CHECK_THAT(s.message(), Catch::Contains("12 pixels all read 0"));
  }
  SECTION("a file cut short, a damaged byte, not a PNG at all") {
    const std::string good = dir.file("good.png");
    REQUIRE(write_png(good, 7, 5, 16, PNG_COLOR_TYPE_GRAY, test_depths()));
    const std::string bytes = io_test::read_bytes(good);
    for (std::size_t keep : {std::size_t{4}, std::size_t{20}, std::size_t{40}, bytes.size() - 13}) {
      const std::string path = dir.file("cut.png");
      io_test::write_bytes(path, bytes.substr(0, keep));
      const ppcr::Status s = ppcr::io::read_cloud(path, &cloud);
      INFO(keep << " bytes: " << s.to_string());
      CHECK(s.code() == StatusCode::kParseError);
      CHECK_THAT(s.message(), Catch::Contains(path));
      CHECK(cloud.empty());
    }
    std::string damaged = bytes;
    damaged[damaged.size() / 2] ^= 0x5a;  // inside the image data: a CRC or zlib error
    io_test::write_bytes(dir.file("damaged.png"), damaged);
    CHECK(ppcr::io::read_cloud(dir.file("damaged.png"), &cloud).code() == StatusCode::kParseError);
    CHECK(cloud.empty());
    io_test::write_bytes(dir.file("text.png"), "1 2 3\n4 5 6\n");
    const ppcr::Status s = ppcr::io::read_cloud(dir.file("text.png"), &cloud);
    CHECK_THAT(s.message(), Catch::Contains("not a PNG file"));
  }
  SECTION("a camera that cannot back-project") {
    const std::string path = dir.file("frame.png");
    REQUIRE(write_png(path, 7, 5, 16, PNG_COLOR_TYPE_GRAY, test_depths()));
    DepthCamera camera;
    camera.fy = 0.0;
    ppcr::Status s = ppcr::io::read_cloud(path, camera, &cloud);
    CHECK(s.code() == StatusCode::kInvalidArgument);
    CHECK_THAT(s.message(), Catch::Contains("fy = 0"));
    camera = DepthCamera();
    camera.cx = std::numeric_limits<double>::quiet_NaN();
    s = ppcr::io::read_cloud(path, camera, &cloud);
    CHECK_THAT(s.message(), Catch::Contains("cx = nan"));
    camera = DepthCamera();
    camera.depth_scale = -5000.0;
    CHECK(ppcr::io::read_cloud(path, camera, &cloud).code() == StatusCode::kInvalidArgument);
  }
  SECTION("not written: a cloud is not a depth image") {
    const ppcr::Status s = ppcr::io::write_cloud(dir.file("out.png"), {Eigen::Vector3d(1, 2, 3)});
    CHECK(s.code() == StatusCode::kInvalidArgument);
    CHECK_THAT(s.message(), Catch::Contains("read, not written"));
    CHECK_FALSE(std::filesystem::exists(dir.file("out.png")));
  }
}

TEST_CASE("Depth PNG: every truncation and every flipped byte of a file is read or refused cleanly",
          "[io][depth]") {
  // libpng reports damage by longjmp out of the decoder: each of these takes one of those paths
  // (the sanitize build checks that none leaks or touches freed memory).
  io_test::TempDir dir;
  const std::string good = dir.file("good.png");
  REQUIRE(write_png(good, 7, 5, 16, PNG_COLOR_TYPE_GRAY, test_depths()));
  const std::string bytes = io_test::read_bytes(good);
  std::size_t refused = 0;
  const auto read = [&](const std::string& content, const std::string& what) {
    PointCloud cloud;
    const ppcr::Status s = ppcr::io::read_cloud_from_buffer("mem.png", content.data(),
                                                            content.size(), Format::kAuto, &cloud);
    INFO(what << ": " << s.to_string());
    if (s.ok()) {
      CHECK(!cloud.empty());
    } else {
      ++refused;
      CHECK(cloud.empty());
      CHECK_THAT(s.message(), Catch::StartsWith("mem.png: "));
    }
  };
  for (std::size_t keep = 0; keep < bytes.size(); ++keep) {
    read(bytes.substr(0, keep), std::to_string(keep) + " bytes kept");
  }
  CHECK(refused == bytes.size());  // the last chunk (IEND) is required too
  refused = 0;
  for (std::size_t at = 0; at < bytes.size(); ++at) {
    std::string flipped = bytes;
    flipped[at] = static_cast<char>(flipped[at] ^ 0x24);
    read(flipped, "byte " + std::to_string(at) + " flipped");
  }
  // Each flip breaks the signature or a chunk's CRC (which covers its type and data), or cuts
  // the chunk sequence (a length): every one is refused.
  CHECK(refused == bytes.size());
}
