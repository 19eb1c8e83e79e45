// ppcr_odometry (tools/odometry) on sequences from ppcr_synth --sequence: the trajectory it
// writes is close to the exact ground truth, an unreadable scan stops it with a message naming
// the scan and the poses of the scans before it on disk, folders are read in natural order.
#include <sys/wait.h>

#include <algorithm>
#include <catch2/catch.hpp>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <memory>
#include <sstream>
#include <string>
#include <vector>

#include "odometry/odometry.hpp"
#include "odometry/pair_log.hpp"
#include "odometry/pair_registrar.hpp"
#include "odometry/scan_list.hpp"
#include "odometry/trajectory_format.hpp"
#include "odometry/trajectory_metrics.hpp"
#include "odometry/trajectory_writer.hpp"
#include "ppcr/io.hpp"
#include "ppcr/synthetic.hpp"

namespace {

namespace fs = std::filesystem;

constexpr double kAteBound = 0.03;  // metres, on a 1.3-1.6 m room path with 1 cm noise

// A fresh folder for one test case (ctest may run the cases in parallel).
fs::path case_dir(const std::string& name) {
  const fs::path dir = fs::path(PPCR_SEQUENCE_TEST_DIR) / name;
  fs::remove_all(dir);
  fs::create_directories(dir);
  return dir;
}

int run(const std::string& exe, const std::string& arguments, const fs::path& stderr_path) {
  const std::string command = "'" + exe + "' " + arguments + " > '" + stderr_path.string() +
                              ".out' 2> '" + stderr_path.string() + "'";
  const int status = std::system(command.c_str());
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

std::string read_text(const fs::path& path) {
  std::ifstream file(path);
  std::stringstream text;
  text << file.rdbuf();
  return text.str();
}

std::vector<std::string> lines_of(const fs::path& path) {
  std::ifstream file(path);
  std::vector<std::string> lines;
  for (std::string line; std::getline(file, line);) lines.push_back(line);
  return lines;
}

// A room sequence of `scans` scans with 1 cm range noise in dir/seq (ppcr_synth --sequence).
void make_sequence(const fs::path& dir, int scans) {
  const std::string arguments = "'" + (dir / "seq").string() + "' --sequence " +
                                std::to_string(scans) + " --noise 0.01 --seed 3";
  REQUIRE(run(PPCR_SYNTH_EXE, arguments, dir / "synth.err") == 0);
}

ppcr_odometry::Trajectory read_trajectory(const fs::path& path) {
  ppcr_odometry::Trajectory t;
  const ppcr::Status s = ppcr_odometry::read_trajectory(path.string(), &t);
  INFO(s.to_string());
  REQUIRE(s.ok());
  return t;
}

double ate(const ppcr_odometry::Trajectory& truth, const ppcr_odometry::Trajectory& estimate) {
  ppcr_odometry::TrajectoryErrors errors;
  REQUIRE(ppcr_odometry::trajectory_errors(truth.poses, estimate.poses, 1, &errors).ok());
  return errors.ate_rmse;
}

// ppcr, counting the targets made from the previous source; with `fresh`, each target is made
// with set_target() from the cloud instead.
class CountingRegistrar : public ppcr_odometry::PairRegistrar {
 public:
  CountingRegistrar(const ppcr::RegistrationOptions& o, bool fresh)
      : ppcr_(ppcr_odometry::make_ppcr_registrar(o)), fresh_(fresh) {}
  std::string name() const override { return ppcr_->name(); }
  ppcr::Status set_target(const ppcr::PointCloud& target) override {
    return ppcr_->set_target(target);
  }
  ppcr::Status set_target_to_source(const ppcr::PointCloud& target) override {
    ++reused;
    return fresh_ ? ppcr_->set_target(target) : ppcr_->set_target_to_source(target);
  }
  ppcr_odometry::PairOutcome align(const ppcr::PointCloud& source,
                                   const Eigen::Isometry3d& T_guess) override {
    return ppcr_->align(source, T_guess);
  }
  int reused = 0;

 private:
  std::unique_ptr<ppcr_odometry::PairRegistrar> ppcr_;
  bool fresh_;
};

}  // namespace

TEST_CASE(
    "scan to scan, each target is the previous source as align() prepared it: the same "
    "trajectory as targets made from the files") {
  const fs::path dir = case_dir("reuse");
  make_sequence(dir, 8);
  std::vector<std::string> scans;
  REQUIRE(ppcr_odometry::list_scans({(dir / "seq/scans").string()}, &scans).ok());
  REQUIRE(scans.size() == 8);
  ppcr::RegistrationOptions o;
  o.radius = 0.25;  // below the scans' extents: the same internal unit both ways, same bits
  o.source_voxel = o.target_voxel = 0.05;
  ppcr_odometry::OdometrySettings settings;
  settings.times.assign(scans.size(), 0.0);
  settings.quiet = true;
  std::vector<std::string> kitti;
  for (const bool fresh : {true, false}) {
    CountingRegistrar registrar(o, fresh);
    const std::string path = (dir / (fresh ? "fresh.kitti" : "reused.kitti")).string();
    ppcr_odometry::TrajectoryWriter trajectory;
    REQUIRE(trajectory.open(path, "").ok());
    ppcr_odometry::PairLog log;
    ppcr_odometry::OdometrySummary summary;
    REQUIRE(
        ppcr_odometry::run_odometry(scans, settings, &registrar, &trajectory, &log, &summary).ok());
    REQUIRE(trajectory.close().ok());
    CHECK(registrar.reused == 6);  // every target but the first pair's
    kitti.push_back(read_text(path));
  }
  CHECK(kitti[0] == kitti[1]);
  CHECK(std::count(kitti[1].begin(), kitti[1].end(), '\n') == 8);
}

TEST_CASE("the ground truth files hold the library's exact trajectory in the first scan's frame") {
  const fs::path dir = case_dir("ground_truth");
  make_sequence(dir, 12);
  ppcr::synthetic::SequenceOptions options;
  options.scans = 12;
  options.seed = 3;
  std::vector<Eigen::Isometry3d> world;
  REQUIRE(ppcr::synthetic::make_sequence_trajectory(options, &world).ok());
  const ppcr_odometry::Trajectory kitti = read_trajectory(dir / "seq/ground_truth_kitti.txt");
  const ppcr_odometry::Trajectory tum = read_trajectory(dir / "seq/ground_truth_tum.txt");
  REQUIRE(kitti.poses.size() == 12);
  REQUIRE(tum.poses.size() == 12);
  for (std::size_t i = 0; i < 12; ++i) {
    const Eigen::Matrix4d expected = (world[0].inverse() * world[i]).matrix();
    CHECK((kitti.poses[i].matrix() - expected).norm() < 1e-12);
    CHECK((tum.poses[i].matrix() - expected).norm() < 1e-12);
    CHECK(tum.times[i] == Approx(0.1 * static_cast<double>(i)));
    CHECK(fs::exists(dir / "seq/scans" / ("scan_00000" + std::to_string(i % 10) + ".ply")));
  }
}

TEST_CASE("a short room sequence registered scan to scan and to a local map tracks the truth") {
  const fs::path dir = case_dir("track");
  make_sequence(dir, 15);
  const ppcr_odometry::Trajectory truth = read_trajectory(dir / "seq/ground_truth_kitti.txt");
  // 0: no --local-map (ppcr's default, 5).
  for (const int local_map : {1, 3, 5, 0}) {
    INFO("--local-map " << local_map);
    const fs::path out = dir / ("map" + std::to_string(local_map));
    const std::string flag = local_map > 0 ? " --local-map " + std::to_string(local_map) : "";
    const std::string arguments = "'" + (dir / "seq/scans").string() + "'" + flag + " --kitti '" +
                                  out.string() + ".kitti' --tum '" + out.string() +
                                  ".tum' --pairs '" + out.string() + ".csv'";
    REQUIRE(run(PPCR_ODOMETRY_EXE, arguments, out.string() + ".err") == 0);
    CHECK(read_text(out.string() + ".err").find("scans/s") != std::string::npos);
    const ppcr_odometry::Trajectory kitti = read_trajectory(out.string() + ".kitti");
    const ppcr_odometry::Trajectory tum = read_trajectory(out.string() + ".tum");
    REQUIRE(kitti.poses.size() == 15);
    REQUIRE(tum.poses.size() == 15);
    CHECK(ate(truth, kitti) < kAteBound);
    CHECK(ate(truth, tum) < kAteBound);
    const std::vector<std::string> rows = lines_of(out.string() + ".csv");
    REQUIRE(rows.size() == 15);  // the header and one row per registered pair
    CHECK(rows[0].rfind("scan,file,method,fitness,quality", 0) == 0);
    CHECK(rows[1].find(",ppcr,") != std::string::npos);
  }
  CHECK(read_text(dir / "map0.kitti") == read_text(dir / "map5.kitti"));
  CHECK(read_text(dir / "map0.kitti") != read_text(dir / "map1.kitti"));
}

// A KITTI velodyne/ folder: the sequence's scans as 000000.bin... (float32 x y z intensity), with
// KITTI's times.txt beside them, registered as the .ply scans are (float32 rounding apart).
TEST_CASE("a folder of KITTI .bin frames registers, its times.txt skipped") {
  const fs::path dir = case_dir("kitti_bin");
  make_sequence(dir, 6);
  const fs::path velodyne = dir / "velodyne";
  fs::create_directories(velodyne);
  std::vector<fs::path> plys;
  for (const auto& e : fs::directory_iterator(dir / "seq/scans")) plys.push_back(e.path());
  std::sort(plys.begin(), plys.end());
  REQUIRE(plys.size() == 6u);
  for (std::size_t i = 0; i < plys.size(); ++i) {
    ppcr::PointCloud cloud;
    REQUIRE(ppcr::io::read_cloud(plys[i].string(), &cloud).ok());
    char name[32];
    std::snprintf(name, sizeof name, "%06zu.bin", i);
    REQUIRE(ppcr::io::write_cloud((velodyne / name).string(), cloud).ok());
  }
  std::ofstream(velodyne / "times.txt") << "0.0\n0.1\n0.2\n0.3\n0.4\n0.5\n";
  const fs::path out = dir / "est";
  REQUIRE(run(PPCR_ODOMETRY_EXE, "'" + velodyne.string() + "' --kitti '" + out.string() + ".kitti'",
              out.string() + ".err") == 0);
  CHECK(read_text(out.string() + ".err").find("times.txt") != std::string::npos);  // skipped
  const ppcr_odometry::Trajectory truth = read_trajectory(dir / "seq/ground_truth_kitti.txt");
  const ppcr_odometry::Trajectory estimate = read_trajectory(out.string() + ".kitti");
  REQUIRE(estimate.poses.size() == 6u);
  CHECK(ate(truth, estimate) < kAteBound);
}

TEST_CASE("the evaluation (--evaluate) prints the ATE and RPE of an estimate") {
  const fs::path dir = case_dir("evaluate");
  make_sequence(dir, 6);
  const std::string truth = (dir / "seq/ground_truth_kitti.txt").string();
  const std::string tum = (dir / "seq/ground_truth_tum.txt").string();
  REQUIRE(run(PPCR_ODOMETRY_EXE, "--evaluate '" + truth + "' '" + tum + "'", dir / "eval.err") ==
          0);
  const std::string printed = read_text(dir / "eval.err.out");
  CHECK(printed.rfind("poses 6 ate_rmse ", 0) == 0);
  std::istringstream fields(printed.substr(std::string("poses 6 ate_rmse ").size()));
  double ate_value = -1.0;
  fields >> ate_value;
  CHECK(ate_value < 1e-9);  // the same trajectory in two formats
  CHECK(run(PPCR_ODOMETRY_EXE, "--evaluate '" + truth + "'", dir / "one.err") == 2);
  // A KITTI estimate shorter than the truth: compared by index over the shorter, and said.
  {
    std::ofstream shorter(dir / "short.kitti");
    const auto lines = lines_of(truth);
    for (std::size_t i = 0; i + 2 < lines.size(); ++i) shorter << lines[i] << "\n";
  }
  CHECK(run(PPCR_ODOMETRY_EXE,
            "--evaluate '" + truth + "' '" + (dir / "short.kitti").string() + "'",
            dir / "short.err") == 0);
  CHECK(read_text(dir / "short.err.out").rfind("poses 4 ", 0) == 0);
  CHECK(read_text(dir / "short.err").find("the ground truth has 6 poses and the estimate 4") !=
        std::string::npos);
}

// TUM files carry times: each estimated pose is compared with the truth interpolated at its
// time. Truth at 10 Hz and an estimate at other times, both sampled from one motion with constant
// velocity and angular velocity (which linear interpolation and slerp reproduce): ATE 0.
TEST_CASE("the evaluation pairs TUM trajectories by timestamp") {
  const fs::path dir = case_dir("evaluate_tum");
  auto pose_at = [](double t) {
    Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
    T.linear() = Eigen::AngleAxisd(0.4 * t, Eigen::Vector3d(0, 0.6, 0.8)).toRotationMatrix();
    T.translation() = Eigen::Vector3d(0.5, -0.2, 0.1) * t;
    return T;
  };
  {
    std::ofstream truth(dir / "truth.tum"), estimate(dir / "estimate.tum");
    for (int k = 0; k <= 45; ++k)
      truth << ppcr_odometry::tum_line(100.0 + 0.1 * k, pose_at(0.1 * k)) << "\n";
    for (int k = 0; k < 30; ++k) {  // 6 Hz, starting between two true poses; the last 3 outside
      const double t = 0.033 + k / 6.0;
      estimate << ppcr_odometry::tum_line(100.0 + t, pose_at(t)) << "\n";
    }
  }
  REQUIRE(run(PPCR_ODOMETRY_EXE,
              "--evaluate '" + (dir / "truth.tum").string() + "' '" +
                  (dir / "estimate.tum").string() + "'",
              dir / "eval.err") == 0);
  const std::string printed = read_text(dir / "eval.err.out");
  REQUIRE(printed.rfind("poses 30 ate_rmse ", 0) != 0);  // not paired by index
  REQUIRE(printed.rfind("poses 27 ate_rmse ", 0) == 0);
  std::istringstream fields(printed.substr(std::string("poses 27 ate_rmse ").size()));
  double ate_value = -1.0;
  fields >> ate_value;
  CHECK(ate_value < 1e-9);
  CHECK(read_text(dir / "eval.err").find("paired by timestamp: 27 of 30") != std::string::npos);
}

TEST_CASE("a sequence whose first scan cannot be read leaves no output file") {
  const fs::path dir = case_dir("failed_start");
  make_sequence(dir, 3);
  std::ofstream(dir / "seq/scans/scan_000000.ply") << "ply\nformat ascii 1.0\nend_header\ngarbage";
  const fs::path out = dir / "out";
  const std::string arguments = "'" + (dir / "seq/scans").string() + "' --kitti '" + out.string() +
                                ".kitti' --tum '" + out.string() + ".tum' --pairs '" +
                                out.string() + ".csv'";
  CHECK(run(PPCR_ODOMETRY_EXE, arguments, out.string() + ".err") == 1);
  CHECK(read_text(out.string() + ".err").find("(no output written)") != std::string::npos);
  CHECK_FALSE(fs::exists(out.string() + ".kitti"));
  CHECK_FALSE(fs::exists(out.string() + ".tum"));
  CHECK_FALSE(fs::exists(out.string() + ".csv"));
}

TEST_CASE("an unreadable scan stops the sequence naming it, with the poses before it on disk") {
  const fs::path dir = case_dir("unreadable");
  make_sequence(dir, 8);
  std::ofstream(dir / "seq/scans/scan_000004.ply") << "ply\nformat ascii 1.0\nend_header\ngarbage";
  const fs::path out = dir / "out";
  const std::string arguments = "'" + (dir / "seq/scans").string() + "' --kitti '" + out.string() +
                                ".kitti' --tum '" + out.string() + ".tum' --pairs '" +
                                out.string() + ".csv'";
  CHECK(run(PPCR_ODOMETRY_EXE, arguments, out.string() + ".err") == 1);
  const std::string message = read_text(out.string() + ".err");
  CHECK(message.find("error: scan 4 (") != std::string::npos);
  CHECK(message.find("scan_000004.ply") != std::string::npos);
  // Scans 0-3 have their poses, each a complete line: 12 (KITTI) or 8 (TUM) numbers.
  for (const auto& [extension, numbers] :
       {std::pair<std::string, std::size_t>{".kitti", 12}, {".tum", 8}}) {
    const std::string text = read_text(out.string() + extension);
    REQUIRE(!text.empty());
    CHECK(text.back() == '\n');
    const std::vector<std::string> lines = lines_of(out.string() + extension);
    CHECK(lines.size() == 4);
    for (const std::string& line : lines) {
      std::istringstream fields(line);
      std::size_t count = 0;
      for (double v; fields >> v;) ++count;
      CHECK(count == numbers);
    }
    CHECK(read_trajectory(out.string() + extension).poses.size() == 4);
  }
  CHECK(lines_of(out.string() + ".csv").size() == 4);  // header + pairs 1-3
}

TEST_CASE("a folder of unpadded scan numbers is registered in natural order") {
  const fs::path dir = case_dir("natural");
  make_sequence(dir, 12);
  const fs::path renamed = dir / "renamed";
  fs::create_directories(renamed);
  for (int i = 0; i < 12; ++i) {
    char name[32];
    std::snprintf(name, sizeof(name), "scan_%06d.ply", i);
    fs::copy_file(dir / "seq/scans" / name, renamed / ("scan_" + std::to_string(i) + ".ply"));
  }
  const fs::path out = dir / "out";
  const std::string arguments = "'" + renamed.string() + "' --kitti '" + out.string() +
                                ".kitti' --pairs '" + out.string() + ".csv' --quiet";
  REQUIRE(run(PPCR_ODOMETRY_EXE, arguments, out.string() + ".err") == 0);
  CHECK(read_text(out.string() + ".err").empty());  // --quiet
  const std::vector<std::string> rows = lines_of(out.string() + ".csv");
  REQUIRE(rows.size() == 12);
  for (int i = 1; i < 12; ++i) {
    const std::string file = "scan_" + std::to_string(i) + ".ply,";
    CHECK(rows[static_cast<std::size_t>(i)].find(file) != std::string::npos);
  }
  const ppcr_odometry::Trajectory truth = read_trajectory(dir / "seq/ground_truth_kitti.txt");
  CHECK(ate(truth, read_trajectory(out.string() + ".kitti")) < kAteBound);
}

TEST_CASE("one output is enough, while none or bad values exit 2 with one line naming it") {
  const fs::path dir = case_dir("usage");
  make_sequence(dir, 3);
  const std::string scans = "'" + (dir / "seq/scans").string() + "'";
  const fs::path tum = dir / "only.tum";
  REQUIRE(run(PPCR_ODOMETRY_EXE, scans + " --tum '" + tum.string() + "'", dir / "only.err") == 0);
  CHECK(read_trajectory(tum).poses.size() == 3);
  std::ofstream(dir / "times.txt") << "100.5\n100.625\n\n100.75\n";
  const std::string timed =
      " --tum '" + tum.string() + "' --timestamps '" + (dir / "times.txt").string() + "'";
  REQUIRE(run(PPCR_ODOMETRY_EXE, scans + timed, dir / "timed.err") == 0);
  CHECK(read_trajectory(tum).times == std::vector<double>{100.5, 100.625, 100.75});
  std::ofstream(dir / "short.txt") << "1\n2\n";
  CHECK(run(PPCR_ODOMETRY_EXE,
            scans + " --tum t --timestamps '" + (dir / "short.txt").string() + "'",
            dir / "short.err") == 2);
  CHECK(read_text(dir / "short.err").find("2 times for 3 scans") != std::string::npos);
  CHECK(run(PPCR_ODOMETRY_EXE, scans, dir / "no_output.err") == 2);
  CHECK(read_text(dir / "no_output.err").find("--kitti") != std::string::npos);
  CHECK(run(PPCR_ODOMETRY_EXE, scans + " --kitti k --method nothing", dir / "method.err") == 2);
  CHECK(read_text(dir / "method.err").find("--method") != std::string::npos);
  CHECK(run(PPCR_ODOMETRY_EXE, scans + " --kitti k --local-map 0", dir / "map.err") == 2);
  CHECK(run(PPCR_ODOMETRY_EXE, scans + " --kitti k --radius -1", dir / "radius.err") == 2);
  CHECK(read_text(dir / "radius.err").find("--radius") != std::string::npos);
}
