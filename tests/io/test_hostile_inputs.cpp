// Hostile inputs: every malformed file must give a Status (never a crash, a hang, a huge
// allocation or a silently wrong cloud) whose message names the file and the offending line or
// byte. The inputs are generated here: truncations at every byte of small valid binary files,
// lying headers, garbage, empty and missing files, random mutations.
#include <lzf.h>

#include <catch2/catch.hpp>
#include <random>
#include <string>
#include <vector>

#include "io_test_util.hpp"
#include "ppcr/io.hpp"

using ppcr::PointCloud;
using ppcr::StatusCode;
using ppcr::io::Format;
using ppcr::io::ReadReport;

namespace {

ppcr::Status read_mem(const std::string& name, const std::string& bytes, PointCloud* cloud,
                      ReadReport* report = nullptr) {
  return ppcr::io::read_cloud_from_buffer(name, bytes.data(), bytes.size(), Format::kAuto, cloud,
                                          report);
}

// Reads `bytes` as file `name` and checks the code and that the message holds each needle.
void expect_error(const std::string& name, const std::string& bytes, StatusCode code,
                  const std::vector<std::string>& needles) {
  PointCloud cloud = {Eigen::Vector3d(1, 2, 3)};  // must come back empty
  const ppcr::Status s = read_mem(name, bytes, &cloud);
  INFO("file " << name << " -> " << s.to_string());
  CHECK(s.code() == code);
  CHECK_THAT(s.message(), Catch::Contains(name));
  for (const std::string& needle : needles) CHECK_THAT(s.message(), Catch::Contains(needle));
  CHECK(cloud.empty());
}

// A small valid binary little-endian PLY: float x y z + uchar intensity, then a face element.
std::string small_ply(bool big_endian) {
  std::string f = std::string("ply\nformat ") +
                  (big_endian ? "binary_big_endian" : "binary_little_endian") +
                  " 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
                  "property uchar intensity\nelement face 1\n"
                  "property list uchar int vertex_indices\nend_header\n";
  for (int v = 0; v < 3; ++v) {
    for (int k = 0; k < 3; ++k)
      io_test::put<float>(&f, 0.5f * static_cast<float>(v + k), big_endian);
    io_test::put<std::uint8_t>(&f, 9, big_endian);
  }
  io_test::put<std::uint8_t>(&f, 3, big_endian);
  for (int i = 0; i < 3; ++i) io_test::put<std::int32_t>(&f, i, big_endian);
  return f;
}

const char kPcdHeader[] =
    "# .PCD v0.7 - Point Cloud Data file format\nVERSION 0.7\nFIELDS x y z\nSIZE 4 4 4\n"
    "TYPE F F F\nCOUNT 1 1 1\nWIDTH 3\nHEIGHT 1\nVIEWPOINT 0 0 0 1 0 0 0\nPOINTS 3\n";

std::string small_pcd_binary() {
  std::string f = std::string(kPcdHeader) + "DATA binary\n";
  for (int i = 0; i < 9; ++i) io_test::put<float>(&f, 1.0f + static_cast<float>(i));
  return f;
}

std::string small_pcd_compressed() {
  std::string soa;
  for (int i = 0; i < 9; ++i) io_test::put<float>(&soa, 1.0f + static_cast<float>(i));
  std::string packed(soa.size() * 2 + 16, '\0');
  const unsigned int n = lzf_compress(soa.data(), static_cast<unsigned int>(soa.size()), &packed[0],
                                      static_cast<unsigned int>(packed.size()));
  packed.resize(n);
  std::string f = std::string(kPcdHeader) + "DATA binary_compressed\n";
  io_test::put_le_u32(&f, n);
  io_test::put_le_u32(&f, static_cast<std::uint32_t>(soa.size()));
  return f + packed;
}

}  // namespace

TEST_CASE("Truncation at every byte of small binary files is an error naming line or byte",
          "[io][hostile]") {
  struct Sample {
    std::string name;
    std::string bytes;
  };
  const std::vector<Sample> samples = {{"le.ply", small_ply(false)},
                                       {"be.ply", small_ply(true)},
                                       {"bin.pcd", small_pcd_binary()},
                                       {"lzf.pcd", small_pcd_compressed()}};
  for (const Sample& sample : samples) {
    PointCloud full;
    const ppcr::Status whole = read_mem(sample.name, sample.bytes, &full);
    INFO(sample.name << ": " << whole.message());
    REQUIRE(whole.ok());
    REQUIRE(full.size() == 3u);
    for (std::size_t length = 0; length < sample.bytes.size(); ++length) {
      PointCloud cloud;
      const ppcr::Status s = read_mem(sample.name, sample.bytes.substr(0, length), &cloud);
      INFO(sample.name << " cut to " << length << " bytes: " << s.to_string());
      CHECK(s.code() == StatusCode::kParseError);
      CHECK_THAT(s.message(), Catch::Contains(sample.name));
      const bool located = s.message().find("byte") != std::string::npos ||
                           s.message().find("line") != std::string::npos ||
                           s.message().find("empty") != std::string::npos;
      CHECK(located);
      CHECK(cloud.empty());
    }
  }
}

