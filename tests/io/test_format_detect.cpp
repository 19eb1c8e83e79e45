// Format choice: by extension (any case), else by the first bytes; unknown content is an error
// showing the first bytes escaped.
#include <catch2/catch.hpp>
#include <string>

#include "io_test_util.hpp"
#include "ppcr/io.hpp"

using ppcr::PointCloud;
using ppcr::StatusCode;
using ppcr::io::Format;
using ppcr::io::ReadReport;

TEST_CASE("Format from extension is case-insensitive", "[io][format]") {
  using ppcr::io::format_from_extension;
  CHECK(format_from_extension("a/b.ply") == Format::kPly);
  CHECK(format_from_extension("B.PLY") == Format::kPly);
  CHECK(format_from_extension("x.Pcd") == Format::kPcd);
  for (const char* name : {"c.xyz", "c.TXT", "c.csv", "c.pts", "dir.v2/c.XyZ"}) {
    CHECK(format_from_extension(name) == Format::kXyz);
  }
  CHECK(format_from_extension("noext") == Format::kAuto);
  CHECK(format_from_extension("dir.ply/noext") == Format::kAuto);
  CHECK(format_from_extension("c.dat") == Format::kAuto);
  CHECK(format_from_extension("c.bin") == Format::kKittiBin);
  CHECK(std::string(ppcr::io::to_string(Format::kPcd)) == "pcd");
}

TEST_CASE("Format from content when the extension says nothing", "[io][format]") {
  struct Case {
    std::string text;
    Format format;
  };
  const Case cases[] = {
      {"ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float y\n"
       "property float z\nend_header\n1 2 3\n",
       Format::kPly},
      {"ply\r\nformat ascii 1.0\r\nelement vertex 1\r\nproperty float x\r\nproperty float y\r\n"
       "property float z\r\nend_header\r\n1 2 3\r\n",
       Format::kPly},
      {"# .PCD v0.7\nVERSION 0.7\nFIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nWIDTH 1\nDATA ascii\n"
       "1 2 3\n",
       Format::kPcd},
      {"VERSION .7\nFIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nWIDTH 1\nDATA ascii\n1 2 3\n",
       Format::kPcd},
      {"FIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nWIDTH 1\nDATA ascii\n1 2 3\n", Format::kPcd},
      {"# scan\n\n1 2 3\n", Format::kXyz},
      {"x,y,z\n1,2,3\n", Format::kXyz},
      {"-1.5e3 2 3\n", Format::kXyz},
  };
  for (const Case& c : cases) {
    PointCloud cloud;
    ReadReport report;
    const ppcr::Status s = ppcr::io::read_cloud_from_buffer(
        "data.dat", c.text.data(), c.text.size(), Format::kAuto, &cloud, &report);
    INFO(c.text << " -> " << s.message());
    REQUIRE(s.ok());
    CHECK(report.format == c.format);
    CHECK(cloud.size() == 1u);
  }
  // Reading by path: the extension wins over the content.
  io_test::TempDir dir;
  io_test::write_bytes(dir.file("really_xyz.ply"), "1 2 3\n");
  PointCloud cloud;
  ppcr::Status s = ppcr::io::read_cloud(dir.file("really_xyz.ply"), &cloud);
  CHECK(s.code() == StatusCode::kParseError);
  CHECK_THAT(s.message(), Catch::Contains("really_xyz.ply") && Catch::Contains("line 1"));
  // ... unless a format is given.
  s = ppcr::io::read_cloud(dir.file("really_xyz.ply"), &cloud, nullptr, Format::kXyz);
  CHECK(s.ok());
  CHECK(cloud.size() == 1u);
}

TEST_CASE("Unknown content names the file and shows the first bytes escaped", "[io][format]") {
  const std::string text = std::string(
      "\x7f"
      "ELF\x02\x01\x01\0\0\0",
      10);
  PointCloud cloud;
  const ppcr::Status s =
      ppcr::io::read_cloud_from_buffer("prog", text.data(), text.size(), Format::kAuto, &cloud);
  CHECK(s.code() == StatusCode::kParseError);
  CHECK_THAT(s.message(),
             Catch::Contains("prog") && Catch::Contains("\\x7fELF\\x02\\x01\\x01\\x00"));
}
