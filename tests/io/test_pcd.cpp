// PCD reading and writing: ascii, binary and binary_compressed variants built byte by byte here
// (binary_compressed with liblzf's own lzf_compress), decoded points compared with the values put
// in.
#include <lzf.h>

#include <catch2/catch.hpp>
#include <cmath>
#include <limits>
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

double f32(double v) { return static_cast<double>(static_cast<float>(v)); }

std::string lzf(const std::string& raw) {
  std::string out(raw.size() * 2 + 64, '\0');
  const unsigned int n = lzf_compress(raw.data(), static_cast<unsigned int>(raw.size()), &out[0],
                                      static_cast<unsigned int>(out.size()));
  REQUIRE(n > 0);
  out.resize(n);
  return out;
}

const float kNaN = std::numeric_limits<float>::quiet_NaN();

}  // namespace

TEST_CASE("PCD write/read round trip is bit-exact (binary, double)", "[io][pcd]") {
  io_test::TempDir dir;
  const PointCloud cloud = io_test::awkward_cloud(777, 11);
  const std::string path = dir.file("cloud.PCD");  // extension case must not matter
  REQUIRE(ppcr::io::write_cloud(path, cloud).ok());
  const std::string bytes = io_test::read_bytes(path);
  CHECK(bytes.rfind("# .PCD v0.7", 0) == 0);
  CHECK(bytes.find("\nFIELDS x y z\nSIZE 8 8 8\nTYPE F F F\nCOUNT 1 1 1\nWIDTH 777\nHEIGHT 1\n") !=
        std::string::npos);
  CHECK(bytes.find("\nPOINTS 777\nDATA binary\n") != std::string::npos);
  const std::size_t data = bytes.find("DATA binary\n") + 12;
  CHECK(bytes.size() - data == 777u * 24u);

  PointCloud back;
  ReadReport report;
  const ppcr::Status s = ppcr::io::read_cloud(path, &back, &report);
  INFO(s.message());
  REQUIRE(s.ok());
  CHECK(io_test::bit_identical(cloud, back));
  CHECK(report.format == Format::kPcd);
  CHECK(report.encoding == "binary");
  CHECK(report.points_in_file == 777u);
}

TEST_CASE("PCD ascii with COUNT 3 fields, x y z not first, and padding fields", "[io][pcd]") {
  const std::string header =
      "# .PCD v0.7 - Point Cloud Data file format\n"
      "VERSION 0.7\n"
      "FIELDS normal x rgb _ y z\n"
      "SIZE 4 8 4 1 4 4\n"
      "TYPE F F U U F F\n"
      "COUNT 3 1 1 2 1 1\n"
      "WIDTH 3\n"
      "HEIGHT 1\n"
      "VIEWPOINT 0 0 0 1 0 0 0\n"
      "POINTS 3\n"
      "DATA ascii\n";
  // Rows written with values for the "_" field (as the header lists it) ...
  const std::string with_padding =
      "0.1 0.2 0.3 1.5 4278190080 0 0 -2.25 3e-3\n"
      "1 1 1 -1e-5 0 9 9 1e10 -0\n"
      "\n"
      "0 0 0 7 1 0 0 8 9\n";
  // ... or without them (as PCL writes ascii).
  const std::string without_padding =
      "0.1 0.2 0.3 1.5 4278190080 -2.25 3e-3\n"
      "1 1 1 -1e-5 0 1e10 -0\n"
      "0 0 0 7 1 8 9\n";
  for (const std::string& body : {with_padding, without_padding}) {
    PointCloud cloud;
    ReadReport report;
    const ppcr::Status s = read_mem("ascii.pcd", header + body, &cloud, &report);
    INFO(s.message());
    REQUIRE(s.ok());
    REQUIRE(cloud.size() == 3u);
    CHECK(cloud[0] == Eigen::Vector3d(1.5, -2.25, 3e-3));
    CHECK(cloud[1] == Eigen::Vector3d(-1e-5, 1e10, -0.0));
    CHECK(cloud[2] == Eigen::Vector3d(7, 8, 9));
    CHECK(report.encoding == "ascii");
  }
  // A row with a different number of values is an error naming its line.
  PointCloud cloud;
  const ppcr::Status bad = read_mem("ascii.pcd", header + without_padding + "1 2 3\n", &cloud);
  CHECK(bad.code() == StatusCode::kParseError);
  CHECK_THAT(bad.message(), Catch::Contains("ascii.pcd") && Catch::Contains("line 15"));
}

