// Registration of the real scans in ../shared/data (see its README.md) against their ground
// truths: the paper's 45-degree bunny pair and an outdoor LiDAR pair started from a perturbed
// ground truth. Skipped (exit 77) when the data folder is absent.
#include <catch2/catch.hpp>
#include <cmath>
#include <fstream>
#include <limits>
#include <sstream>
#include <string>
#include <vector>

#include "core_test_util.hpp"
#include "ppcr/metrics.hpp"
#include "ppcr/registration.hpp"
#include "ppcr/se3.hpp"
#include "test_data.hpp"

#if defined(PPCR_TEST_HAVE_IO)
#include "ppcr/io.hpp"
#endif

using ppcr::PointCloud;
using ppcr::RegistrationOptions;
using ppcr::RegistrationResult;

namespace {

#if defined(PPCR_TEST_HAVE_IO)
PointCloud load_cloud(const std::string& relative) {
  PointCloud cloud;
  const ppcr::Status s = ppcr::io::read_cloud(ppcr_test::data_path(relative), &cloud);
  INFO(s.to_string());
  REQUIRE(s.ok());
  return cloud;
}
#else
// Without ppcr_io (configured with PPCR_BUILD_IO=OFF): the data's own format only, binary
// little-endian PLY whose vertex element has float x, y, z as its first properties.
PointCloud load_cloud(const std::string& relative) {
  const std::string path = ppcr_test::data_path(relative);
  std::ifstream in(path, std::ios::binary);
  REQUIRE(in.good());
  std::string line;
  std::size_t count = 0;
  int properties = 0;
  bool in_vertex = false;
  while (std::getline(in, line) && line != "end_header") {
    std::istringstream ls(line);
    std::string word;
    ls >> word;
    if (word == "format") {
      std::string fmt;
      ls >> fmt;
      REQUIRE(fmt == "binary_little_endian");
    } else if (word == "element") {
      std::string name;
      ls >> name;
      in_vertex = name == "vertex";
      if (in_vertex) ls >> count;
    } else if (word == "property" && in_vertex) {
      std::string type;
      ls >> type;
      REQUIRE(type == "float");
      ++properties;
    }
  }
  REQUIRE(properties >= 3);
  PointCloud cloud(count);
  std::vector<float> row(static_cast<std::size_t>(properties));
  for (std::size_t i = 0; i < count; ++i) {
    in.read(reinterpret_cast<char*>(row.data()),
            static_cast<std::streamsize>(row.size() * sizeof(float)));
    REQUIRE(in.good());
    cloud[i] = Eigen::Vector3d(row[0], row[1], row[2]);
  }
  return cloud;
}
#endif

// 16 numbers, row-major; re-orthonormalised (the files carry 9 significant digits).
Eigen::Isometry3d load_transform(const std::string& relative) {
  std::ifstream in(ppcr_test::data_path(relative));
  REQUIRE(in.good());
  Eigen::Matrix4d M;
  for (int r = 0; r < 4; ++r) {
    for (int c = 0; c < 4; ++c) REQUIRE(static_cast<bool>(in >> M(r, c)));
  }
  REQUIRE(ppcr::se3::is_rigid(M, 1e-5));
  Eigen::Isometry3d T;
  T.matrix() = M;
  return ppcr::se3::orthonormalized(T);
}

std::string describe(const RegistrationResult& r, const Eigen::Isometry3d& T_gt) {
  std::ostringstream s;
  s << r.status.to_string() << ", stop " << ppcr::to_string(r.stop_reason) << ", " << r.iterations
    << " iterations, " << r.source_points << " / " << r.target_points << " points, scale "
    << r.scale << ", rotation error " << ppcr::rotation_error_deg(r.T_target_source, T_gt)
    << " deg, translation error " << ppcr::translation_error(r.T_target_source, T_gt);
  return s.str();
}

// The trace is finite and the costs in it are those the cost drop is computed from.
void check_trace(const RegistrationResult& r) {
  REQUIRE(static_cast<int>(r.history.size()) == r.iterations);
  for (const ppcr::IterationRecord& h : r.history) {
    INFO("iteration " << h.iteration);
    CHECK(std::isfinite(h.initial_cost));
    CHECK(std::isfinite(h.final_cost));
    CHECK(h.initial_cost > 0.0);
    CHECK(h.final_cost >= 0.0);
    CHECK(h.cost_drop == Approx((h.initial_cost - h.final_cost) / h.initial_cost).margin(1e-15));
    CHECK(std::isfinite(h.mse_prev));
    CHECK(h.mse_prev >= 0.0);
    CHECK(std::isfinite(h.scale));
    CHECK(h.scale > 0.0);
    CHECK(h.matched_source_points > 0u);
    CHECK(h.T_target_source.matrix().allFinite());
    CHECK(ppcr::se3::is_rigid(h.T_target_source.matrix(), 1e-9));
  }
  CHECK(r.initial_cost == r.history.front().initial_cost);
  CHECK(r.final_cost == r.history.back().final_cost);
  // The stop was the cost drop: the last cost_drop_patience + 1 drops were below 1 %.
  if (r.stop_reason == ppcr::StopReason::kCostDrop) {
    const int patience = RegistrationOptions().expert.cost_drop_patience;
    REQUIRE(r.iterations >= patience + 1);
    for (int i = r.iterations - patience - 1; i < r.iterations; ++i) {
      CHECK(r.history[static_cast<std::size_t>(i)].cost_drop < 0.01);
    }
  }
}

// The settings both scans are registered with: each error model, and the plane model's options
// that docs/BENCHMARK.md rows use.
struct Setting {
  const char* name;
  ppcr::ErrorModel model;
  bool source_normals;
  double noise_floor;
  double dof = 5.0;
  int max_neighbours = 10;
  int coarse_stride = -1;  // automatic

