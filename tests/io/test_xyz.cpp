// XYZ / CSV / PTS text reading and writing.
#include <catch2/catch.hpp>
#include <cmath>
#include <string>

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

}  // namespace

TEST_CASE("XYZ write/read round trip is bit-exact (17 significant digits)", "[io][xyz]") {
  io_test::TempDir dir;
  const PointCloud cloud = io_test::awkward_cloud(2000, 5);
  for (const char* name : {"c.xyz", "c.txt", "c.csv", "c.PTS"}) {
    const std::string path = dir.file(name);
    REQUIRE(ppcr::io::write_cloud(path, cloud).ok());
    PointCloud back;
    ReadReport report;
    const ppcr::Status s = ppcr::io::read_cloud(path, &back, &report);
    INFO(name << ": " << s.message());
    REQUIRE(s.ok());
    CHECK(io_test::bit_identical(cloud, back));
    CHECK(report.format == Format::kXyz);
    CHECK(report.points_in_file == 2000u);
  }
  // The text is "%.17g" per coordinate, one point per line.
  const std::string text = io_test::read_bytes(dir.file("c.xyz"));
  char expected[200];
  std::snprintf(expected, sizeof(expected), "%.17g %.17g %.17g\n", cloud[2].x(), cloud[2].y(),
                cloud[2].z());
  std::size_t third_line = 0;
  for (int i = 0; i < 2; ++i) third_line = text.find('\n', third_line) + 1;
  CHECK(text.substr(third_line, std::strlen(expected)) == expected);
}

TEST_CASE("XYZ whitespace and comma separated, comments, blank lines, CRLF", "[io][xyz]") {
  const std::string f =
      "# a comment line\n"
      "\n"
      "1 2 3\n"
      "  4\t5   6  # trailing comment\r\n"
      "\r\n"
      "7,8,9\n"
      "-1e-3 , +2.5 ,3E2\n"
      "   # indented comment\n"
      "0.1 0.2 0.3";  // no final newline
  PointCloud cloud;
  ReadReport report;
  const ppcr::Status s = read_mem("mixed.xyz", f, &cloud, &report);
  INFO(s.message());
  REQUIRE(s.ok());
  REQUIRE(cloud.size() == 5u);
  CHECK(cloud[0] == Eigen::Vector3d(1, 2, 3));
  CHECK(cloud[1] == Eigen::Vector3d(4, 5, 6));
  CHECK(cloud[2] == Eigen::Vector3d(7, 8, 9));
  CHECK(cloud[3] == Eigen::Vector3d(-1e-3, 2.5, 300));
  CHECK(cloud[4] == Eigen::Vector3d(0.1, 0.2, 0.3));
  CHECK(report.points_in_file == 5u);
}

TEST_CASE("CSV with a header of column names and extra columns", "[io][xyz]") {
  const std::string f =
      "# exported\n"
      "x,y,z,intensity,ring\n"
      "1.5,2.5,3.5,100,0\n"
      "-1,-2,-3,nan,1\n";
  PointCloud cloud;
  ReadReport report;
  const ppcr::Status s = read_mem("scan.csv", f, &cloud, &report);
  INFO(s.message());
  REQUIRE(s.ok());
  REQUIRE(cloud.size() == 2u);
  CHECK(cloud[0] == Eigen::Vector3d(1.5, 2.5, 3.5));
  CHECK(cloud[1] == Eigen::Vector3d(-1, -2, -3));
  CHECK(report.non_finite_dropped == 0u);  // the NaN is in a skipped column
}

TEST_CASE("XYZ: a header is tolerated only as the first non-comment line", "[io][xyz]") {
  PointCloud cloud;
  const ppcr::Status s = read_mem("late.csv", "1,2,3\nx,y,z\n4,5,6\n", &cloud);
  CHECK(s.code() == StatusCode::kParseError);
  CHECK_THAT(s.message(), Catch::Contains("late.csv") && Catch::Contains("line 2") &&
                              Catch::Contains("field 1") && Catch::Contains("'x'"));
  CHECK(cloud.empty());
}