TEST_CASE("PCD binary with mixed field types and padding", "[io][pcd]") {
  std::string f =
      "# .PCD v0.7 - Point Cloud Data file format\n"
      "VERSION 0.7\n"
      "FIELDS rgb x _ y z curvature\n"
      "SIZE 4 8 1 4 2 4\n"
      "TYPE U F U F I F\n"
      "COUNT 1 1 3 1 1 1\n"
      "WIDTH 2\n"
      "HEIGHT 1\n"
      "VIEWPOINT 1 2 3 1 0 0 0\n"
      "POINTS 2\n"
      "DATA binary\n";
  const double xs[2] = {0.1, -123.456};
  const float ys[2] = {2.5f, 1e-20f};
  const std::int16_t zs[2] = {-32768, 12};
  for (int i = 0; i < 2; ++i) {
    io_test::put<std::uint32_t>(&f, 0xdeadbeefu);
    io_test::put<double>(&f, xs[i]);
    f += std::string("\x01\x02\x03", 3);
    io_test::put<float>(&f, ys[i]);
    io_test::put<std::int16_t>(&f, zs[i]);
    io_test::put<float>(&f, kNaN);  // a NaN in a field we skip does not matter
  }
  PointCloud cloud;
  ReadReport report;
  const ppcr::Status s = read_mem("mixed.pcd", f, &cloud, &report);
  INFO(s.message());
  REQUIRE(s.ok());
  REQUIRE(cloud.size() == 2u);
  for (int i = 0; i < 2; ++i) {
    CHECK(cloud[i].x() == xs[i]);
    CHECK(cloud[i].y() == static_cast<double>(ys[i]));
    CHECK(cloud[i].z() == static_cast<double>(zs[i]));
  }
  CHECK(report.non_finite_dropped == 0u);
}

TEST_CASE("PCD binary x y z of every TYPE/SIZE", "[io][pcd]") {
  struct TypeCase {
    const char* type;
    int size;
    double values[3];
  };
  const TypeCase cases[] = {
      {"I", 1, {-128, 127, 3}},
      {"U", 1, {0, 255, 4}},
      {"I", 2, {-32768, 32767, -1}},
      {"U", 2, {0, 65535, 2}},
      {"I", 4, {-2147483648.0, 2147483647.0, 5}},
      {"U", 4, {0, 4294967295.0, 6}},
      {"I", 8, {-9007199254740992.0, 9007199254740992.0, -7}},
      {"U", 8, {0, 18446744073709551616.0 / 2, 8}},
      {"F", 4, {0.5, -3e38, 1e-45}},
      {"F", 8, {0.1, -1e308, 4.9e-324}},
  };
  for (const TypeCase& tc : cases) {
    std::string f = "VERSION 0.7\nFIELDS x y z\nSIZE " + std::to_string(tc.size) + " " +
                    std::to_string(tc.size) + " " + std::to_string(tc.size) + "\nTYPE " + tc.type +
                    " " + tc.type + " " + tc.type +
                    "\nCOUNT 1 1 1\nWIDTH 1\nHEIGHT 1\nPOINTS 1\nDATA binary\n";
    double expected[3];
    for (int k = 0; k < 3; ++k) {
      const double v = tc.values[k];
      const std::string t = tc.type;
      expected[k] = v;
      if (t == "F" && tc.size == 4) {
        io_test::put<float>(&f, static_cast<float>(v));
        expected[k] = f32(v);
      } else if (t == "F") {
        io_test::put<double>(&f, v);
      } else if (t == "I" && tc.size == 1) {
        io_test::put<std::int8_t>(&f, static_cast<std::int8_t>(v));
      } else if (t == "I" && tc.size == 2) {
        io_test::put<std::int16_t>(&f, static_cast<std::int16_t>(v));
      } else if (t == "I" && tc.size == 4) {
        io_test::put<std::int32_t>(&f, static_cast<std::int32_t>(v));
      } else if (t == "I") {
        io_test::put<std::int64_t>(&f, static_cast<std::int64_t>(v));
      } else if (tc.size == 1) {
        io_test::put<std::uint8_t>(&f, static_cast<std::uint8_t>(v));
      } else if (tc.size == 2) {
        io_test::put<std::uint16_t>(&f, static_cast<std::uint16_t>(v));
      } else if (tc.size == 4) {
        io_test::put<std::uint32_t>(&f, static_cast<std::uint32_t>(v));
      } else {
        io_test::put<std::uint64_t>(&f, static_cast<std::uint64_t>(v));
      }
    }
    PointCloud cloud;
    const ppcr::Status s = read_mem("types.pcd", f, &cloud);
    INFO(tc.type << tc.size << ": " << s.message());
    REQUIRE(s.ok());
    REQUIRE(cloud.size() == 1u);
    for (int k = 0; k < 3; ++k) CHECK(cloud[0][k] == expected[k]);
  }
}

