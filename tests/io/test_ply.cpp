// PLY reading and writing: every variant is built byte by byte here and the decoded points are
// compared with the values put in (exact for double, float-rounded for float).
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

}  // namespace

TEST_CASE("PLY write/read round trip is bit-exact (binary little endian, double)", "[io][ply]") {
  io_test::TempDir dir;
  const PointCloud cloud = io_test::awkward_cloud(1000, 7);
  const std::string path = dir.file("cloud.ply");
  const ppcr::Status w = ppcr::io::write_cloud(path, cloud);
  REQUIRE(w.ok());

  // The file is what the contract says: a header, then 24 little-endian bytes per vertex.
  const std::string bytes = io_test::read_bytes(path);
  const std::size_t end = bytes.find("end_header\n");
  REQUIRE(end != std::string::npos);
  CHECK(bytes.find("format binary_little_endian 1.0\n") != std::string::npos);
  CHECK(bytes.find("element vertex 1000\n") != std::string::npos);
  CHECK(bytes.find("property double x\nproperty double y\nproperty double z\n") !=
        std::string::npos);
  CHECK(bytes.size() - (end + 11) == 1000u * 24u);
  std::string first;
  io_test::put<double>(&first, cloud[0].x());
  io_test::put<double>(&first, cloud[0].y());
  io_test::put<double>(&first, cloud[0].z());
  CHECK(bytes.substr(end + 11, 24) == first);

  PointCloud back;
  ReadReport report;
  const ppcr::Status r = ppcr::io::read_cloud(path, &back, &report);
  REQUIRE(r.ok());
  CHECK(io_test::bit_identical(cloud, back));
  CHECK(report.format == Format::kPly);
  CHECK(report.encoding == "binary_little_endian");
  CHECK(report.points_in_file == 1000u);
  CHECK(report.non_finite_dropped == 0u);
}

TEST_CASE("PLY big endian, float xyz with colours, list properties and faces around vertices",
          "[io][ply]") {
  const bool be = true;
  std::string f =
      "ply\n"
      "format binary_big_endian 1.0\n"
      "comment made by hand\n"
      "obj_info test file\n"
      "element face 2\n"
      "property list uchar int vertex_indices\n"
      "property uchar flags\n"
      "element vertex 3\n"
      "property float x\n"
      "property uchar red\n"
      "property float y\n"
      "property list ushort float extra\n"
      "property float z\n"
      "property uchar green\n"
      "element edge 2\n"
      "property int a\n"
      "property list int short b\n"
      "end_header\n";
  // faces (before the vertices): 3 and 4 indices
  io_test::put<std::uint8_t>(&f, 3, be);
  for (int i : {0, 1, 2}) io_test::put<std::int32_t>(&f, i, be);
  io_test::put<std::uint8_t>(&f, 0xff, be);
  io_test::put<std::uint8_t>(&f, 4, be);
  for (int i : {2, 1, 0, 1}) io_test::put<std::int32_t>(&f, i, be);
  io_test::put<std::uint8_t>(&f, 7, be);
  // vertices
  const double xyz[3][3] = {{0.1, -2.5, 1e-3}, {1e6, 3.14159265358979, -7.25}, {-0.0, 42.0, 1e-30}};
  const int extra_len[3] = {0, 2, 5};
  for (int v = 0; v < 3; ++v) {
    io_test::put<float>(&f, static_cast<float>(xyz[v][0]), be);
    io_test::put<std::uint8_t>(&f, static_cast<std::uint8_t>(200 + v), be);
    io_test::put<float>(&f, static_cast<float>(xyz[v][1]), be);
    io_test::put<std::uint16_t>(&f, static_cast<std::uint16_t>(extra_len[v]), be);
    for (int k = 0; k < extra_len[v]; ++k) io_test::put<float>(&f, 99.0f + k, be);
    io_test::put<float>(&f, static_cast<float>(xyz[v][2]), be);
    io_test::put<std::uint8_t>(&f, 17, be);
  }
  // edges (after the vertices)
  io_test::put<std::int32_t>(&f, 5, be);
  io_test::put<std::int32_t>(&f, 2, be);
  io_test::put<std::int16_t>(&f, -1, be);
  io_test::put<std::int16_t>(&f, 300, be);
  io_test::put<std::int32_t>(&f, 6, be);
  io_test::put<std::int32_t>(&f, 0, be);

  PointCloud cloud;
  ReadReport report;
  const ppcr::Status s = read_mem("hand.ply", f, &cloud, &report);
  INFO(s.message());
  REQUIRE(s.ok());
  REQUIRE(cloud.size() == 3u);
  for (int v = 0; v < 3; ++v) {
    for (int k = 0; k < 3; ++k) CHECK(cloud[v][k] == f32(xyz[v][k]));
  }
  CHECK(std::signbit(cloud[2][0]));
  CHECK(report.encoding == "binary_big_endian");
  CHECK(report.points_in_file == 3u);

  // The same file with one more byte after the last element is refused (counts disagree).
  PointCloud c2;
  const ppcr::Status extra = read_mem("hand.ply", f + "x", &c2);
  CHECK(extra.code() == StatusCode::kParseError);
  CHECK_THAT(extra.message(), Catch::Contains("hand.ply") && Catch::Contains("1 unexpected bytes"));
  CHECK(c2.empty());
}

