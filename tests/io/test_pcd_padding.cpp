// PCDs written by PCL's command-line tools (pcl_convert_pcd_ascii_binary, pcl_ply2pcd) go through
// PCL's blob writer, which pads the data section with zeros up to a page boundary: zeros after
// the points are accepted as padding, any other trailing byte is refused with the count.
#include <catch2/catch.hpp>
#include <string>

#include "quirk_files.hpp"

using io_quirks::expect_points;
using io_quirks::expect_refused;

TEST_CASE("PCD binary padded with zeros after the points reads (PCL tools)", "[io][pcd][quirks]") {
  const std::string file = io_quirks::pcd_binary(5);
  const std::size_t page = 4096;
  expect_points("padded.pcd", file + std::string(page - file.size() % page, '\0'),
                io_quirks::ramp(5));
  expect_points("one_zero.pcd", file + std::string(1, '\0'), io_quirks::ramp(5));
}

TEST_CASE("PCD binary_compressed padded with zeros after the LZF data reads (PCL tools)",
          "[io][pcd][quirks]") {
  const std::string file = io_quirks::pcd_compressed(7);
  expect_points("padded_lzf.pcd", file + std::string(4096 - file.size() % 4096, '\0'),
                io_quirks::ramp(7));
}

TEST_CASE("PCD ascii followed by zero bytes reads", "[io][pcd][quirks]") {
  const std::string file = io_quirks::pcd_header(2, "ascii") + "0.5 0.5 0.5\n1.5 2.5 3.5\n";
  expect_points("padded_ascii.pcd", file + std::string(100, '\0'), io_quirks::ramp(2));
}

TEST_CASE("PCD trailing bytes that are not zeros are refused with their count",
          "[io][pcd][quirks]") {
  const std::string binary = io_quirks::pcd_binary(3);
  // 10 extra bytes, the last one not zero.
  std::string tail(10, '\0');
  tail.back() = '\x01';
  expect_refused("dirty.pcd", binary + tail,
                 {"10 unexpected extra bytes", "not zero padding",
                  "byte " + std::to_string(binary.size() + 9)});
  // A fourth point the header does not declare: 12 bytes of data.
  std::string point;
  for (int k = 0; k < 3; ++k) io_test::put<float>(&point, 7.0f);
  expect_refused("extra_point.pcd", binary + point, {"12 unexpected extra bytes"});
  const std::string lzf = io_quirks::pcd_compressed(3);
  expect_refused("dirty_lzf.pcd", lzf + "abc", {"3 unexpected extra bytes", "'a'"});
  expect_refused("dirty_ascii.pcd",
                 io_quirks::pcd_header(1, "ascii") + "0.5 0.5 0.5\n" + std::string(4, '\0') + "x",
                 {"unexpected data after the last of POINTS 1 points"});
}