TEST_CASE("Headers claiming billions of points in a tiny file are refused before allocating",
          "[io][hostile]") {
  std::string ply_bin =
      "ply\nformat binary_little_endian 1.0\nelement vertex 4000000000\nproperty float x\n"
      "property float y\nproperty float z\nend_header\n";
  ply_bin += std::string(200 - ply_bin.size(), '\0');
  expect_error("huge.ply", ply_bin, StatusCode::kParseError, {"4000000000", "truncated", "byte"});

  std::string ply_ascii =
      "ply\nformat ascii 1.0\nelement vertex 4000000000\nproperty float x\nproperty float y\n"
      "property float z\nend_header\n1 2 3\n";
  expect_error("huge_ascii.ply", ply_ascii, StatusCode::kParseError, {"4000000000", "byte"});

  // A list property claiming 4e9 items.
  std::string ply_list =
      "ply\nformat binary_little_endian 1.0\nelement vertex 1\nproperty float x\n"
      "property float y\nproperty float z\nelement face 1\nproperty list uint int idx\n"
      "end_header\n";
  for (int k = 0; k < 3; ++k) io_test::put<float>(&ply_list, 1.0f);
  io_test::put<std::uint32_t>(&ply_list, 4000000000u);
  expect_error("list.ply", ply_list, StatusCode::kParseError, {"4000000000 items", "byte"});

  // A negative list length.
  std::string ply_neg =
      "ply\nformat binary_little_endian 1.0\nelement vertex 1\nproperty float x\n"
      "property float y\nproperty float z\nproperty list int float n\nend_header\n";
  for (int k = 0; k < 3; ++k) io_test::put<float>(&ply_neg, 1.0f);
  io_test::put<std::int32_t>(&ply_neg, -3);
  expect_error("neg.ply", ply_neg, StatusCode::kParseError, {"negative length -3", "byte"});

  const std::string pcd_header =
      "VERSION 0.7\nFIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nCOUNT 1 1 1\nWIDTH 4000000000\n"
      "HEIGHT 1\nPOINTS 4000000000\n";
  expect_error("huge.pcd", pcd_header + "DATA binary\n" + std::string(60, '\0'),
               StatusCode::kParseError, {"4000000000 points", "truncated", "byte"});
  expect_error("huge_ascii.pcd", pcd_header + "DATA ascii\n1 2 3\n", StatusCode::kParseError,
               {"4000000000", "too short"});
  std::string lzf_header = pcd_header + "DATA binary_compressed\n";
  io_test::put_le_u32(&lzf_header, 4);
  io_test::put_le_u32(&lzf_header, 0xffffffffu);
  expect_error("huge_lzf.pcd", lzf_header + "abcd", StatusCode::kParseError,
               {"uncompressed", "byte"});
  // A plausible uncompressed size that 4 compressed bytes cannot produce.
  std::string ratio =
      "VERSION 0.7\nFIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nCOUNT 1 1 1\nWIDTH 100000\n"
      "HEIGHT 1\nPOINTS 100000\nDATA binary_compressed\n";
  io_test::put_le_u32(&ratio, 4);
  io_test::put_le_u32(&ratio, 1200000);
  expect_error("ratio.pcd", ratio + "abcd", StatusCode::kParseError, {"more than LZF"});
}