TEST_CASE("PLY x y z of every numeric type, both byte orders", "[io][ply]") {
  struct TypeCase {
    const char* name;
    int kind;  // 0 int8, 1 uint8, 2 int16, 3 uint16, 4 int32, 5 uint32, 6 float, 7 double
  };
  const TypeCase cases[] = {{"char", 0},  {"int8", 0},    {"uchar", 1},  {"uint8", 1},
                            {"short", 2}, {"int16", 2},   {"ushort", 3}, {"uint16", 3},
                            {"int", 4},   {"int32", 4},   {"uint", 5},   {"uint32", 5},
                            {"float", 6}, {"float32", 6}, {"double", 7}, {"float64", 7}};
  // Per kind: three values that the type represents exactly, including its extremes.
  const double values[8][3] = {{-128, 127, -5},
                               {0, 255, 7},
                               {-32768, 32767, -300},
                               {0, 65535, 1234},
                               {-2147483648.0, 2147483647.0, -77},
                               {0, 4294967295.0, 99},
                               {0.5, -1.25e-8, 3.0e38},
                               {0.1, -1e300, 4.9e-324}};
  for (const TypeCase& tc : cases) {
    for (bool be : {false, true}) {
      std::string f = std::string("ply\nformat ") +
                      (be ? "binary_big_endian" : "binary_little_endian") +
                      " 1.0\nelement vertex 1\n";
      for (const char* axis : {"x", "y", "z"}) {
        f += std::string("property ") + tc.name + " " + axis + "\n";
      }
      f += "end_header\n";
      for (double v : values[tc.kind]) {
        switch (tc.kind) {
          case 0:
            io_test::put<std::int8_t>(&f, static_cast<std::int8_t>(v), be);
            break;
          case 1:
            io_test::put<std::uint8_t>(&f, static_cast<std::uint8_t>(v), be);
            break;
          case 2:
            io_test::put<std::int16_t>(&f, static_cast<std::int16_t>(v), be);
            break;
          case 3:
            io_test::put<std::uint16_t>(&f, static_cast<std::uint16_t>(v), be);
            break;
          case 4:
            io_test::put<std::int32_t>(&f, static_cast<std::int32_t>(v), be);
            break;
          case 5:
            io_test::put<std::uint32_t>(&f, static_cast<std::uint32_t>(v), be);
            break;
          case 6:
            io_test::put<float>(&f, static_cast<float>(v), be);
            break;
          default:
            io_test::put<double>(&f, v, be);
            break;
        }
      }
      PointCloud cloud;
      const ppcr::Status s = read_mem("types.ply", f, &cloud);
      INFO(tc.name << (be ? " big endian" : " little endian") << ": " << s.message());
      REQUIRE(s.ok());
      REQUIRE(cloud.size() == 1u);
      for (int k = 0; k < 3; ++k) {
        const double expected = tc.kind == 6 ? f32(values[tc.kind][k]) : values[tc.kind][k];
        CHECK(cloud[0][k] == expected);
      }
    }
  }
}

TEST_CASE("PLY ascii with CRLF, comments, lists and elements before and after", "[io][ply]") {
  const std::string f =
      "ply\r\n"
      "format ascii 1.0\r\n"
      "comment CRLF everywhere\r\n"
      "obj_info scanner 7\r\n"
      "element material 1\r\n"
      "property uchar r\r\n"
      "element vertex 4\r\n"
      "property int x\r\n"
      "property double y\r\n"
      "property float z\r\n"
      "property list uchar float curvature\r\n"
      "property float intensity\r\n"
      "element face 1\r\n"
      "property list uchar int vertex_indices\r\n"
      "end_header\r\n"
      "255\r\n"
      "1 0.1 -3.5e-2 0 0.5\r\n"
      "-2 1e300 +7 2 1 2 0.25\r\n"
      "\r\n"
      "3   -0.0\t2.5 1 9 nan\r\n"
      "4 nan 1 0 1\r\n"
      "3 0 1 2\r\n";
  PointCloud cloud;
  ReadReport report;
  const ppcr::Status s = read_mem("crlf.ply", f, &cloud, &report);
  INFO(s.message());
  REQUIRE(s.ok());
  REQUIRE(cloud.size() == 3u);
  CHECK(cloud[0] == Eigen::Vector3d(1, 0.1, -3.5e-2));
  CHECK(cloud[1] == Eigen::Vector3d(-2, 1e300, 7));
  CHECK(cloud[2] == Eigen::Vector3d(3, -0.0, 2.5));
  CHECK(std::signbit(cloud[2].y()));
  CHECK(report.points_in_file == 4u);
  CHECK(report.non_finite_dropped == 1u);  // the "nan" y of the 4th vertex
  CHECK(report.encoding == "ascii");
}

