// ppcr_cli as a user runs it (std::system on the built tool, clouds written by the test): a
// failed write to stdout, an output path that cannot be written, empty and out-of-range values
// and the grouped --help each give a clear message and a non-zero status, never a crash.
#include <sys/wait.h>
#include <unistd.h>

#include <catch2/catch.hpp>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include "tools/cli_run.hpp"

namespace {

using cli_test::kDir;
using cli_test::read_text;
using cli_test::Run;
using cli_test::run_cli;

// A wavy surface and the same surface moved a little, as .xyz text (one NaN row in the source).
void write_pair() {
  std::filesystem::create_directories(kDir);
  std::ofstream target(kDir + "/target.xyz"), source(kDir + "/source.xyz");
  target.precision(17);
  source.precision(17);
  for (double x = -0.5; x <= 0.5; x += 0.02) {
    for (double y = -0.5; y <= 0.5; y += 0.02) {
      const double z = 0.1 * std::sin(4 * x) * std::cos(3 * y);
      target << x << ' ' << y << ' ' << z << '\n';
      source << x + 0.01 << ' ' << y - 0.01 << ' ' << z << '\n';
    }
  }
  source << "nan 0 0\n";
}

const std::string& pair_args() {
  static const std::string args =
      "'" + kDir + "/source.xyz' '" + kDir + "/target.xyz' --radius 0.1";
  return args;
}

bool contains(const std::string& s, const std::string& part) {
  return s.find(part) != std::string::npos;
}

}  // namespace

TEST_CASE("ppcr_cli registers, and its JSON counts the points the reader dropped", "[cli]") {
  write_pair();
  const Run r = run_cli(pair_args() + " --json");
  INFO(r.err);
  REQUIRE(r.status == 0);
  CHECK(contains(r.out, "\"source_non_finite\": 1"));
  CHECK(contains(r.out, "\"fitness\""));
  CHECK(contains(r.out, "\"inlier_rmse\""));
  CHECK(contains(r.out, "\"information\""));
  CHECK(contains(r.out, "\"covariance\""));
  CHECK(contains(r.err, "fitness"));
  CHECK(contains(r.err, "; 1-sigma "));
}

TEST_CASE("ppcr_cli counts the copies of a point it registered once", "[cli]") {
  write_pair();
  {
    std::ifstream in(kDir + "/source.xyz");
    std::ofstream out(kDir + "/copies.xyz");
    // One more point (off the grid), written 4 times: 3 copies.
    out << in.rdbuf() << "0.013 -0.017 0\n0.013 -0.017 0\n0.013 -0.017 0\n0.013 -0.017 0\n";
  }
  const std::string args = "'" + kDir + "/copies.xyz' '" + kDir + "/target.xyz' --radius 0.1";
  const Run json = run_cli(args + " --json");
  INFO(json.err);
  REQUIRE(json.status == 0);
  CHECK(contains(json.out, "\"source_duplicates\": 3"));
  CHECK(contains(json.out, "\"target_duplicates\": 0"));
  const Run text = run_cli(args);
  CHECK(contains(text.err, "copies of a point registered once: 3 in the source, 0 in the target"));
}

TEST_CASE("ppcr_cli: a stdout that cannot be written is exit 1", "[cli]") {
  write_pair();
  for (const std::string& args : {pair_args() + " --json", pair_args(), std::string("--help")}) {
    const Run r = run_cli(args, "/dev/full");
    INFO(args << ": " << r.err);
    CHECK(r.status == 1);
    CHECK(contains(r.err, "stdout"));
  }
}

TEST_CASE("ppcr_cli: an output path that cannot be written fails before the registration",
          "[cli]") {
  write_pair();
  for (const char* flag : {"--output-transform", "--output-cloud", "--trace"}) {
    const Run r = run_cli(pair_args() + " --verbose " + flag + " '" + kDir + "/no/such/dir/x'");
    INFO(flag << ": " << r.err);
    CHECK(r.status == 1);
    CHECK(contains(r.err, flag));
    CHECK(contains(r.err, "No such file or directory"));
    CHECK_FALSE(contains(r.err, "iter "));  // no iteration ran
  }
}

TEST_CASE("ppcr_cli: an output cloud of unknown format is refused before the registration",
          "[cli]") {
  write_pair();
  for (const char* name : {"/aligned.las", "/aligned.png"}) {  // .png: read, never written
    const std::string path = kDir + name;
    const Run r = run_cli(pair_args() + " --verbose --output-cloud '" + path + "'");
    INFO(r.err);
    CHECK(r.status == 2);
    CHECK(contains(r.err, "--output-cloud " + path + ": not a cloud format to write"));
    CHECK_FALSE(contains(r.err, "iter "));   // no iteration ran
    CHECK(access(path.c_str(), F_OK) != 0);  // and no file left
  }
}

TEST_CASE("ppcr_cli: empty, negative and oversized values are refused with the flag", "[cli]") {
  write_pair();
  const std::pair<const char*, const char*> cases[] = {
      {"--source-voxel ''", "--source-voxel"},
      {"--output-transform ''", "--output-transform"},
      {"--trace ''", "--trace"},
      {"--cost-drop-threshold -0.5", "--cost-drop-threshold"},
      {"--steps-threshold -1", "--steps-threshold"},
      {"--neighbour-cache 2147483647", "--neighbour-cache"},
      {"--radius -1", "--radius"},
  };
  for (const auto& [args, flag] : cases) {
    const Run r = run_cli(pair_args() + " " + args);
    INFO(args << ": " << r.err);
    CHECK(r.status == 2);
    CHECK(contains(r.err, flag));
  }
}