TEST_CASE("Negative, overflowing and disagreeing counts", "[io][hostile]") {
  const std::string ply_head = "ply\nformat binary_little_endian 1.0\n";
  const std::string xyz_props = "property float x\nproperty float y\nproperty float z\n";
  expect_error("neg.ply", ply_head + "element vertex -5\n" + xyz_props + "end_header\n",
               StatusCode::kParseError, {"line 3", "negative"});
  expect_error("ovf.ply",
               ply_head + "element vertex 99999999999999999999\n" + xyz_props + "end_header\n",
               StatusCode::kParseError, {"line 3", "2^64"});
  // Fewer vertices declared than the data hold: the extra bytes are reported.
  std::string more = ply_head + "element vertex 2\n" + xyz_props + "end_header\n";
  for (int i = 0; i < 9; ++i) io_test::put<float>(&more, 1.0f);
  expect_error("more.ply", more, StatusCode::kParseError, {"12 unexpected bytes", "byte"});

  const std::string pcd_fields = "VERSION 0.7\nFIELDS x y z\nSIZE 4 4 4\nTYPE F F F\n";
  expect_error("neg.pcd", pcd_fields + "WIDTH -3\nHEIGHT 1\nPOINTS 3\nDATA ascii\n",
               StatusCode::kParseError, {"line 5", "negative"});
  expect_error("negp.pcd", pcd_fields + "WIDTH 3\nHEIGHT 1\nPOINTS -1\nDATA ascii\n",
               StatusCode::kParseError, {"line 7", "negative"});
  expect_error("ovf.pcd", pcd_fields + "WIDTH 4294967296\nHEIGHT 4294967296\nDATA binary\n",
               StatusCode::kParseError, {"line 5", "overflows"});
  expect_error("disagree.pcd", pcd_fields + "WIDTH 3\nHEIGHT 2\nPOINTS 5\nDATA ascii\n",
               StatusCode::kParseError, {"line 7", "POINTS 5", "3 x 2 = 6"});
  // ascii with fewer / more rows than POINTS.
  expect_error("short.pcd",
               pcd_fields + "WIDTH 3\nPOINTS 3\nDATA ascii\n1.000 2.000 3.000\n4.000 5.000 6.000\n",
               StatusCode::kParseError, {"truncated", "POINTS is 3", "after 2 points"});
  expect_error("long.pcd", pcd_fields + "WIDTH 1\nPOINTS 1\nDATA ascii\n1 2 3\n4 5 6\n",
               StatusCode::kParseError, {"line 9", "after the last"});
}

TEST_CASE("Malformed headers name the line and what was expected", "[io][hostile]") {
  const std::string xyz_props = "property float x\nproperty float y\nproperty float z\n";
  expect_error("type.ply",
               "ply\nformat ascii 1.0\nelement vertex 1\nproperty float128 x\nend_header\n",
               StatusCode::kParseError, {"line 4", "unknown property type 'float128'"});
  expect_error("fmt.ply", "ply\nformat binary_middle_endian 1.0\nend_header\n",
               StatusCode::kParseError, {"line 2", "binary_middle_endian"});
  expect_error("noend.ply", "ply\nformat ascii 1.0\nelement vertex 1\n" + xyz_props + "1 2 3\n",
               StatusCode::kParseError, {"line 7", "unknown header keyword '1'"});
  expect_error("noend2.ply", "ply\nformat ascii 1.0\nelement vertex 1\n" + xyz_props,
               StatusCode::kParseError, {"end_header", "byte"});
  expect_error("novertex.ply", "ply\nformat ascii 1.0\nelement face 0\nend_header\n",
               StatusCode::kParseError, {"no 'vertex' element"});
  expect_error("noz.ply",
               "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float y\n"
               "end_header\n1 2\n",
               StatusCode::kParseError, {"line 3", "no property 'z'"});
  expect_error("notply.ply", "PLY\nformat ascii 1.0\n", StatusCode::kParseError,
               {"line 1", "'PLY\\nformat ascii'"});
  expect_error(
      "ascii_bad.ply",
      "ply\nformat ascii 1.0\nelement vertex 2\n" + xyz_props + "end_header\n1 2 3\n4 5 abc\n",
      StatusCode::kParseError, {"line 9", "column 5", "'abc'"});

  const std::string pcd_ok = "VERSION 0.7\nFIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nWIDTH 1\n";
  expect_error("nodata.pcd", pcd_ok + "POINTS 1\n", StatusCode::kParseError, {"no DATA line"});
  expect_error("data.pcd", pcd_ok + "DATA binary_lz4\n", StatusCode::kParseError,
               {"line 6", "binary_lz4"});
  expect_error("f2.pcd", "VERSION 0.7\nFIELDS x y z\nSIZE 2 4 4\nTYPE F F F\nWIDTH 1\nDATA ascii\n",
               StatusCode::kParseError, {"line 4", "TYPE F SIZE 2"});
  expect_error("nox.pcd",
               "VERSION 0.7\nFIELDS a y z\nSIZE 4 4 4\nTYPE F F F\nWIDTH 1\nDATA ascii\n",
               StatusCode::kParseError, {"line 2", "no field 'x'"});
  expect_error("sizes.pcd",
               "VERSION 0.7\nFIELDS x y z\nSIZE 4 4\nTYPE F F F\nWIDTH 1\nDATA ascii\n",
               StatusCode::kParseError, {"line 3", "2 entries", "names 3"});
  expect_error("kw.pcd", "VERSION 0.7\nFIELDS x y z\nFOO 1\n", StatusCode::kParseError,
               {"line 3", "'FOO'"});
  expect_error("ver.pcd", "VERSION 9.1\nFIELDS x y z\n", StatusCode::kParseError,
               {"line 1", "9.1"});
}

