// Real scans (../shared/data, read in place): counts, finiteness and a plausible extent, then
// PLY / PCD / XYZ write + read back bit-identically; the ground-truth matrices as transforms.
#include <catch2/catch.hpp>
#include <chrono>
#include <string>

#include "io_test_util.hpp"
#include "ppcr/io.hpp"
#include "test_data.hpp"

using ppcr::PointCloud;
using ppcr::io::Format;
using ppcr::io::ReadReport;

namespace {

struct Scan {
  const char* relative_path;
  std::size_t points;
  double min_extent_m, max_extent_m;  // plausible bounding-box diagonal
};

void check_scan(const Scan& scan) {
  const std::string path = ppcr_test::data_path(scan.relative_path);
  PointCloud cloud;
  ReadReport report;
  const ppcr::Status s = ppcr::io::read_cloud(path, &cloud, &report);
  INFO(path << ": " << s.message());
  REQUIRE(s.ok());
  CHECK(report.format == Format::kPly);
  CHECK(report.encoding == "binary_little_endian");
  CHECK(report.points_in_file == scan.points);
  CHECK(report.non_finite_dropped == 0u);
  REQUIRE(cloud.size() == scan.points);
  Eigen::Vector3d lo = cloud[0], hi = cloud[0];
  bool finite = true;
  bool float_exact = true;  // the files store float: every value must be a float
  for (const Eigen::Vector3d& p : cloud) {
    finite = finite && p.allFinite();
    lo = lo.cwiseMin(p);
    hi = hi.cwiseMax(p);
    for (int k = 0; k < 3; ++k) {
      float_exact = float_exact && static_cast<double>(static_cast<float>(p[k])) == p[k];
    }
  }
  CHECK(finite);
  CHECK(float_exact);
  const double diagonal = (hi - lo).norm();
  CHECK(diagonal > scan.min_extent_m);
  CHECK(diagonal < scan.max_extent_m);

  io_test::TempDir dir;
  for (const char* name : {"copy.ply", "copy.pcd", "copy.xyz"}) {
    const std::string out = dir.file(name);
    REQUIRE(ppcr::io::write_cloud(out, cloud).ok());
    PointCloud back;
    const ppcr::Status r = ppcr::io::read_cloud(out, &back);
    INFO(name << ": " << r.message());
    REQUIRE(r.ok());
    CHECK(io_test::bit_identical(cloud, back));
  }
}

}  // namespace

TEST_CASE("Real bunny scan bun000.ply: 40256 points, about 0.15 m", "[io][real_data]") {
  check_scan({"bunny/bun000.ply", 40256, 0.1, 0.4});
}

TEST_CASE("Real LiDAR scan source.ply: 69792 points, tens of metres", "[io][real_data]") {
  check_scan({"lidar/source.ply", 69792, 20.0, 200.0});
}

TEST_CASE("Real ground-truth matrices read as rigid transforms", "[io][real_data]") {
  for (const char* relative : {"bunny/bun045_gt.txt", "lidar/source_gt.txt"}) {
    Eigen::Isometry3d T;
    const ppcr::Status s = ppcr::io::read_transform(ppcr_test::data_path(relative), &T);
    INFO(relative << ": " << s.message());
    REQUIRE(s.ok());
    CHECK(T.matrix().row(3) == Eigen::RowVector4d(0, 0, 0, 1));
    CHECK(std::abs(T.linear().determinant() - 1.0) < 1e-6);
  }
}

TEST_CASE("Reading bun000.ply takes milliseconds", "[io][real_data][timing]") {
  const std::string path = ppcr_test::data_path("bunny/bun000.ply");
  PointCloud cloud;
  REQUIRE(ppcr::io::read_cloud(path, &cloud).ok());  // warm the page cache
  double best_ms = 1e9;
  for (int i = 0; i < 10; ++i) {
    const auto t0 = std::chrono::steady_clock::now();
    REQUIRE(ppcr::io::read_cloud(path, &cloud).ok());
    const auto t1 = std::chrono::steady_clock::now();
    best_ms = std::min(best_ms, std::chrono::duration<double, std::milli>(t1 - t0).count());
  }
  WARN("best of 10 reads of bun000.ply (40256 points): " << best_ms << " ms");
  // Generous bound (debug or sanitizer builds, a busy machine): a regression to per-point
  // allocation or per-byte I/O would be far slower still.
  CHECK(best_ms < 250.0);
}