TEST_CASE("PLY non-finite vertices are dropped and counted, none finite is kEmptyCloud",
          "[io][ply]") {
  auto make = [](const std::vector<float>& coords) {
    std::string f = "ply\nformat binary_little_endian 1.0\nelement vertex " +
                    std::to_string(coords.size() / 3) +
                    "\nproperty float x\nproperty float y\nproperty float z\nend_header\n";
    for (float c : coords) io_test::put<float>(&f, c);
    return f;
  };
  const float nan = std::numeric_limits<float>::quiet_NaN();
  const float inf = std::numeric_limits<float>::infinity();
  PointCloud cloud;
  ReadReport report;
  ppcr::Status s =
      read_mem("nf.ply", make({1, 2, 3, nan, 0, 0, 4, -inf, 5, 6, 7, 8}), &cloud, &report);
  REQUIRE(s.ok());
  REQUIRE(cloud.size() == 2u);
  CHECK(cloud[0] == Eigen::Vector3d(1, 2, 3));
  CHECK(cloud[1] == Eigen::Vector3d(6, 7, 8));
  CHECK(report.non_finite_dropped == 2u);
  CHECK(report.points_in_file == 4u);

  s = read_mem("allnan.ply", make({nan, 0, 0, 0, inf, 0}), &cloud, &report);
  CHECK(s.code() == StatusCode::kEmptyCloud);
  CHECK_THAT(s.message(), Catch::Contains("allnan.ply") && Catch::Contains("2 points"));
  CHECK(report.non_finite_dropped == 2u);
  CHECK(cloud.empty());

  s = read_mem("zero.ply", make({}), &cloud, &report);
  CHECK(s.code() == StatusCode::kEmptyCloud);
  CHECK_THAT(s.message(), Catch::Contains("zero.ply") && Catch::Contains("zero points"));
}

TEST_CASE("PLY writer refuses non-finite points and reports unwritable paths", "[io][ply]") {
  io_test::TempDir dir;
  PointCloud cloud = {Eigen::Vector3d(1, 2, 3),
                      Eigen::Vector3d(0, std::numeric_limits<double>::quiet_NaN(), 0)};
  ppcr::Status s = ppcr::io::write_cloud(dir.file("nan.ply"), cloud);
  CHECK(s.code() == StatusCode::kInvalidArgument);
  CHECK_THAT(s.message(), Catch::Contains("nan.ply") && Catch::Contains("point 1"));

  cloud.pop_back();
  s = ppcr::io::write_cloud(dir.file("no/such/folder/c.ply"), cloud);
  CHECK(s.code() == StatusCode::kIoError);
  CHECK_THAT(s.message(), Catch::Contains("no/such/folder/c.ply"));

  s = ppcr::io::write_cloud(dir.path().string(), cloud, Format::kPly);
  CHECK(s.code() == StatusCode::kIoError);

  s = ppcr::io::write_cloud(dir.file("c.unknown"), cloud);
  CHECK(s.code() == StatusCode::kInvalidArgument);
  CHECK_THAT(s.message(), Catch::Contains("c.unknown"));

#ifdef __linux__
  // A full disk: /dev/full accepts the open and fails the writes.
  if (std::filesystem::exists("/dev/full")) {
    s = ppcr::io::write_cloud("/dev/full", io_test::awkward_cloud(100000, 3), Format::kPly);
    CHECK(s.code() == StatusCode::kIoError);
    CHECK_THAT(s.message(), Catch::Contains("/dev/full"));
  }
#endif
}

TEST_CASE("PLY writer writes an empty cloud as a valid file that reads as kEmptyCloud",
          "[io][ply]") {
  io_test::TempDir dir;
  const std::string path = dir.file("empty.ply");
  REQUIRE(ppcr::io::write_cloud(path, PointCloud()).ok());
  PointCloud back;
  CHECK(ppcr::io::read_cloud(path, &back).code() == StatusCode::kEmptyCloud);
}
