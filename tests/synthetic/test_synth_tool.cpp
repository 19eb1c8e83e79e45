// ppcr_synth (tools/synth): the files it writes agree with make_scan_pair() exactly, its problem
// file follows the benchmark's format and protocol, and bad arguments fail with one line.
#include <sys/wait.h>

#include <catch2/catch.hpp>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "ppcr/io.hpp"
#include "ppcr/synthetic.hpp"

namespace {

/// Runs ppcr_synth with `arguments`, stderr into `stderr_path`; returns the exit code.
int run_tool(const std::string& arguments, const std::string& stderr_path) {
  const std::string command = std::string("'") + PPCR_SYNTH_EXE + "' " + arguments +
                              " > /dev/null 2> '" + stderr_path + "'";
  const int status = std::system(command.c_str());
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

std::string read_text(const std::string& path) {
  std::ifstream file(path);
  std::stringstream text;
  text << file.rdbuf();
  return text.str();
}

ppcr::PointCloud read(const std::string& path) {
  ppcr::PointCloud cloud;
  const ppcr::Status status = ppcr::io::read_cloud(path, &cloud);
  INFO(path << ": " << status.to_string());
  REQUIRE(status.ok());
  return cloud;
}

}  // namespace

TEST_CASE("ppcr_synth writes the pair, its ground truth and benchmark problems",
          "[synthetic][tool]") {
  const std::string dir = std::string(PPCR_SYNTH_TEST_DIR) + "/street";
  const std::string log = std::string(PPCR_SYNTH_TEST_DIR) + "_street.log";
  std::filesystem::create_directories(PPCR_SYNTH_TEST_DIR);
  REQUIRE(run_tool("'" + dir +
                       "' --scene street --seed 9 --noise 0.01 --outliers 0.2 --rotation 12 "
                       "--translation 4 --problems 7 --max-problem-rotation 25 "
                       "--max-problem-translation 0.5",
                   log) == 0);

  ppcr::synthetic::ScanOptions options;
  options.scene = ppcr::synthetic::SceneKind::kStreet;
  options.seed = 9;
  options.noise_sigma = 0.01;
  options.outlier_fraction = 0.2;
  options.rotation_deg = 12;
  options.translation_m = 4;
  ppcr::synthetic::ScanPair pair;
  REQUIRE(ppcr::synthetic::make_scan_pair(options, &pair).ok());

  // Clouds and ground truth are exact (double PLY, 17 significant digits).
  CHECK(read(dir + "/source.ply") == pair.source);
  CHECK(read(dir + "/target.ply") == pair.target);
  Eigen::Isometry3d gt;
  REQUIRE(ppcr::io::read_transform(dir + "/ground_truth.txt", &gt).ok());
  CHECK(gt.matrix() == pair.T_target_source.matrix());
  const ppcr::PointCloud source_gt_frame = read(dir + "/source_gt_frame.ply");
  REQUIRE(source_gt_frame.size() == pair.source.size());
  Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
  for (std::size_t i = 0; i < pair.source.size(); ++i) {
    CHECK((source_gt_frame[i] - pair.T_target_source * pair.source[i]).norm() == 0.0);
    centroid += source_gt_frame[i];
  }
  centroid /= static_cast<double>(source_gt_frame.size());

  // problems.txt: header, then `id source target overlap t1..t12` with local misplacements.
  std::ifstream problems(dir + "/problems.txt");
  std::string line;
  REQUIRE(std::getline(problems, line));
  CHECK(line == "id source target overlap t1 t2 t3 t4 t5 t6 t7 t8 t9 t10 t11 t12");
  int count = 0;
  while (std::getline(problems, line)) {
    std::istringstream fields(line);
    std::string id;
    std::string source;
    std::string target;
    double overlap = 0.0;
    Eigen::Matrix4d T0 = Eigen::Matrix4d::Identity();
    fields >> id >> source >> target >> overlap;
    for (int r = 0; r < 3; ++r) {
      for (int c = 0; c < 4; ++c) fields >> T0(r, c);
    }
    REQUIRE(fields);
    std::string extra;
    CHECK(!(fields >> extra));
    CHECK(source == "source_gt_frame.ply");
    CHECK(target == "target.ply");
    CHECK(overlap > 0.2);  // 20 % of the source points are outliers
    CHECK(overlap < 0.8);
    const Eigen::Matrix3d R = T0.topLeftCorner<3, 3>();
    CHECK((R.transpose() * R - Eigen::Matrix3d::Identity()).norm() < 1e-12);
    CHECK(R.determinant() == Approx(1.0));
    CHECK(Eigen::AngleAxisd(R).angle() <= 25.0 * std::acos(-1.0) / 180.0 + 1e-12);
    // Rotation about the source centroid: the centroid only moves by the translation part.
    const Eigen::Vector3d moved = R * centroid + T0.topRightCorner<3, 1>();
    CHECK((moved - centroid).norm() <= 0.5 + 1e-9);
    ++count;
  }
  CHECK(count == 7);
}

TEST_CASE("ppcr_synth: the objects scene seen by the depth camera, with its noise models",
          "[synthetic][tool]") {
  const std::string dir = std::string(PPCR_SYNTH_TEST_DIR) + "/objects";
  const std::string log = std::string(PPCR_SYNTH_TEST_DIR) + "_objects.log";
  std::filesystem::create_directories(PPCR_SYNTH_TEST_DIR);
  // The camera preset, one flag overriding it; --translation defaults to 0.3 for the objects.
  REQUIRE(run_tool("'" + dir +
                       "' --scene objects --sensor camera --steps 160 --seed 4 --noise 0.001 "
                       "--noise-per-metre 0.002 --depth-quantisation 0.003 --problems 2",
                   log) == 0);
  ppcr::synthetic::ScanOptions options;
  options.scene = ppcr::synthetic::SceneKind::kObjects;
  options.seed = 4;
  options.sensor = ppcr::synthetic::depth_camera(160, 240);
  options.noise_sigma = 0.001;
  options.noise_per_metre = 0.002;
  options.depth_quantisation = 0.003;
  options.translation_m = 0.3;
  ppcr::synthetic::ScanPair pair;
  REQUIRE(ppcr::synthetic::make_scan_pair(options, &pair).ok());
  CHECK(read(dir + "/source.ply") == pair.source);
  CHECK(read(dir + "/target.ply") == pair.target);
  Eigen::Isometry3d gt;
  REQUIRE(ppcr::io::read_transform(dir + "/ground_truth.txt", &gt).ok());
  CHECK(gt.matrix() == pair.T_target_source.matrix());
}

TEST_CASE("ppcr_synth rejects bad arguments with one line naming them", "[synthetic][tool]") {
  const std::string dir = std::string(PPCR_SYNTH_TEST_DIR) + "/bad";
  const std::string log = std::string(PPCR_SYNTH_TEST_DIR) + "_bad.log";
  std::filesystem::create_directories(PPCR_SYNTH_TEST_DIR);
  struct Case {
    std::string arguments;
    std::vector<std::string> expected;  // substrings of the error line
  };
  const std::vector<Case> cases = {
      {"--noise -1", {"--noise", "-1"}},
      {"--outliers 1", {"--outliers", "1"}},
      {"--translation 5", {"--translation", "5"}},
      {"--scene forest", {"--scene", "forest"}},
      {"--beams 0", {"--beams", "0"}},
      {"--seed -3", {"--seed", "-3"}},
      {"--noise abc", {"--noise", "abc"}},
      {"--max-problem-rotation 200", {"--max-problem-rotation", "200"}},
      {"--noise-per-metre -0.5", {"--noise-per-metre", "-0.5"}},
      {"--depth-quantisation -1", {"--depth-quantisation", "-1"}},
      {"--sensor camera --hfov 200", {"--hfov", "200"}},
      {"--sensor sonar", {"--sensor", "sonar"}},
      {"--scene objects --translation 1", {"--translation", "1"}},
  };
  for (const Case& c : cases) {
    INFO(c.arguments);
    CHECK(run_tool("'" + dir + "' " + c.arguments, log) == 2);
    const std::string error = read_text(log);
    INFO(error);
    CHECK(error.rfind("ppcr_synth: error: ", 0) == 0);
    CHECK(error.find('\n') == error.size() - 1);  // one line
    for (const std::string& part : c.expected) CHECK(error.find(part) != std::string::npos);
  }
  CHECK(run_tool("", log) == 2);  // OUT_DIR missing
}
