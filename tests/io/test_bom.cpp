// A UTF-8 byte-order mark (EF BB BF), which Windows editors put at the start of text files, is
// skipped in every format: text clouds, PCD and PLY headers, transform files, and when the
// format is recognised from the content.
#include <catch2/catch.hpp>
#include <string>

#include "quirk_files.hpp"

using io_quirks::expect_points;
using io_quirks::kBom;

TEST_CASE("BOM before a headerless text cloud, a CSV header and a PTS count", "[io][bom]") {
  const std::string bom = kBom;
  expect_points("bom.xyz", bom + "0.5 0.5 0.5\n1.5 2.5 3.5\n", io_quirks::ramp(2));
  expect_points("bom.csv", bom + "x,y,z\n0.5,0.5,0.5\n", io_quirks::ramp(1));
  expect_points("bom.pts", bom + "2\n0.5 0.5 0.5\n1.5 2.5 3.5\n", io_quirks::ramp(2));
  expect_points("bom_z_first.csv", bom + "z,y,x\n0.5,0.5,0.5\n3.5,2.5,1.5\n", io_quirks::ramp(2));
}

TEST_CASE("BOM before a PCD header (ascii, binary, binary_compressed)", "[io][bom]") {
  const std::string bom = kBom;
  expect_points("bom_ascii.pcd",
                bom + io_quirks::pcd_header(2, "ascii") + "0.5 0.5 0.5\n1.5 2.5 3.5\n",
                io_quirks::ramp(2));
  expect_points("bom_binary.pcd", bom + io_quirks::pcd_binary(4), io_quirks::ramp(4));
  expect_points("bom_lzf.pcd", bom + io_quirks::pcd_compressed(4), io_quirks::ramp(4));
}

TEST_CASE("BOM before a PLY header (ascii and binary)", "[io][bom]") {
  const std::string bom = kBom;
  expect_points("bom_ascii.ply",
                bom +
                    "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\n"
                    "property float y\nproperty float z\nend_header\n0.5 0.5 0.5\n",
                io_quirks::ramp(1));
  expect_points("bom_binary.ply", bom + io_quirks::ply_binary(3), io_quirks::ramp(3));
}

TEST_CASE("BOM: the format is still recognised from the content", "[io][bom]") {
  const std::string bom = kBom;
  expect_points("cloud.dat", bom + io_quirks::ply_binary(2), io_quirks::ramp(2));
  expect_points("cloud.dat", bom + io_quirks::pcd_binary(2), io_quirks::ramp(2));
  expect_points("cloud.dat", bom + "0.5 0.5 0.5\n", io_quirks::ramp(1));
  ppcr::PointCloud cloud;
  ppcr::io::ReadReport report;
  REQUIRE(io_quirks::read_mem("cloud.dat", bom + io_quirks::pcd_binary(2), &cloud, &report).ok());
  CHECK(report.format == ppcr::io::Format::kPcd);
}

TEST_CASE("BOM before a transform file", "[io][bom][transform]") {
  const std::string text = std::string(kBom) + "1 0 0 1.5\n0 1 0 -2\n0 0 1 0.25\n0 0 0 1\n";
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  const ppcr::Status s =
      ppcr::io::read_transform_from_buffer("bom_T.txt", text.data(), text.size(), &T);
  INFO(s.to_string());
  REQUIRE(s.ok());
  CHECK(T.translation() == Eigen::Vector3d(1.5, -2, 0.25));
}

TEST_CASE("Only a BOM at the very start is skipped", "[io][bom]") {
  const std::string bom = kBom;
  io_quirks::expect_refused("late_bom.xyz", "0.5 0.5 0.5\n" + bom + "1.5 2.5 3.5\n",
                            {"line 2", "\\xef\\xbb\\xbf"});
  io_quirks::expect_refused("two_boms.xyz", bom + bom + "0.5 0.5 0.5\n", {"line 1"});
}