TEST_CASE("XYZ errors name the file, line, field and text", "[io][xyz]") {
  struct Case {
    const char* text;
    const char* needles[3];
  };
  const Case cases[] = {
      {"1 2 3\n4 five 6\n", {"line 2", "field 2", "'five'"}},
      {"1 2 3\n4 5 6abc\n", {"line 2", "field 3", "'6abc'"}},
      {"1 2 3\n4 5\n", {"line 2", "at least 3", "found 2"}},
      {"1 2 3\n4 5 6 7\n", {"line 2", "4 fields", "line 1 has 3"}},
      {"1,,3\n", {"line 1", "field 2", "empty field"}},
      {"1,2,3,\n", {"line 1", "field 4", "empty field"}},
      {"1 2 3\n1 2 0x10\n", {"line 2", "field 3", "'0x10'"}},
      {"1 2 3\n1 2 1e999\n", {"line 2", "field 3", "'1e999'"}},
      {"1 2 3\n\x01\x02 1 2\n", {"line 2", "field 1", "\\x01\\x02"}},
  };
  for (const Case& c : cases) {
    PointCloud cloud;
    const ppcr::Status s = read_mem("bad.xyz", c.text, &cloud);
    INFO(c.text << " -> " << s.message());
    CHECK(s.code() == StatusCode::kParseError);
    CHECK_THAT(s.message(), Catch::Contains("bad.xyz"));
    for (const char* needle : c.needles) CHECK_THAT(s.message(), Catch::Contains(needle));
    CHECK(cloud.empty());
  }
}

// Points run together on a line (20 lines of 6000 numbers: "x y z x y z ...") were read as 20
// points, the first three fields of each line. A line holds one point: at most 64 fields.
TEST_CASE("XYZ: a line of more fields than a point has is refused with its count", "[io][xyz]") {
  auto line_of = [](int fields) {
    std::string line;
    for (int i = 0; i < fields; ++i) line += (i ? " " : "") + std::to_string(i % 3 + 1);
    return line + "\n";
  };
  std::string text;
  for (int i = 0; i < 20; ++i) text += line_of(6000);
  PointCloud cloud;
  ppcr::Status s = read_mem("run_together.xyz", text, &cloud);
  INFO(s.message());
  CHECK(s.code() == StatusCode::kParseError);
  CHECK_THAT(s.message(), Catch::Contains("run_together.xyz") &&
                              Catch::Contains("line 1 has 6000 fields") &&
                              Catch::Contains("one point per line"));
  CHECK(cloud.empty());
  // The same with commas, and after a first line of a plausible width.
  std::string commas = line_of(3) + line_of(65);
  for (char& c : commas) c = c == ' ' ? ',' : c;
  s = read_mem("wide.csv", commas, &cloud);
  CHECK(s.code() == StatusCode::kParseError);
  CHECK_THAT(s.message(), Catch::Contains("wide.csv") && Catch::Contains("line 2 has 65 fields"));
  // A header of too many names is refused alike; 64 fields are a point.
  std::string header = "x y z";
  for (int i = 3; i < 70; ++i) header += " a" + std::to_string(i);
  s = read_mem("header.txt", header + "\n" + line_of(70), &cloud);
  CHECK(s.code() == StatusCode::kParseError);
  CHECK_THAT(s.message(), Catch::Contains("line 1 has 70 fields"));
  s = read_mem("wide_ok.xyz", line_of(64) + line_of(64), &cloud);
  CHECK(s.ok());
  CHECK(cloud.size() == 2u);
}

TEST_CASE("XYZ NaN/inf points are dropped and counted, a file of none is kEmptyCloud",
          "[io][xyz]") {
  PointCloud cloud;
  ReadReport report;
  ppcr::Status s = read_mem("n.xyz", "1 2 3\nnan 1 1\n4 inf 6\n7 8 9\n", &cloud, &report);
  REQUIRE(s.ok());
  CHECK(cloud.size() == 2u);
  CHECK(report.non_finite_dropped == 2u);
  CHECK(report.points_in_file == 4u);

  s = read_mem("n.xyz", "nan nan nan\n", &cloud, &report);
  CHECK(s.code() == StatusCode::kEmptyCloud);
  CHECK_THAT(s.message(), Catch::Contains("n.xyz"));

  s = read_mem("only_comments.xyz", "# nothing\n\n# here\n", &cloud, &report);
  CHECK(s.code() == StatusCode::kEmptyCloud);
  s = read_mem("only_header.csv", "x,y,z\n", &cloud, &report);
  CHECK(s.code() == StatusCode::kEmptyCloud);
}

TEST_CASE("PTS: a point count on the first line is checked against the data", "[io][xyz]") {
  PointCloud cloud;
  ppcr::Status s = read_mem("scan.pts", "2\n1 2 3 10 255 0 0\n4 5 6 11 0 255 0\n", &cloud);
  INFO(s.message());
  REQUIRE(s.ok());
  REQUIRE(cloud.size() == 2u);
  CHECK(cloud[1] == Eigen::Vector3d(4, 5, 6));

  s = read_mem("scan.pts", "3\n1 2 3 10 255 0 0\n4 5 6 11 0 255 0\n", &cloud);
  CHECK(s.code() == StatusCode::kParseError);
  CHECK_THAT(s.message(), Catch::Contains("scan.pts") && Catch::Contains("line 1") &&
                              Catch::Contains("3 points") && Catch::Contains("holds 2"));
  CHECK(cloud.empty());
}
