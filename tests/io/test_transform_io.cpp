// Transform files: 4x4 (or 3x4) rigid matrices in text, exact round trips, and refusals of
// non-rigid or malformed matrices with messages saying what is wrong.
#include <catch2/catch.hpp>
#include <cmath>
#include <random>
#include <string>

#include "io_test_util.hpp"
#include "ppcr/io.hpp"

using ppcr::StatusCode;

namespace {

ppcr::Status parse(const std::string& name, const std::string& text, Eigen::Isometry3d* T) {
  return ppcr::io::read_transform_from_buffer(name, text.data(), text.size(), T);
}

Eigen::Isometry3d random_rigid(std::mt19937_64* rng) {
  std::normal_distribution<double> g(0.0, 1.0);
  const Eigen::Quaterniond q(g(*rng), g(*rng), g(*rng), g(*rng));
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = q.normalized().toRotationMatrix();
  T.translation() = Eigen::Vector3d(g(*rng), g(*rng), g(*rng)) * 100.0;
  return T;
}

}  // namespace

TEST_CASE("Transform write/read round trip is bit-exact", "[io][transform]") {
  io_test::TempDir dir;
  std::mt19937_64 rng(3);
  for (int i = 0; i < 50; ++i) {
    const Eigen::Isometry3d T = random_rigid(&rng);
    const std::string path = dir.file("T.txt");
    REQUIRE(ppcr::io::write_transform(path, T).ok());
    Eigen::Isometry3d back = Eigen::Isometry3d::Identity();
    const ppcr::Status s = ppcr::io::read_transform(path, &back);
    INFO(s.message());
    REQUIRE(s.ok());
    for (int r = 0; r < 4; ++r) {
      for (int c = 0; c < 4; ++c) CHECK(back.matrix()(r, c) == T.matrix()(r, c));
    }
  }
  // The file is 4 lines of 4 numbers, "%.17g".
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.translation() = Eigen::Vector3d(0.1, -2, 1e-20);
  REQUIRE(ppcr::io::write_transform(dir.file("t.txt"), T).ok());
  CHECK(io_test::read_bytes(dir.file("t.txt")) ==
        "1 0 0 0.10000000000000001\n0 1 0 -2\n0 0 1 9.9999999999999995e-21\n0 0 0 1\n");
}

TEST_CASE("Transform text: 16 or 12 numbers, comments, any blank layout", "[io][transform]") {
  const double c = std::cos(0.3), s = std::sin(0.3);
  char rows[512];
  std::snprintf(rows, sizeof(rows),
                "# ground truth\n%.17g %.17g 0 1.5\n%.17g %.17g 0 -2 # row 2\n\n0 0 1 0.25\n", c,
                -s, s, c);
  Eigen::Isometry3d T;
  for (const std::string& text : {std::string(rows), std::string(rows) + "0 0 0 1\n"}) {
    const ppcr::Status st = parse("gt.txt", text, &T);
    INFO(st.message());
    REQUIRE(st.ok());
    CHECK(T.matrix()(0, 0) == c);
    CHECK(T.matrix()(0, 1) == -s);
    CHECK(T.matrix()(1, 0) == s);
    CHECK(T.translation() == Eigen::Vector3d(1.5, -2, 0.25));
    CHECK(T.matrix().row(3) == Eigen::RowVector4d(0, 0, 0, 1));
  }
  // All on one line, CRLF.
  REQUIRE(parse("one.txt", "1 0 0 0 0 1 0 0 0 0 1 0 0 0 0 1\r\n", &T).ok());
  CHECK(T.matrix() == Eigen::Matrix4d::Identity());
}

TEST_CASE("Transform files that are not rigid or not 4x4 are refused with the reason",
          "[io][transform]") {
  struct Case {
    const char* text;
    const char* needles[2];
  };
  const Case cases[] = {
      {"1.03 0 0 0\n0 1 0 0\n0 0 1 0\n0 0 0 1\n", {"R^T R deviates from I by 0.06", ""}},
      {"2 0 0 0\n0 2 0 0\n0 0 2 0\n0 0 0 1\n", {"not orthonormal", ""}},
      {"-1 0 0 0\n0 1 0 0\n0 0 1 0\n0 0 0 1\n", {"det R = -1", "reflection"}},
      {"1 0 0 0\n0 1 0 0\n0 0 1 0\n0 0 0.5 1\n", {"last row", "expected (0 0 0 1)"}},
      {"1 0 0\n0 1 0\n0 0 1\n", {"found 9 numbers", "expected 16"}},
      {"1 0 0 0\n0 1 x 0\n0 0 1 0\n0 0 0 1\n", {"line 2, column 5", "'x'"}},
      {"1 0 0 0\n0 1 0 0\n0 0 1 nan\n0 0 0 1\n", {"line 3, column 7", "non-finite"}},
      {"1 0 0 0 0 1 0 0 0 0 1 0 0 0 0 1 5\n", {"line 1, column 33", "17th value"}},
      {"", {"empty", ""}},
  };
  for (const Case& c : cases) {
    Eigen::Isometry3d T;
    const ppcr::Status s = parse("T.txt", c.text, &T);
    INFO(c.text << " -> " << s.message());
    CHECK(s.code() == StatusCode::kParseError);
    CHECK_THAT(s.message(), Catch::Contains("T.txt"));
    for (const char* needle : c.needles) CHECK_THAT(s.message(), Catch::Contains(needle));
  }
  Eigen::Isometry3d T;
  io_test::TempDir dir;
  ppcr::Status s = ppcr::io::read_transform(dir.file("none.txt"), &T);
  CHECK(s.code() == StatusCode::kIoError);
  CHECK_THAT(s.message(), Catch::Contains("none.txt"));

  Eigen::Isometry3d bad = Eigen::Isometry3d::Identity();
  bad.linear() *= 1.1;
  s = ppcr::io::write_transform(dir.file("bad.txt"), bad);
  CHECK(s.code() == StatusCode::kInvalidArgument);
  CHECK_THAT(s.message(), Catch::Contains("bad.txt") && Catch::Contains("deviates"));
}
