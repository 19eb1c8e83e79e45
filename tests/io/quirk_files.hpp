// quirk_files.hpp - small files as real writers lay them out, built byte by byte for the tests of
// padded PCDs, byte-order marks and text columns.
#pragma once

#include <lzf.h>

#include <catch2/catch.hpp>
#include <string>
#include <vector>

#include "io_test_util.hpp"
#include "ppcr/io.hpp"

namespace io_quirks {

constexpr char kBom[] = "\xEF\xBB\xBF";

inline ppcr::Status read_mem(const std::string& name, const std::string& bytes,
                             ppcr::PointCloud* cloud, ppcr::io::ReadReport* report = nullptr) {
  return ppcr::io::read_cloud_from_buffer(name, bytes.data(), bytes.size(), ppcr::io::Format::kAuto,
                                          cloud, report);
}

/// Reads `bytes` as `name` and requires exactly the expected points.
inline void expect_points(const std::string& name, const std::string& bytes,
                          const std::vector<Eigen::Vector3d>& expected) {
  ppcr::PointCloud cloud;
  const ppcr::Status s = read_mem(name, bytes, &cloud);
  INFO(name << ": " << s.to_string());
  REQUIRE(s.ok());
  REQUIRE(cloud.size() == expected.size());
  for (std::size_t i = 0; i < expected.size(); ++i) CHECK(cloud[i] == expected[i]);
}

/// Reads `bytes` as `name` and requires kParseError naming the file and holding every needle.
inline void expect_refused(const std::string& name, const std::string& bytes,
                           const std::vector<std::string>& needles) {
  ppcr::PointCloud cloud = {Eigen::Vector3d(1, 2, 3)};
  const ppcr::Status s = read_mem(name, bytes, &cloud);
  INFO(name << " -> " << s.to_string());
  CHECK(s.code() == ppcr::StatusCode::kParseError);
  CHECK_THAT(s.message(), Catch::Contains(name));
  for (const std::string& needle : needles) CHECK_THAT(s.message(), Catch::Contains(needle));
  CHECK(cloud.empty());
}

/// A PCD header for `points` float x y z points in the given DATA encoding.
inline std::string pcd_header(int points, const char* data) {
  return "# .PCD v0.7 - Point Cloud Data file format\nVERSION 0.7\nFIELDS x y z\nSIZE 4 4 4\n"
         "TYPE F F F\nCOUNT 1 1 1\nWIDTH " +
         std::to_string(points) + "\nHEIGHT 1\nVIEWPOINT 0 0 0 1 0 0 0\nPOINTS " +
         std::to_string(points) + "\nDATA " + data + "\n";
}

/// Points (i, 2i, 3i) + 0.5 for i = 0..n-1, as written to every file here.
inline std::vector<Eigen::Vector3d> ramp(int n) {
  std::vector<Eigen::Vector3d> out;
  for (int i = 0; i < n; ++i) out.emplace_back(0.5 + i, 0.5 + 2 * i, 0.5 + 3 * i);
  return out;
}

inline std::string pcd_binary(int n) {
  std::string f = pcd_header(n, "binary");
  for (const Eigen::Vector3d& p : ramp(n)) {
    for (int k = 0; k < 3; ++k) io_test::put<float>(&f, static_cast<float>(p[k]));
  }
  return f;
}

inline std::string pcd_compressed(int n) {
  std::string soa;
  const std::vector<Eigen::Vector3d> points = ramp(n);
  for (int k = 0; k < 3; ++k) {
    for (const Eigen::Vector3d& p : points) io_test::put<float>(&soa, static_cast<float>(p[k]));
  }
  std::string packed(soa.size() * 2 + 16, '\0');
  const unsigned int size = lzf_compress(soa.data(), static_cast<unsigned int>(soa.size()),
                                         &packed[0], static_cast<unsigned int>(packed.size()));
  packed.resize(size);
  std::string f = pcd_header(n, "binary_compressed");
  io_test::put_le_u32(&f, size);
  io_test::put_le_u32(&f, static_cast<std::uint32_t>(soa.size()));
  return f + packed;
}

inline std::string ply_binary(int n) {
  std::string f = "ply\nformat binary_little_endian 1.0\nelement vertex " + std::to_string(n) +
                  "\nproperty float x\nproperty float y\nproperty float z\nend_header\n";
  for (const Eigen::Vector3d& p : ramp(n)) {
    for (int k = 0; k < 3; ++k) io_test::put<float>(&f, static_cast<float>(p[k]));
  }
  return f;
}

}  // namespace io_quirks