TEST_CASE("ppcr_cli --help groups the options", "[cli]") {
  const Run r = run_cli("--help");
  REQUIRE(r.status == 0);
  const std::size_t registration = r.out.find("Registration:");
  const std::size_t termination = r.out.find("Termination:");
  const std::size_t expert = r.out.find("Expert");
  REQUIRE(registration != std::string::npos);
  REQUIRE(termination != std::string::npos);
  REQUIRE(expert != std::string::npos);
  CHECK(registration < termination);
  CHECK(termination < expert);
  CHECK(r.out.find("--radius", registration) < termination);
  CHECK(r.out.find("--coarse-stride", expert) != std::string::npos);
  // Two examples and the exit codes; no parser artefacts (a negated flag's "{false}", a range
  // check's "FLOAT:FLOAT in [0 - 1]").
  CHECK(r.out.find("Examples:") != std::string::npos);
  CHECK(r.out.find("Exit status: 0 registered") != std::string::npos);
  CHECK(r.out.find("{false}") == std::string::npos);
  CHECK(r.out.find("FLOAT:") == std::string::npos);
  CHECK(r.out.find("--no-source-normals: off") != std::string::npos);
}

TEST_CASE("ppcr_cli: a mistyped flag is named with the closest flag, exit 2", "[cli]") {
  write_pair();
  Run r = run_cli(pair_args() + " --raduis 0.02");
  CHECK(r.status == 2);
  CHECK(r.err.find("--raduis: unknown flag; did you mean --radius?") != std::string::npos);
  r = run_cli(pair_args() + " --voxel-size 0.1");
  CHECK(r.status == 2);
  CHECK(r.err.find("did you mean --voxel?") != std::string::npos);
  r = run_cli(pair_args() + " --voxel 0.1 --source-voxel 0.2");  // one or the other
  CHECK(r.status == 2);
  CHECK(r.err.find("--voxel excludes --source-voxel") != std::string::npos);
}

TEST_CASE("ppcr_cli reports the verdict: JSON fields and the summary line", "[cli]") {
  write_pair();
  const Run r = run_cli(pair_args() + " --json");
  INFO(r.err);
  REQUIRE(r.status == 0);
  CHECK(contains(r.out, "\"quality\": \"good\""));
  CHECK(contains(r.out, "\"quality_reason\": \"\""));
  CHECK(contains(r.out, "\"close_fraction\""));
  CHECK(contains(r.out, "\"target_spacing\""));
  CHECK(contains(r.err, "quality good"));
}

// The wavy target cut to x <= 0.2 (so a part of the source has no counterpart), and a surface
// that coincides with the target nowhere.
void write_cut_and_other() {
  std::ofstream cut(kDir + "/cut.xyz"), other(kDir + "/other.xyz");
  cut.precision(17);
  other.precision(17);
  for (double x = -0.5; x <= 0.5; x += 0.02) {
    for (double y = -0.5; y <= 0.5; y += 0.02) {
      if (x <= 0.2) cut << x << ' ' << y << ' ' << 0.1 * std::sin(4 * x) * std::cos(3 * y) << '\n';
      other << x << ' ' << y << ' ' << 0.15 * std::sin(11 * x + 1) * std::cos(9 * y) << '\n';
    }
  }
}

TEST_CASE("ppcr_cli --min-fitness: below it, exit 3 with the outputs written", "[cli]") {
  write_pair();
  write_cut_and_other();
  const std::string transform = kDir + "/min_fitness.txt";
  std::filesystem::remove(transform);
  const std::string args = "'" + kDir + "/source.xyz' '" + kDir + "/cut.xyz' --radius 0.1";
  Run r = run_cli(args + " --json");
  INFO(r.err);
  REQUIRE(r.status == 0);
  CHECK(contains(r.out, "\"fitness\": 0.7"));  // about 3/4 of the source is within the radius
  r = run_cli(args + " --min-fitness 0.8 --output-transform '" + transform + "'");
  CHECK(r.status == 3);
  CHECK(contains(r.err, "below --min-fitness 0.8"));
  CHECK(std::filesystem::exists(transform));
  CHECK(r.out.size() > 0);  // the matrix is still printed
  r = run_cli(args + " --min-fitness 0.6");
  CHECK(r.status == 0);
  r = run_cli(args + " --min-fitness 1.5");
  CHECK(r.status == 2);
  CHECK(contains(r.err, "--min-fitness"));
}

TEST_CASE("ppcr_cli: a result that fails the verdict is exit 3, never 0", "[cli]") {
  write_pair();
  write_cut_and_other();
  const Run r = run_cli("'" + kDir + "/other.xyz' '" + kDir + "/target.xyz' --radius 0.1 --json");
  INFO(r.err << r.out);
  CHECK(r.status == 3);
  CHECK(contains(r.out, "\"quality\": \"failed\""));
  CHECK(contains(r.err, "failed its quality check"));
}

TEST_CASE("ppcr_cli without --radius: the automatic radius, named in the JSON", "[cli]") {
  write_pair();
  const std::string clouds = "'" + kDir + "/source.xyz' '" + kDir + "/target.xyz'";
  Run r = run_cli(clouds + " --json");
  INFO(r.err);
  REQUIRE(r.status == 0);
  CHECK(contains(r.out, "\"radius_source\": \"auto\""));
  // The grid's spacing is 2 cm: 8 spacings.
  CHECK(contains(r.out, "\"radius_used\": 0.16"));
  CHECK(contains(r.err, "radius 0.16"));
  r = run_cli(pair_args() + " --json");
  CHECK(contains(r.out, "\"radius_source\": \"user\""));
  CHECK(contains(r.out, "\"radius_used\": 0.1"));
}
