// ppcr_odometry on a TUM RGB-D folder (the first frames of ../shared/data/tum_fr1_rpy, linked into
// a folder of TUM's layout): its depth images registered in time order, their timestamps in the
// TUM output, and --evaluate against TUM's ground truth, paired by time.
#include <sys/wait.h>

#include <algorithm>
#include <catch2/catch.hpp>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "test_data.hpp"

namespace fs = std::filesystem;

TEST_CASE("a TUM RGB-D folder runs as a sequence with its frames' times, and evaluates") {
  const fs::path data = ppcr_test::data_path("tum_fr1_rpy");
  std::vector<fs::path> frames;
  for (const auto& e : fs::directory_iterator(data / "depth")) frames.push_back(e.path());
  std::sort(frames.begin(), frames.end());
  REQUIRE(frames.size() == 100u);
  const fs::path dir = fs::path(PPCR_SEQUENCE_TEST_DIR) / "tum";
  fs::remove_all(dir);
  fs::create_directories(dir / "depth");
  for (std::size_t i = 0; i < 4; ++i)
    fs::create_symlink(frames[i], dir / "depth" / frames[i].filename());
  fs::create_symlink(data / "groundtruth.txt", dir / "groundtruth.txt");
  fs::create_symlink(data / "depth.txt", dir / "depth.txt");  // with depth/: TUM's layout

  const std::string out = (dir / "estimate.txt").string();
  const std::string command = std::string("'") + PPCR_ODOMETRY_EXE + "' '" + dir.string() +
                              "' --depth-intrinsics 517.3 516.5 318.6 255.3 --voxel 0.02 "
                              "--radius 0.1 --quiet --tum '" +
                              out + "' 2> '" + out + ".err'";
  int status = std::system(command.c_str());
  INFO(command);
  REQUIRE(WIFEXITED(status));
  REQUIRE(WEXITSTATUS(status) == 0);
  std::ifstream estimate(out);
  std::vector<std::string> times;
  for (std::string line; std::getline(estimate, line);)
    times.push_back(line.substr(0, line.find(' ')));
  REQUIRE(times.size() == 4u);
  for (std::size_t i = 0; i < 4; ++i) {  // the name's time, to the last digit
    CHECK(std::stod(times[i]) == std::stod(frames[i].stem().string()));
    CHECK(times[i].size() <= frames[i].stem().string().size());
  }

  const std::string evaluate = std::string("'") + PPCR_ODOMETRY_EXE + "' --evaluate '" +
                               (dir / "groundtruth.txt").string() + "' '" + out + "' > '" + out +
                               ".eval' 2>&1";
  status = std::system(evaluate.c_str());
  REQUIRE(WIFEXITED(status));
  CHECK(WEXITSTATUS(status) == 0);
  std::ifstream printed_file(out + ".eval");
  std::stringstream printed;
  printed << printed_file.rdbuf();
  INFO(printed.str());
  CHECK(printed.str().find("paired by timestamp: 4 of 4") != std::string::npos);
  const std::size_t at = printed.str().find("poses 4 ate_rmse ");
  REQUIRE(at != std::string::npos);
  const double ate = std::stod(printed.str().substr(at + 17));
  CHECK(ate < 0.02);  // metres, over 4 frames (0.1 s); the truth itself is good to ~1 cm here
}