  void apply(RegistrationOptions* o) const {
    o->error_model = model;
    o->expert.source_normals = source_normals;
    o->expert.noise_floor = noise_floor;
    o->dof = dof;
    o->max_neighbours = max_neighbours;
    o->expert.coarse_stride = coarse_stride;
  }
};

const Setting kSettings[] = {
    {"plane", ppcr::ErrorModel::kPlane, false, 0.0},
    {"plane, source normals", ppcr::ErrorModel::kPlane, true, 0.0},
    {"plane, source normals, noise floor", ppcr::ErrorModel::kPlane, true, 1.0},
    {"issue #8's setting: floor 0.8, dof 1.25, 5 neighbours, stride 3", ppcr::ErrorModel::kPlane,
     true, 0.8, 1.25, 5, 3},
    {"point", ppcr::ErrorModel::kPoint, false, 0.0},
};

// Checks shared by both scans' settings: k reaches the association (at most k pairs per matched
// source point), and the plane model's noise floor reaches the scale schedule through align() (the
// synthetic registration test shows that the floor binds).
void check_wiring(const Setting& setting, const RegistrationResult& r) {
  CHECK(r.correspondences <=
        static_cast<std::size_t>(setting.max_neighbours) * r.matched_source_points);
  if (setting.model == ppcr::ErrorModel::kPlane && setting.noise_floor > 0.0) {
    CHECK(r.scale >= 0.999 * setting.noise_floor * r.target_surface_noise);
  }
}

}  // namespace

TEST_CASE("bunny: bun045 onto bun000 from identity (the paper's 45-degree case)", "[real]") {
  const PointCloud target = load_cloud("bunny/bun000.ply");
  const PointCloud source = load_cloud("bunny/bun045.ply");
  const Eigen::Isometry3d T_gt = load_transform("bunny/bun045_gt.txt");
  CHECK(target.size() == 40256u);
  CHECK(source.size() == 40097u);
  // The start is far: the ground truth's rotation is 34.3 degrees (the scan is nominally at 45
  // degrees, as the data README says, but bun045_gt.txt rotates by 34.3).
  CHECK(ppcr::rotation_error_deg(Eigen::Isometry3d::Identity(), T_gt) > 30.0);
  // Measured when written: plane 0.066 degrees / 0.05 mm, with source normals 0.080 /
  // 0.04 mm, with the noise floor 0.082 / 0.04 mm, with 5 neighbours and coarse stride 3
  // 0.046 / 0.02 mm; point 0.39 degrees / 0.5 mm (the
  // authors' code: 3.7-4.3 degrees on these clouds in metres, 0.52 in millimetres).
  for (const Setting& setting : kSettings) {
    RegistrationOptions o;
    o.radius = 0.02;
    o.source_voxel = o.target_voxel = 0.002;
    setting.apply(&o);
    const bool plane = setting.model == ppcr::ErrorModel::kPlane;
    const RegistrationResult r = ppcr::align(source, target, o);
    INFO(setting.name << ": " << describe(r, T_gt) << ", surface noise " << r.target_surface_noise);
    REQUIRE(r.status.ok());
    CHECK(r.converged());
    check_wiring(setting, r);
    if (plane) {
      // The scanner's surface noise at the 2 mm voxel: measured 0.22 mm.
      CHECK(r.target_surface_noise > 1e-4);
      CHECK(r.target_surface_noise < 4e-4);
    }
    CHECK(ppcr::rotation_error_deg(r.T_target_source, T_gt) < (plane ? 0.2 : 0.6));
    CHECK(ppcr::translation_error(r.T_target_source, T_gt) < (plane ? 5e-4 : 1e-3));
    check_trace(r);
    // Evaluated after the run (ppcr::evaluate): the error fell over the run.
    const ppcr::PoseErrors first = ppcr::evaluate(source, r.history.front().T_target_source, T_gt);
    const ppcr::PoseErrors last = ppcr::evaluate(source, r.history.back().T_target_source, T_gt);
    CHECK(last.mse < 0.01 * first.mse);
    CHECK(last.benchmark_error < first.benchmark_error);
  }
}