TEST_CASE("PCD binary_compressed (LZF, structure of arrays), with and without padding data",
          "[io][pcd]") {
  const int n = 50;
  std::vector<float> x(n), y(n), z(n), nx(n);
  for (int i = 0; i < n; ++i) {
    x[i] = 0.1f * static_cast<float>(i);
    y[i] = -1000.0f + static_cast<float>(i * i);
    z[i] = static_cast<float>(std::sin(i));
    nx[i] = 1.0f;
  }
  x[7] = kNaN;  // one non-finite point
  // Fields: x, a padding field, y z, a normal of COUNT 3 (as 3 equal values).
  const std::string header =
      "# .PCD v0.7 - Point Cloud Data file format\n"
      "VERSION 0.7\n"
      "FIELDS x _ y z normal\n"
      "SIZE 4 1 4 4 4\n"
      "TYPE F U F F F\n"
      "COUNT 1 4 1 1 3\n"
      "WIDTH 50\n"
      "HEIGHT 1\n"
      "VIEWPOINT 0 0 0 1 0 0 0\n"
      "POINTS 50\n"
      "DATA binary_compressed\n";
  for (bool padding_in_data : {false, true}) {
    std::string soa;
    for (int i = 0; i < n; ++i) io_test::put<float>(&soa, x[i]);
    if (padding_in_data) soa += std::string(4 * n, '\x5a');
    for (int i = 0; i < n; ++i) io_test::put<float>(&soa, y[i]);
    for (int i = 0; i < n; ++i) io_test::put<float>(&soa, z[i]);
    for (int i = 0; i < n; ++i) {
      for (int k = 0; k < 3; ++k) io_test::put<float>(&soa, nx[i]);
    }
    const std::string packed = lzf(soa);
    std::string f = header;
    io_test::put_le_u32(&f, static_cast<std::uint32_t>(packed.size()));
    io_test::put_le_u32(&f, static_cast<std::uint32_t>(soa.size()));
    f += packed;

    PointCloud cloud;
    ReadReport report;
    const ppcr::Status s = read_mem("lzf.pcd", f, &cloud, &report);
    INFO((padding_in_data ? "padding in data: " : "PCL layout: ") << s.message());
    REQUIRE(s.ok());
    REQUIRE(cloud.size() == static_cast<std::size_t>(n - 1));
    CHECK(report.non_finite_dropped == 1u);
    CHECK(report.points_in_file == 50u);
    CHECK(report.encoding == "binary_compressed");
    std::size_t j = 0;
    for (int i = 0; i < n; ++i) {
      if (i == 7) continue;
      CHECK(cloud[j].x() == static_cast<double>(x[i]));
      CHECK(cloud[j].y() == static_cast<double>(y[i]));
      CHECK(cloud[j].z() == static_cast<double>(z[i]));
      ++j;
    }

    // Corrupting the LZF stream, or lying about the uncompressed size, is an error.
    std::string corrupt = f;
    corrupt[header.size() + 8] = static_cast<char>(0xff);  // a back reference before the start
    PointCloud c2;
    ppcr::Status bad = read_mem("lzf.pcd", corrupt, &c2);
    CHECK(bad.code() == StatusCode::kParseError);
    CHECK_THAT(bad.message(), Catch::Contains("lzf.pcd") && Catch::Contains("byte"));
    CHECK(c2.empty());
    std::string lie = f;
    lie[header.size() + 4] = static_cast<char>(lie[header.size() + 4] + 1);
    bad = read_mem("lzf.pcd", lie, &c2);
    CHECK(bad.code() == StatusCode::kParseError);
    CHECK_THAT(bad.message(), Catch::Contains("uncompressed"));
  }
}