TEST_CASE("Empty, missing, directory and garbage inputs", "[io][hostile]") {
  for (const char* name : {"e.ply", "e.pcd", "e.xyz", "e.bin", "e.dat"}) {
    expect_error(name, "", StatusCode::kParseError, {"empty"});
  }
  io_test::TempDir dir;
  PointCloud cloud = {Eigen::Vector3d(1, 1, 1)};
  ppcr::Status s = ppcr::io::read_cloud(dir.file("missing.ply"), &cloud);
  CHECK(s.code() == StatusCode::kIoError);
  CHECK_THAT(s.message(), Catch::Contains("missing.ply") && Catch::Contains("no such file"));
  CHECK(cloud.empty());

  s = ppcr::io::read_cloud(dir.path().string(), &cloud);
  CHECK(s.code() == StatusCode::kIoError);
  CHECK_THAT(s.message(), Catch::Contains(dir.path().string()) && Catch::Contains("directory"));

  const std::string empty_path = dir.file("empty.xyz");
  io_test::write_bytes(empty_path, "");
  s = ppcr::io::read_cloud(empty_path, &cloud);
  CHECK(s.code() == StatusCode::kParseError);
  CHECK_THAT(s.message(), Catch::Contains("empty.xyz") && Catch::Contains("empty"));

  std::mt19937 rng(1234);
  std::string garbage(200, '\0');
  for (char& c : garbage) c = static_cast<char>(rng() & 0xff);
  garbage[0] = '\x89';  // not a digit, not a PLY/PCD keyword
  for (const char* name : {"g.ply", "g.pcd", "g.xyz", "g.bin", "g.dat"}) {
    expect_error(name, garbage, StatusCode::kParseError, {});
  }
  expect_error("g.dat", garbage, StatusCode::kParseError, {"unknown point cloud format", "\\x89"});
  expect_error("words.dat", "hello world\nthis is text\n", StatusCode::kParseError,
               {"unknown point cloud format", "'hello world\\nthis is "});
}

TEST_CASE("Random mutations of valid files never crash and never give a wrong-sized cloud",
          "[io][hostile]") {
  struct Sample {
    std::string name;
    std::string bytes;
  };
  std::vector<Sample> samples = {
      {"le.ply", small_ply(false)},
      {"be.ply", small_ply(true)},
      {"bin.pcd", small_pcd_binary()},
      {"lzf.pcd", small_pcd_compressed()},
      {"a.xyz", "1 2 3\n4,5,6\n# c\n7 8 9\n"},
      {"a.pcd", std::string(kPcdHeader) + "DATA ascii\n1 2 3\n4 5 6\n7 8 9\n"},
      {"a.ply",
       "ply\nformat ascii 1.0\nelement vertex 2\nproperty float x\n"
       "property float y\nproperty float z\nelement f 1\n"
       "property list uchar int i\nend_header\n1 2 3\n4 5 6\n2 0 1\n"}};
  std::mt19937 rng(99);
  std::size_t ok_count = 0, error_count = 0;
  for (int iteration = 0; iteration < 20000; ++iteration) {
    const Sample& sample = samples[static_cast<std::size_t>(iteration) % samples.size()];
    std::string bytes = sample.bytes;
    const int edits = 1 + static_cast<int>(rng() % 4);
    for (int e = 0; e < edits && !bytes.empty(); ++e) {
      const std::size_t at = rng() % bytes.size();
      switch (rng() % 4) {
        case 0:
          bytes[at] = static_cast<char>(rng() & 0xff);
          break;  // overwrite
        case 1:
          bytes.erase(at, 1 + rng() % 8);
          break;  // delete
        case 2:
          bytes.insert(at, 1, static_cast<char>(rng() & 0xff));
          break;  // insert
        default:
          bytes[at] = "0123456789-.e \n"[rng() % 15];
          break;  // plausible
      }
    }
    PointCloud cloud;
    ReadReport report;
    const ppcr::Status s = read_mem(sample.name, bytes, &cloud, &report);
    if (s.ok()) {
      ++ok_count;
      bool finite = true;
      for (const Eigen::Vector3d& p : cloud) finite = finite && p.allFinite();
      CHECK(finite);
      CHECK(cloud.size() + report.non_finite_dropped == report.points_in_file);
    } else {
      ++error_count;
      CHECK_THAT(s.message(), Catch::Contains(sample.name));
      CHECK(cloud.empty());
    }
  }
  CHECK(ok_count > 0);
  CHECK(error_count > 0);
}