TEST_CASE("lidar: back to the ground truth from a 10 degree / 0.5 m perturbation", "[real]") {
  const PointCloud source = load_cloud("lidar/source.ply");
  const PointCloud target = load_cloud("lidar/target.ply");
  const Eigen::Isometry3d T_gt = load_transform("lidar/source_gt.txt");
  for (const Setting& setting : kSettings) {
    RegistrationOptions o;
    o.radius = 1.0;
    o.source_voxel = o.target_voxel = 0.2;
    setting.apply(&o);
    const bool plane = setting.model == ppcr::ErrorModel::kPlane;
    for (double sign : {1.0, -1.0}) {
      // Perturbation in the target frame: 10 degrees about an axis near the vertical, 0.5 m
      // horizontally.
      const Eigen::Isometry3d perturbation =
          core_test::make_pose(Eigen::Vector3d(0.1, 0.05, 1.0), sign * core_test::deg2rad(10.0),
                               0.5 * Eigen::Vector3d(0.8, 0.6, 0.0));
      const Eigen::Isometry3d T0 = perturbation * T_gt;
      REQUIRE(ppcr::rotation_error_deg(T0, T_gt) == Approx(10.0).epsilon(1e-9));
      const RegistrationResult r = ppcr::align(source, target, o, T0);
      INFO(setting.name << ", yaw sign " << sign << ": " << describe(r, T_gt) << ", surface noise "
                        << r.target_surface_noise);
      REQUIRE(r.status.ok());
      CHECK(r.converged());
      check_wiring(setting, r);
      if (plane) {
        // The beam-sparse scans' surface noise at the 0.2 m voxel: measured 6.0 cm.
        CHECK(r.target_surface_noise > 0.03);
        CHECK(r.target_surface_noise < 0.1);
      }
      // Measured when written (both yaw signs): plane 0.13 degrees / 8 mm (the issue's
      // EM prototype: a 1.2 degree local minimum on this yaw), with source normals 0.15 degrees /
      // 7 mm, with the noise floor 0.21 degrees / 4 mm, issue #8's setting with 5 neighbours and
      // coarse stride 3 0.14 degrees / 8 mm; point 0.19 degrees / 10 mm.
      CHECK(ppcr::rotation_error_deg(r.T_target_source, T_gt) < 0.3);
      CHECK(ppcr::translation_error(r.T_target_source, T_gt) < 0.03);
      check_trace(r);
    }
  }
}

namespace {
// Every coordinate times c, rounded to float32 when as_float (as a float file would hold it).
// The bunny pair bun045 -> bun000 with its truth, and the benchmark protocol's options for it.
struct BunnyPair {
  PointCloud source, target;
  Eigen::Isometry3d T_gt;
  RegistrationOptions protocol_options() const {
    RegistrationOptions o;
    o.radius = 0.02;
    o.source_voxel = o.target_voxel = 0.002;
    return o;
  }
};

BunnyPair load_bunny() {
  return {load_cloud("bunny/bun045.ply"), load_cloud("bunny/bun000.ply"),
          load_transform("bunny/bun045_gt.txt")};
}

PointCloud scaled(const PointCloud& cloud, double c, bool as_float = false) {
  PointCloud out(cloud.size());
  for (std::size_t i = 0; i < cloud.size(); ++i) {
    out[i] = c * cloud[i];
    if (as_float) out[i] = out[i].cast<float>().cast<double>();
  }
  return out;
}
}  // namespace