TEST_CASE("PCD organized cloud with NaN padding, binary and ascii", "[io][pcd]") {
  // WIDTH 4 x HEIGHT 3; points with NaN are the organized cloud's padding.
  const int width = 4, height = 3;
  std::vector<Eigen::Vector3f> pts;
  for (int r = 0; r < height; ++r) {
    for (int c = 0; c < width; ++c) {
      const bool hole = (r * width + c) % 3 == 1;
      pts.emplace_back(hole ? kNaN : 0.25f * static_cast<float>(c),
                       hole ? kNaN : -0.5f * static_cast<float>(r), hole ? kNaN : 1.0f + c + r);
    }
  }
  const std::string header =
      "# .PCD v0.7 - Point Cloud Data file format\n"
      "VERSION 0.7\nFIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nCOUNT 1 1 1\n"
      "WIDTH 4\nHEIGHT 3\nVIEWPOINT 0 0 0 1 0 0 0\nPOINTS 12\n";
  std::string binary = header + "DATA binary\n";
  std::string ascii = header + "DATA ascii\n";
  for (const Eigen::Vector3f& p : pts) {
    for (int k = 0; k < 3; ++k) io_test::put<float>(&binary, p[k]);
    char line[128];
    if (std::isnan(p.x())) {
      std::snprintf(line, sizeof(line), "nan nan nan\n");
    } else {
      std::snprintf(line, sizeof(line), "%.9g %.9g %.9g\n", static_cast<double>(p.x()),
                    static_cast<double>(p.y()), static_cast<double>(p.z()));
    }
    ascii += line;
  }
  for (const std::string& f : {binary, ascii}) {
    PointCloud cloud;
    ReadReport report;
    const ppcr::Status s = read_mem("organized.pcd", f, &cloud, &report);
    INFO(s.message());
    REQUIRE(s.ok());
    CHECK(report.points_in_file == 12u);
    CHECK(report.non_finite_dropped == 4u);
    REQUIRE(cloud.size() == 8u);
    std::size_t j = 0;
    for (const Eigen::Vector3f& p : pts) {
      if (std::isnan(p.x())) continue;
      CHECK(cloud[j] == p.cast<double>());
      ++j;
    }
  }
  // POINTS must agree with WIDTH x HEIGHT.
  std::string lying = binary;
  lying.replace(lying.find("POINTS 12"), 9, "POINTS 11");
  PointCloud cloud;
  const ppcr::Status s = read_mem("organized.pcd", lying, &cloud);
  CHECK(s.code() == StatusCode::kParseError);
  CHECK_THAT(s.message(), Catch::Contains("organized.pcd") && Catch::Contains("line 10") &&
                              Catch::Contains("POINTS 11") && Catch::Contains("4 x 3 = 12"));
}

TEST_CASE("PCD v.5 / v.6 headers: no VIEWPOINT, optional HEIGHT/COUNT/TYPE/POINTS", "[io][pcd]") {
  const std::string v5 =
      "# .PCD v.5 - Point Cloud Data file format\n"
      "VERSION .5\n"
      "FIELDS x y z\n"
      "SIZE 4 4 4\n"
      "TYPE F F F\n"
      "WIDTH 2\n"
      "POINTS 2\n"
      "DATA ascii\n"
      "1 2 3\n"
      "4 5 6\n";
  const std::string v6 =
      "# .PCD v.6 - Point Cloud Data file format\r\n"
      "VERSION .6\r\n"
      "COLUMNS x y z i\r\n"
      "SIZE 4 4 4 4\r\n"
      "COUNT 1 1 1 1\r\n"
      "WIDTH 2\r\n"
      "HEIGHT 1\r\n"
      "DATA ascii\r\n"
      "1 2 3 0\r\n"
      "4 5 6 0\r\n";
  for (const std::string& f : {v5, v6}) {
    PointCloud cloud;
    const ppcr::Status s = read_mem("old.pcd", f, &cloud);
    INFO(s.message());
    REQUIRE(s.ok());
    REQUIRE(cloud.size() == 2u);
    CHECK(cloud[0] == Eigen::Vector3d(1, 2, 3));
    CHECK(cloud[1] == Eigen::Vector3d(4, 5, 6));
  }
}