// Units never change the answer (the solver works in units of the radius): the bunny pair with
// its benchmark radius and voxels, every length scaled by c. In double precision the scaled pair
// is the same problem to rounding; stored as float32 (as most files are), each scale rounds the
// coordinates differently, a relative change of ~6e-8.
TEST_CASE("bunny: the same rotation in any units, 1e-12 to 1e12, double and float32", "[real]") {
  const BunnyPair bunny = load_bunny();
  const PointCloud& target = bunny.target;
  const PointCloud& source = bunny.source;
  const Eigen::Isometry3d& T_gt = bunny.T_gt;
  const RegistrationOptions o = bunny.protocol_options();
  const RegistrationResult ref = ppcr::align(source, target, o);
  INFO(describe(ref, T_gt));
  REQUIRE(ref.converged());
  REQUIRE(ppcr::rotation_error_deg(ref.T_target_source, T_gt) < 0.5);
  for (bool as_float : {false, true}) {
    for (double c : {1e-12, 1e-9, 1e-3, 1e3, 1e9, 1e12}) {
      RegistrationOptions oc = o;
      oc.radius = c * o.radius;
      oc.source_voxel = oc.target_voxel = c * o.source_voxel;
      const RegistrationResult r =
          ppcr::align(scaled(source, c, as_float), scaled(target, c, as_float), oc);
      INFO((as_float ? "float32" : "double") << ", scale " << c << ": " << describe(r, T_gt));
      REQUIRE(r.converged());
      // The angle between the two rotations, radians (|R1 - R2|_F = 2 sqrt(2) sin(angle / 2)).
      const double angle =
          2.0 * std::asin((r.T_target_source.linear() - ref.T_target_source.linear()).norm() /
                          (2.0 * std::sqrt(2.0)));
      CHECK(angle < (as_float ? 1e-6 : 1e-9));
    }
  }
}

// The Student-t with dof -> infinity is the Gaussian model: at any huge finite dof the pose is
// the Gaussian's to rounding. (At 1e100 it ended 1e-4 away and at 1e308 failed its verdict, when
// the weights were formed as q^e from a rounded q and (nu + z_min) * sum overflowed.)
TEST_CASE("bunny: Student-t at dof 1e12, 1e100 and 1e308 gives the Gaussian's pose", "[real]") {
  const BunnyPair b = load_bunny();
  RegistrationOptions gaussian = b.protocol_options();
  gaussian.expert.weight_model = ppcr::WeightModel::kGaussian;
  const RegistrationResult ref = ppcr::align(b.source, b.target, gaussian);
  INFO("Gaussian: " << describe(ref, b.T_gt));
  REQUIRE(ref.converged());
  REQUIRE(ref.quality == ppcr::Quality::kGood);
  for (double dof : {1e12, 1e100, 1e308, std::numeric_limits<double>::max()}) {
    RegistrationOptions t = b.protocol_options();
    t.dof = dof;
    const RegistrationResult r = ppcr::align(b.source, b.target, t);
    INFO("dof " << dof << ": " << describe(r, b.T_gt));
    REQUIRE(r.converged());
    CHECK(r.quality == ppcr::Quality::kGood);
    CHECK((r.T_target_source.matrix() - ref.T_target_source.matrix()).cwiseAbs().maxCoeff() < 1e-9);
  }
}

// No radius given: the automatic one (8 target point spacings) registers the bunny in
// millimetres and the LiDAR pair in centimetres as the tuned radius does in metres.
TEST_CASE("automatic radius: the bunny in millimetres, the LiDAR pair in centimetres", "[real]") {
  auto in_units = [](Eigen::Isometry3d T, double c) {
    T.translation() *= c;
    return T;
  };
  SECTION("bunny, millimetres, 2 mm voxels, from identity (34 degrees off)") {
    const PointCloud target = scaled(load_cloud("bunny/bun000.ply"), 1000.0);
    const PointCloud source = scaled(load_cloud("bunny/bun045.ply"), 1000.0);
    const Eigen::Isometry3d T_gt = in_units(load_transform("bunny/bun045_gt.txt"), 1000.0);
    RegistrationOptions o;
    o.source_voxel = o.target_voxel = 2.0;
    REQUIRE(o.radius == RegistrationOptions::kAutomaticRadius);  // the default
    const RegistrationResult r = ppcr::align(source, target, o);
    INFO(describe(r, T_gt) << ", radius " << r.radius << ", spacing " << r.target_spacing);
    REQUIRE(r.converged());
    CHECK(r.radius == RegistrationOptions::kAutomaticRadiusSpacings * r.target_spacing);
    CHECK(r.radius > 5.0);  // about 11 mm: the spacing is about 1.4 mm
    CHECK(r.radius < 20.0);
    CHECK(ppcr::rotation_error_deg(r.T_target_source, T_gt) < 0.2);
    CHECK(ppcr::translation_error(r.T_target_source, T_gt) < 0.5);  // mm
    CHECK(r.quality == ppcr::Quality::kGood);
  }
  SECTION("lidar, centimetres, 20 cm voxels, from a 10 degree / 50 cm perturbation") {
    const PointCloud source = scaled(load_cloud("lidar/source.ply"), 100.0);
    const PointCloud target = scaled(load_cloud("lidar/target.ply"), 100.0);
    const Eigen::Isometry3d T_gt = in_units(load_transform("lidar/source_gt.txt"), 100.0);
    RegistrationOptions o;
    o.source_voxel = o.target_voxel = 20.0;
    for (double sign : {1.0, -1.0}) {
      const Eigen::Isometry3d perturbation =
          core_test::make_pose(Eigen::Vector3d(0.1, 0.05, 1.0), sign * core_test::deg2rad(10.0),
                               50.0 * Eigen::Vector3d(0.8, 0.6, 0.0));
      const RegistrationResult r = ppcr::align(source, target, o, perturbation * T_gt);
      INFO("yaw sign " << sign << ": " << describe(r, T_gt) << ", radius " << r.radius);
      REQUIRE(r.converged());
      CHECK(r.radius > 50.0);  // about 1.1 m: the spacing is about 14 cm
      CHECK(r.radius < 200.0);
      CHECK(ppcr::rotation_error_deg(r.T_target_source, T_gt) < 0.3);
      CHECK(ppcr::translation_error(r.T_target_source, T_gt) < 3.0);  // cm
      CHECK(r.quality == ppcr::Quality::kGood);
    }
  }
}

// The automatic leaf (kAutomaticVoxel) with nothing else set: each cloud filtered to about
// kAutomaticVoxelPoints points, so that the automatic radius, 8 spacings of the filtered target,
// covers the LiDAR pair's 0.5 m misalignment (without a leaf it is 10 cm: the pair ends 0.5 m off);
// the leaves scale with the units.
TEST_CASE("automatic leaf: the LiDAR pair and the bunny with no other option, in any units",
          "[real]") {
  RegistrationOptions o;
  o.source_voxel = o.target_voxel = RegistrationOptions::kAutomaticVoxel;
  for (const double unit : {1.0, 1000.0}) {
    const PointCloud source = scaled(load_cloud("lidar/source.ply"), unit);
    const PointCloud target = scaled(load_cloud("lidar/target.ply"), unit);
    Eigen::Isometry3d T_gt = load_transform("lidar/source_gt.txt");
    T_gt.translation() *= unit;
    const RegistrationResult r = ppcr::align(source, target, o);
    INFO("lidar x " << unit << ": " << describe(r, T_gt) << ", leaves " << r.source_voxel << " "
                    << r.target_voxel << ", radius " << r.radius);
    REQUIRE(r.status.ok());
    CHECK(r.source_voxel > 0.1 * unit);  // about 0.18 m
    CHECK(r.source_voxel < 0.3 * unit);
    const double wanted = static_cast<double>(RegistrationOptions::kAutomaticVoxelPoints);
    CHECK(std::abs(r.source_points / wanted - 1.0) <= 0.15);
    CHECK(std::abs(r.target_points / wanted - 1.0) <= 0.15);
    CHECK(ppcr::rotation_error_deg(r.T_target_source, T_gt) < 0.3);
    CHECK(ppcr::translation_error(r.T_target_source, T_gt) < 0.03 * unit);
    CHECK(r.quality == ppcr::Quality::kGood);
  }
  const BunnyPair bunny = load_bunny();
  const RegistrationResult r = ppcr::align(bunny.source, bunny.target, o);
  INFO("bunny: " << describe(r, bunny.T_gt) << ", leaf " << r.target_voxel);
  REQUIRE(r.status.ok());
  CHECK(r.target_voxel > 0.001);  // about 1.6 mm
  CHECK(r.target_voxel < 0.003);
  CHECK(ppcr::rotation_error_deg(r.T_target_source, bunny.T_gt) < 0.2);
  CHECK(ppcr::translation_error(r.T_target_source, bunny.T_gt) < 0.001);
}
