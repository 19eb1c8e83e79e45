// Tests of the public API (ppcr::Registration, ppcr::align): option validation, input checks, and
// registration of synthetic scenes of analytic surfaces moved by known transforms.
#include <Eigen/Eigenvalues>
#include <algorithm>
#include <catch2/catch.hpp>
#include <cmath>
#include <functional>
#include <limits>
#include <string>
#include <thread>
#include <utility>
#include <vector>

#include "association/kdtree.hpp"
#include "core_test_util.hpp"
#include "ppcr/metrics.hpp"
#include "ppcr/registration.hpp"
#include "preparation/pca_normals.hpp"
#include "result_checks.hpp"

using core_test::Rng;
using ppcr::PointCloud;
using ppcr::RegistrationOptions;
using ppcr::RegistrationResult;
using ppcr::StatusCode;
using ppcr::StopReason;

namespace {

const double kNaN = std::numeric_limits<double>::quiet_NaN();
const double kInf = std::numeric_limits<double>::infinity();

// The scene (about 2 m across) and a ground truth of 10 degrees and a few centimetres.
struct Scene {
  PointCloud target;  // the surfaces, target frame
  PointCloud source;  // the same points (or an independent sample) in the source frame
  Eigen::Isometry3d T_true;
};

const Eigen::Isometry3d& ground_truth() {
  static const Eigen::Isometry3d T =
      core_test::make_pose(Eigen::Vector3d(0.3, -0.5, 1.0), core_test::deg2rad(10.0),
                           Eigen::Vector3d(0.04, -0.03, 0.02));
  return T;
}

// same_points: the source is the target's points moved by T_true^-1 (an exact solution exists);
// otherwise the source is an independent sample of the same surfaces.
Scene make_scene(std::size_t source_points, std::size_t target_points, bool same_points,
                 std::uint64_t seed = 100) {
  Rng rng(seed);
  Scene s;
  s.T_true = ground_truth();
  s.target = core_test::analytic_scene(rng, target_points);
  const PointCloud src_world =
      same_points ? s.target : core_test::analytic_scene(rng, source_points);
  s.source = core_test::transformed(src_world, s.T_true.inverse());
  return s;
}

RegistrationOptions scene_options() {
  RegistrationOptions o;
  o.radius = 0.2;  // 10 % of the scene: covers the initial misalignment (up to ~0.25 m)
  return o;
}

// RMS displacement of the source points between two poses (the error that matters at the
// cloud, whatever the distance of the cloud from the origin).
double rms_error(const PointCloud& source, const Eigen::Isometry3d& A, const Eigen::Isometry3d& B) {
  double sum = 0.0;
  for (const Eigen::Vector3d& x : source) sum += (A * x - B * x).squaredNorm();
  return std::sqrt(sum / static_cast<double>(source.size()));
}

using core_test::brute_force_spacing;

// The upper median over the cloud of the distance to a point's `neighbours`-th nearest (itself
// counted): the normal fits' typical reach (pca_normals.hpp).
double brute_force_reach(const PointCloud& cloud, int neighbours) {
  std::vector<double> reach;
  for (std::size_t i = 0; i < cloud.size(); ++i) {
    const auto nearest =
        core_test::brute_force_nearest(cloud, i, static_cast<std::size_t>(neighbours));
    reach.push_back(std::sqrt(nearest.back().first));
  }
  std::nth_element(reach.begin(), reach.begin() + reach.size() / 2, reach.end());
  return reach[reach.size() / 2];
}

// The PCA normal of cloud[i] by brute force: its `neighbours` nearest points (itself included),
// the smallest eigenvector of their covariance; zero where they do not spread in two directions
// (the plane model's convention, pca_normals.hpp).
Eigen::Vector3d brute_force_normal(const PointCloud& cloud, std::size_t i, int neighbours) {
  const std::vector<std::pair<double, std::size_t>> by_distance =
      core_test::brute_force_nearest(cloud, i, static_cast<std::size_t>(neighbours));
  Eigen::Vector3d mean = Eigen::Vector3d::Zero();
  for (int m = 0; m < neighbours; ++m) mean += cloud[by_distance[m].second];
  mean /= neighbours;
  Eigen::Matrix3d C = Eigen::Matrix3d::Zero();
  for (int m = 0; m < neighbours; ++m) {
    const Eigen::Vector3d d = cloud[by_distance[m].second] - mean;
    C += d * d.transpose();
  }
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(C);
  if (!(eig.eigenvalues()[1] > 1e-6 * eig.eigenvalues()[2])) return Eigen::Vector3d::Zero();
  return eig.eigenvectors().col(0);
}

double rotation_error_deg(const Eigen::Isometry3d& a, const Eigen::Isometry3d& b) {
  return core_test::angle_between_deg(a.linear(), b.linear());
}

std::string describe(const RegistrationResult& r) {
  return r.status.to_string() + ", stop " + ppcr::to_string(r.stop_reason) + ", " +
         std::to_string(r.iterations) + " iterations, scale " + std::to_string(r.scale);
}

bool contains(const std::string& s, const std::string& part) {
  return s.find(part) != std::string::npos;
}

struct BadOption {
  const char* what;
  std::function<void(RegistrationOptions&)> set;
  std::vector<std::string> message_parts;  // the parameter's name and the value seen
};

// Options whose message names the parameter and the value.
std::vector<BadOption> bad_options() {
  using O = RegistrationOptions;
  return {
      {"radius -1", [](O& o) { o.radius = -1.0; }, {"radius", "-1"}},
      {"radius NaN", [](O& o) { o.radius = kNaN; }, {"radius", "nan"}},
      {"radius Inf", [](O& o) { o.radius = kInf; }, {"radius", "inf"}},
      {"max_neighbours 0", [](O& o) { o.max_neighbours = 0; }, {"max_neighbours", "0"}},
      {"max_neighbours -3", [](O& o) { o.max_neighbours = -3; }, {"max_neighbours", "-3"}},
      {"max_neighbours 1025", [](O& o) { o.max_neighbours = 1025; }, {"max_neighbours", "1025"}},
      {"neighbour_cache -1",
       [](O& o) { o.expert.neighbour_cache = -1; },
       {"neighbour_cache", "-1"}},
      {"acceleration_memory -1",
       [](O& o) { o.expert.acceleration_memory = -1; },
       {"acceleration_memory", "-1"}},
      {"acceleration_memory 9",
       [](O& o) { o.expert.acceleration_memory = 9; },
       {"acceleration_memory", "9"}},
      {"coarse_stride 0", [](O& o) { o.expert.coarse_stride = 0; }, {"coarse_stride", "0"}},
      {"coarse_stride -2", [](O& o) { o.expert.coarse_stride = -2; }, {"coarse_stride", "-2"}},
      {"coarse_stride 65", [](O& o) { o.expert.coarse_stride = 65; }, {"coarse_stride", "65"}},
      {"dof 0", [](O& o) { o.dof = 0.0; }, {"dof", "0"}},
      {"dof -2", [](O& o) { o.dof = -2.0; }, {"dof", "-2"}},
      {"dof NaN", [](O& o) { o.dof = kNaN; }, {"dof", "nan"}},
      {"fixed scale 0",
       [](O& o) {
         o.expert.scale_mode = ppcr::ScaleMode::kFixed;
         o.expert.scale = 0.0;
       },
       {"scale", "0"}},
      {"fixed scale -0.5",
       [](O& o) {
         o.expert.scale_mode = ppcr::ScaleMode::kFixed;
         o.expert.scale = -0.5;
       },
       {"scale", "-0.5"}},
      {"EM scale -1", [](O& o) { o.expert.scale = -1.0; }, {"scale", "-1"}},
      {"EM scale NaN", [](O& o) { o.expert.scale = kNaN; }, {"scale", "nan"}},
      {"em_min_shrink 0", [](O& o) { o.expert.em_min_shrink = 0.0; }, {"em_min_shrink", "0"}},
      {"em_min_shrink 1.5", [](O& o) { o.expert.em_min_shrink = 1.5; }, {"em_min_shrink", "1.5"}},
      {"em_min_shrink NaN", [](O& o) { o.expert.em_min_shrink = kNaN; }, {"em_min_shrink", "nan"}},
      {"em_min_scale -1", [](O& o) { o.expert.em_min_scale = -1.0; }, {"em_min_scale", "-1"}},
      {"num_threads 0", [](O& o) { o.num_threads = 0; }, {"num_threads", "0"}},
      {"num_threads -1", [](O& o) { o.num_threads = -1; }, {"num_threads", "-1"}},
      {"lm.max_iterations 0",
       [](O& o) { o.expert.lm_max_iterations = 0; },
       {"lm_max_iterations", "0"}},
      {"unknown criterion bits",
       [](O& o) { o.criteria = ppcr::kCriterionCostDrop | 16u; },
       {"criteria", "18"}},
      {"termination.max_iterations 0", [](O& o) { o.max_iterations = 0; }, {"max_iterations", "0"}},
      {"fixed_iterations 0",
       [](O& o) { o.expert.fixed_iterations = 0; },
       {"fixed_iterations", "0"}},
      {"cost_drop_threshold NaN",
       [](O& o) { o.expert.cost_drop_threshold = kNaN; },
       {"cost_drop_threshold", "nan"}},
      {"plane.normal_neighbours 4",
       [](O& o) {
         o.error_model = ppcr::ErrorModel::kPlane;
         o.expert.normal_neighbours = 4;
       },
       {"normal_neighbours", "4"}},
      {"plane.normal_neighbours 65",
       [](O& o) {
         o.error_model = ppcr::ErrorModel::kPlane;
         o.expert.normal_neighbours = 65;
       },
       {"normal_neighbours", "65"}},
      {"plane.epsilon 0",
       [](O& o) {
         o.error_model = ppcr::ErrorModel::kPlane;
         o.expert.plane_epsilon = 0.0;
       },
       {"plane_epsilon", "0"}},
      {"plane.epsilon 1.5",
       [](O& o) {
         o.error_model = ppcr::ErrorModel::kPlane;
         o.expert.plane_epsilon = 1.5;
       },
       {"plane_epsilon", "1.5"}},
      {"plane.epsilon NaN",
       [](O& o) {
         o.error_model = ppcr::ErrorModel::kPlane;
         o.expert.plane_epsilon = kNaN;
       },
       {"plane_epsilon", "nan"}},
      {"plane.noise_floor -1",
       [](O& o) {
         o.error_model = ppcr::ErrorModel::kPlane;
         o.expert.noise_floor = -1.0;
       },
       {"noise_floor", "-1"}},
      {"plane.noise_floor NaN",
       [](O& o) {
         o.error_model = ppcr::ErrorModel::kPlane;
         o.expert.noise_floor = kNaN;
       },
       {"noise_floor", "nan"}},
      {"cost_drop_max_motion -1",
       [](O& o) { o.expert.cost_drop_max_motion = -1.0; },
       {"cost_drop_max_motion", "-1"}},
      {"cost_drop_max_motion NaN",
       [](O& o) { o.expert.cost_drop_max_motion = kNaN; },
       {"cost_drop_max_motion", "nan"}},
      {"mse_ratio_threshold 0",
       [](O& o) { o.expert.mse_ratio_threshold = 0.0; },
       {"mse_ratio_threshold", "0"}},
  };
}

// Options that are refused, but whose message does not name the parameter and/or the value.
std::vector<BadOption> bad_options_vague_message() {
  using O = RegistrationOptions;
  return {
      {"em_coarse_drop NaN",
       [](O& o) { o.expert.em_coarse_drop = kNaN; },
       {"em_coarse_drop", "nan"}},
      {"em_coarse_patience -1",
       [](O& o) { o.expert.em_coarse_patience = -1; },
       {"em_coarse_patience", "-1"}},
      {"source_voxel -2", [](O& o) { o.source_voxel = -2.0; }, {"source_voxel", "-2"}},
      {"target_voxel -0.5",
       [](O& o) { o.target_voxel = -0.5; },
       {"target_voxel", "kAutomaticVoxel"}},
      {"target_voxel NaN", [](O& o) { o.target_voxel = kNaN; }, {"target_voxel", "nan"}},
      {"lm.function_tolerance -1",
       [](O& o) { o.expert.lm_function_tolerance = -1.0; },
       {"function_tolerance", "-1"}},
      {"lm.fine_function_tolerance -0.5",
       [](O& o) { o.expert.lm_fine_function_tolerance = -0.5; },
       {"fine_function_tolerance", "-0.5"}},
      {"lm.fine_function_tolerance NaN",
       [](O& o) { o.expert.lm_fine_function_tolerance = kNaN; },
       {"fine_function_tolerance", "nan"}},
      {"lm.fine_function_tolerance Inf",
       [](O& o) { o.expert.lm_fine_function_tolerance = kInf; },
       {"fine_function_tolerance", "inf"}},
      {"cost_drop_patience -1",
       [](O& o) { o.expert.cost_drop_patience = -1; },
       {"cost_drop_patience", "-1"}},
      {"mse_patience -2", [](O& o) { o.expert.mse_patience = -2; }, {"mse_patience", "-2"}},
      {"successful_steps_patience -1",
       [](O& o) { o.expert.successful_steps_patience = -1; },
       {"successful_steps_patience", "-1"}},
  };
}

}  // namespace

// ------------------------------------------------------------------------------ validation

TEST_CASE("validate accepts the defaults and the boundaries of each range", "[registration]") {
  CHECK(ppcr::validate(RegistrationOptions()).ok());
  RegistrationOptions o;
  o.max_neighbours = 1;
  CHECK(ppcr::validate(o).ok());
  o.max_neighbours = 1024;
  CHECK(ppcr::validate(o).ok());
  o.expert.em_min_shrink = 1.0;
  CHECK(ppcr::validate(o).ok());
  o.criteria = 0xF;
  o.max_iterations = 1;
  o.expert.lm_max_iterations = 1;
  o.num_threads = 1;
  o.expert.coarse_stride = 1;
  CHECK(ppcr::validate(o).ok());
  o.expert.coarse_stride = 64;
  CHECK(ppcr::validate(o).ok());
  o.expert.coarse_stride = ppcr::ExpertOptions::kAutomatic;
  CHECK(ppcr::validate(o).ok());
  // Plane options are unused by the point model.
  o.error_model = ppcr::ErrorModel::kPoint;
  o.expert.normal_neighbours = 0;
  o.expert.plane_epsilon = -1.0;
  CHECK(ppcr::validate(o).ok());
  o.error_model = ppcr::ErrorModel::kPlane;
  o.expert.normal_neighbours = 5;
  o.expert.plane_epsilon = 1.0;
  CHECK(ppcr::validate(o).ok());
  o.expert.normal_neighbours = 64;
  CHECK(ppcr::validate(o).ok());
  // dof is unused by the Gaussian model.
  o.expert.weight_model = ppcr::WeightModel::kGaussian;
  o.dof = 0.0;
  CHECK(ppcr::validate(o).ok());
}

TEST_CASE("validate rejects each bad parameter, naming it and the value", "[registration]") {
  for (const BadOption& b : bad_options()) {
    RegistrationOptions o;
    b.set(o);
    const ppcr::Status s = ppcr::validate(o);
    INFO(b.what << " -> " << s.to_string());
    CHECK(s.code() == StatusCode::kInvalidArgument);
    for (const std::string& part : b.message_parts) CHECK(contains(s.message(), part));
    // The same status comes back from set_target and align, and the pose stays finite.
    ppcr::Registration reg(o);
    CHECK(reg.set_target(PointCloud(10, Eigen::Vector3d::Ones())).code() ==
          StatusCode::kInvalidArgument);
    const RegistrationResult r = reg.align(PointCloud(10, Eigen::Vector3d::Ones()));
    CHECK(r.status.code() == StatusCode::kInvalidArgument);
    CHECK(r.stop_reason == StopReason::kInvalidInput);
    CHECK_FALSE(r.converged());
    CHECK(r.T_target_source.matrix().allFinite());
  }
}

TEST_CASE("validate rejects the other bad parameters", "[registration]") {
  for (const BadOption& b : bad_options_vague_message()) {
    RegistrationOptions o;
    b.set(o);
    const ppcr::Status s = ppcr::validate(o);
    INFO(b.what << " -> " << s.to_string());
    CHECK(s.code() == StatusCode::kInvalidArgument);
  }
}

// validate()'s contract: every message names the parameter and the value seen (these were once
// grouped: "LM tolerances must be >= 0, got -1", "patience values must be >= 0").
TEST_CASE("validate names the parameter and the value for every bad parameter", "[registration]") {
  for (const BadOption& b : bad_options_vague_message()) {
    RegistrationOptions o;
    b.set(o);
    const ppcr::Status s = ppcr::validate(o);
    INFO(b.what << " -> " << s.to_string());
    for (const std::string& part : b.message_parts) CHECK(contains(s.message(), part));
  }
}

// ------------------------------------------------------------------------------ input checks

TEST_CASE("too few points after dropping non-finite ones: kEmptyCloud with counts",
          "[registration]") {
  const Scene sc = make_scene(0, 500, true);
  const RegistrationOptions o = scene_options();
  SECTION("empty source") {
    const RegistrationResult r = ppcr::align(PointCloud(), sc.target, o);
    INFO(r.status.to_string());
    CHECK(r.status.code() == StatusCode::kEmptyCloud);
    CHECK(r.stop_reason == StopReason::kInvalidInput);
    CHECK(contains(r.status.message(), "source"));
    CHECK(contains(r.status.message(), "0 usable"));
  }
  SECTION("source with 2 finite points and 5 non-finite ones") {
    PointCloud src = {Eigen::Vector3d(0, 0, 0),     Eigen::Vector3d(kNaN, 0, 0),
                      Eigen::Vector3d(1, 0, 0),     Eigen::Vector3d(0, kInf, 0),
                      Eigen::Vector3d(0, 0, -kInf), Eigen::Vector3d(kNaN, kNaN, kNaN),
                      Eigen::Vector3d(0, kNaN, 1)};
    const RegistrationResult r = ppcr::align(src, sc.target, o);
    INFO(r.status.to_string());
    CHECK(r.status.code() == StatusCode::kEmptyCloud);
    CHECK(contains(r.status.message(), "2 usable"));
    CHECK(contains(r.status.message(), "of 7"));
    CHECK(contains(r.status.message(), "5 non-finite"));
    CHECK(r.T_target_source.matrix().allFinite());
  }
  SECTION("target with 2 points") {
    const PointCloud tgt = {Eigen::Vector3d(0, 0, 0), Eigen::Vector3d(1, 0, 0)};
    const RegistrationResult r = ppcr::align(sc.source, tgt, o);
    INFO(r.status.to_string());
    CHECK(r.status.code() == StatusCode::kEmptyCloud);
    CHECK(r.stop_reason == StopReason::kInvalidInput);
    CHECK(contains(r.status.message(), "target"));
    CHECK(contains(r.status.message(), "2 usable"));
  }
  SECTION("a voxel filter that leaves fewer than 3 points") {
    RegistrationOptions ov = o;
    ov.source_voxel = 100.0;  // one voxel for the whole scene
    const RegistrationResult r = ppcr::align(sc.source, sc.target, ov);
    INFO(r.status.to_string());
    CHECK(r.status.code() == StatusCode::kEmptyCloud);
    CHECK(contains(r.status.message(), "1 usable"));
    CHECK(contains(r.status.message(), "voxel"));
  }
  SECTION("exactly 3 points are enough") {
    const PointCloud src = {sc.target[0], sc.target[1], sc.target[2]};
    const RegistrationResult r = ppcr::align(src, sc.target, o);
    INFO(describe(r));
    CHECK(r.status.ok());
    CHECK(r.source_points == 3u);
  }
}

TEST_CASE("align without a target, or after a failed set_target, is refused", "[registration]") {
  ppcr::Registration reg(scene_options());
  const Scene sc = make_scene(0, 300, true);
  RegistrationResult r = reg.align(sc.source);
  CHECK(r.status.code() == StatusCode::kEmptyCloud);
  CHECK(r.stop_reason == StopReason::kInvalidInput);
  CHECK(r.status.message() == "no target: call set_target() first");
  REQUIRE(reg.set_target(sc.target).ok());
  const ppcr::Status refused = reg.set_target(PointCloud(2, Eigen::Vector3d::Zero()));
  CHECK(refused.code() == StatusCode::kEmptyCloud);
  // The refusal's own status, and the result ppcr::align (which sets the target itself) gives,
  // with a finite initial guess and with a non-finite one.
  for (const double entry : {0.1, kNaN}) {
    Eigen::Isometry3d T_initial = Eigen::Isometry3d::Identity();
    T_initial.translation().x() = entry;
    r = reg.align(sc.source, T_initial);
    const RegistrationResult one_shot =
        ppcr::align(sc.source, PointCloud(2, Eigen::Vector3d::Zero()), scene_options(), T_initial);
    INFO("initial x " << entry);
    CHECK(r.status.code() == refused.code());
    CHECK(r.status.message() == refused.message());
    CHECK(r.status.message() == one_shot.status.message());
    CHECK(r.stop_reason == StopReason::kInvalidInput);
    CHECK(r.stop_reason == one_shot.stop_reason);
    CHECK(r.T_target_source.matrix().cwiseEqual(one_shot.T_target_source.matrix()).all());
    CHECK(r.quality == one_shot.quality);
    CHECK(r.iterations == one_shot.iterations);
    CHECK(r.source_points == one_shot.source_points);
    CHECK(r.target_points == one_shot.target_points);
    CHECK(r.source_non_finite == one_shot.source_non_finite);
    CHECK(r.target_non_finite == one_shot.target_non_finite);
  }
  // A refused set_target_to_source() likewise (no source: the last align() was refused).
  const ppcr::Status no_source = reg.set_target_to_source();
  CHECK(no_source.code() == StatusCode::kEmptyCloud);
  CHECK(reg.align(sc.source).status.message() == no_source.message());
  // A target set again clears it.
  REQUIRE(reg.set_target(sc.target).ok());
  CHECK(reg.align(sc.source).status.ok());
}

TEST_CASE("non-finite points are dropped, counted, and change nothing else", "[registration]") {
  const Scene sc = make_scene(0, 1500, true);
  RegistrationOptions o = scene_options();
  o.max_iterations = 15;
  PointCloud src = sc.source, tgt = sc.target;
  src.insert(src.begin() + 10, Eigen::Vector3d(kNaN, 0, 0));
  src.push_back(Eigen::Vector3d(0, kInf, 0));
  src.insert(src.begin(), Eigen::Vector3d(-kInf, kNaN, 1));
  tgt.insert(tgt.begin() + 500, Eigen::Vector3d(0, 0, kNaN));
  tgt.push_back(Eigen::Vector3d(kInf, kInf, kInf));
  const RegistrationResult dirty = ppcr::align(src, tgt, o);
  const RegistrationResult clean = ppcr::align(sc.source, sc.target, o);
  INFO(describe(dirty));
  REQUIRE(dirty.status.ok());
  CHECK(dirty.source_non_finite == 3u);
  CHECK(dirty.target_non_finite == 2u);
  CHECK(clean.source_non_finite == 0u);
  CHECK(clean.target_non_finite == 0u);
  CHECK(dirty.source_points == sc.source.size());
  CHECK(dirty.target_points == sc.target.size());
  CHECK(dirty.T_target_source.matrix() == clean.T_target_source.matrix());
  CHECK(dirty.iterations == clean.iterations);
}

TEST_CASE(
    "no correspondence within the radius: kNoCorrespondences, message with the radius "
    "and both extents",
    "[registration]") {
  const Scene sc = make_scene(0, 500, true);
  RegistrationOptions o = scene_options();
  Eigen::Isometry3d far = Eigen::Isometry3d::Identity();
  far.translation() = Eigen::Vector3d(50.0, 0.0, 0.0);
  const RegistrationResult r = ppcr::align(sc.source, sc.target, o, far);
  INFO(r.status.to_string());
  CHECK(r.status.code() == StatusCode::kNoCorrespondences);
  CHECK(r.stop_reason == StopReason::kNoCorrespondences);
  CHECK_FALSE(r.converged());
  CHECK(contains(r.status.message(), "radius 0.2"));
  CHECK(contains(r.status.message(), "source"));
  CHECK(contains(r.status.message(), "target"));
  // Extents "[lo, hi] x [lo, hi] x [lo, hi]" for both clouds; the source's moved by 50 in x.
  CHECK(std::count(r.status.message().begin(), r.status.message().end(), '[') == 6);
  CHECK(contains(r.status.message(), "[48."));
  CHECK(r.T_target_source.matrix() == far.matrix());
  CHECK(r.iterations == 0);
  CHECK(r.matched_source_points == 0u);
}

TEST_CASE("a non-finite initial guess is refused", "[registration]") {
  const Scene sc = make_scene(0, 300, true);
  Eigen::Isometry3d bad = Eigen::Isometry3d::Identity();
  bad.translation().x() = kNaN;
  const RegistrationResult r = ppcr::align(sc.source, sc.target, scene_options(), bad);
  CHECK(r.status.code() == StatusCode::kInvalidArgument);
  CHECK(r.stop_reason == StopReason::kInvalidInput);
  CHECK(contains(r.status.message(), "initial guess"));
}

// A refused input returns the initial guess, or the identity when the guess is not finite:
// never a NaN pose.
TEST_CASE("the returned pose is finite even when the initial guess is not", "[registration]") {
  const Scene sc = make_scene(0, 300, true);
  Eigen::Isometry3d bad = Eigen::Isometry3d::Identity();
  bad.translation().x() = kNaN;
  const RegistrationResult r = ppcr::align(sc.source, sc.target, scene_options(), bad);
  CHECK(r.T_target_source.matrix().allFinite());
}

// ------------------------------------------------------------------------------ accuracy

TEST_CASE("exact recovery on a noise-free synthetic scene (same points)", "[registration]") {
  const Scene sc = make_scene(0, 3000, true);
  const RegistrationResult r = ppcr::align(sc.source, sc.target, scene_options());
  INFO(describe(r));
  REQUIRE(r.status.ok());
  CHECK(r.converged());
  CHECK(rotation_error_deg(r.T_target_source, sc.T_true) < 0.05);
  CHECK(ppcr::translation_error(r.T_target_source, sc.T_true) < 2e-3);  // 1e-3 of 2 m
  CHECK(rms_error(sc.source, r.T_target_source, sc.T_true) < 1e-3);
  CHECK(r.degenerate_directions == 0);  // plane model (the default): well constrained
  CHECK(r.source_points == 3000u);
  CHECK(r.matched_source_points == 3000u);
}

TEST_CASE("recovery with a source sampled independently of a dense target", "[registration]") {
  // Different samples of the same surfaces: the PPCR optimum is biased by the sampling (patch
  // edges, curvature) by well under a point spacing; measured 0.044 degrees and 0.74 mm.
  const Scene sc = make_scene(3000, 20000, false);
  const RegistrationResult r = ppcr::align(sc.source, sc.target, scene_options());
  INFO(describe(r) << " rotation error " << rotation_error_deg(r.T_target_source, sc.T_true)
                   << " translation error "
                   << ppcr::translation_error(r.T_target_source, sc.T_true));
  REQUIRE(r.status.ok());
  CHECK(r.converged());
  CHECK(rotation_error_deg(r.T_target_source, sc.T_true) < 0.1);
  CHECK(ppcr::translation_error(r.T_target_source, sc.T_true) < 2e-3);
}

TEST_CASE("robust to 30 % uniform outliers in the source", "[registration]") {
  Scene sc = make_scene(0, 3000, true);
  Rng rng(7);
  for (int i = 0; i < 900; ++i) {
    sc.source.push_back(sc.T_true.inverse() * Eigen::Vector3d(core_test::uniform(rng, -1.3, 1.3),
                                                              core_test::uniform(rng, -1.3, 1.3),
                                                              core_test::uniform(rng, -0.3, 1.5)));
  }
  const RegistrationResult r = ppcr::align(sc.source, sc.target, scene_options());
  INFO(describe(r));
  REQUIRE(r.status.ok());
  CHECK(r.converged());
  CHECK(rotation_error_deg(r.T_target_source, sc.T_true) < 0.5);
  CHECK(ppcr::translation_error(r.T_target_source, sc.T_true) < 5e-3);
}

TEST_CASE("raw, fixed and EM scales, Student-t and Gaussian, all converge on the scene",
          "[registration]") {
  const Scene sc = make_scene(0, 2000, true);
  struct Mode {
    const char* name;
    ppcr::WeightModel model;
    ppcr::ScaleMode scale_mode;
    double scale;
    double max_rotation_deg;
  };
  // Raw mode uses s = 1 m on a 2 m scene: nearly uniform weights over the neighbours, hence a
  // smoothing bias (measured 0.12 degrees); the others recover the pose closely.
  const Mode modes[] = {
      {"Student-t EM", ppcr::WeightModel::kStudentT, ppcr::ScaleMode::kEM, 0.0, 0.05},
      {"Student-t raw", ppcr::WeightModel::kStudentT, ppcr::ScaleMode::kRaw, 0.0, 0.5},
      {"Student-t fixed", ppcr::WeightModel::kStudentT, ppcr::ScaleMode::kFixed, 0.02, 0.05},
      {"Gaussian EM", ppcr::WeightModel::kGaussian, ppcr::ScaleMode::kEM, 0.0, 0.05},
      {"Gaussian raw", ppcr::WeightModel::kGaussian, ppcr::ScaleMode::kRaw, 0.0, 0.5},
      {"Gaussian fixed", ppcr::WeightModel::kGaussian, ppcr::ScaleMode::kFixed, 0.02, 0.05},
  };
  for (const Mode& m : modes) {
    RegistrationOptions o = scene_options();
    o.expert.weight_model = m.model;
    o.expert.scale_mode = m.scale_mode;
    o.expert.scale = m.scale;
    const RegistrationResult r = ppcr::align(sc.source, sc.target, o);
    INFO(m.name << ": " << describe(r) << " rotation error "
                << rotation_error_deg(r.T_target_source, sc.T_true));
    REQUIRE(r.status.ok());
    CHECK(r.converged());
    CHECK(rotation_error_deg(r.T_target_source, sc.T_true) < m.max_rotation_deg);
    CHECK(ppcr::translation_error(r.T_target_source, sc.T_true) < 5e-3);
    if (m.scale_mode == ppcr::ScaleMode::kRaw) CHECK(r.scale == 1.0);
    if (m.scale_mode == ppcr::ScaleMode::kFixed) CHECK(r.scale == Approx(0.02).epsilon(1e-15));
    for (const ppcr::IterationRecord& h : r.history) {
      if (m.scale_mode == ppcr::ScaleMode::kRaw) CHECK(h.scale == 1.0);
    }
    // EM starts at the coarse scale radius / 2.
    if (m.scale_mode == ppcr::ScaleMode::kEM) CHECK(r.history.front().scale == Approx(0.1));
  }
}

TEST_CASE("identical source and target from identity stay at identity", "[registration]") {
  const Scene sc = make_scene(0, 2000, true);
  SECTION("k = 1: zero cost at once, exactly identity") {
    RegistrationOptions o = scene_options();
    o.max_neighbours = 1;
    const RegistrationResult r = ppcr::align(sc.target, sc.target, o);
    INFO(describe(r));
    CHECK(r.converged());
    CHECK(r.stop_reason == StopReason::kZeroCost);
    CHECK((r.T_target_source.matrix() - Eigen::Matrix4d::Identity()).cwiseAbs().maxCoeff() < 1e-9);
  }
  SECTION("default k, no noise floor") {
    // With k > 1 identity is not a stationary point of the coarse-scale cost (the neighbour
    // relation and the posteriors are not symmetric); the loop returns to identity as the
    // EM scale shrinks, down to the LM step tolerance (1e-7 of the radius = 2e-8 m).
    RegistrationOptions o = scene_options();
    o.expert.noise_floor = 0.0;
    const RegistrationResult r = ppcr::align(sc.target, sc.target, o);
    INFO(describe(r)
         << " deviation "
         << (r.T_target_source.matrix() - Eigen::Matrix4d::Identity()).cwiseAbs().maxCoeff());
    CHECK(r.converged());
    CHECK((r.T_target_source.matrix() - Eigen::Matrix4d::Identity()).cwiseAbs().maxCoeff() < 1e-7);
  }
  SECTION("defaults: the noise floor keeps the other neighbours' pull, below 3e-6 of the scene") {
    // The scale stops at 0.8 x the surface noise, so identity stays off by the asymmetric
    // posteriors' pull: measured 3.1e-6 on this 2 m scene, 8e-7 with the rows beyond the
    // target's boundary kept (the scene's edges then pull both ways).
    const RegistrationOptions o = scene_options();
    const RegistrationResult r = ppcr::align(sc.target, sc.target, o);
    INFO(describe(r)
         << " deviation "
         << (r.T_target_source.matrix() - Eigen::Matrix4d::Identity()).cwiseAbs().maxCoeff());
    CHECK(r.converged());
    CHECK((r.T_target_source.matrix() - Eigen::Matrix4d::Identity()).cwiseAbs().maxCoeff() < 6e-6);
    RegistrationOptions kept = o;
    kept.expert.reject_boundary = false;
    const RegistrationResult k = ppcr::align(sc.target, sc.target, kept);
    CHECK((k.T_target_source.matrix() - Eigen::Matrix4d::Identity()).cwiseAbs().maxCoeff() < 2e-6);
  }
}

TEST_CASE("a scene 1e6 m from the origin registers as well as at the origin", "[registration]") {
  const Scene sc = make_scene(0, 2000, true);
  const Eigen::Vector3d offset(1e6, -1e6, 1e6);
  PointCloud src = sc.source, tgt = sc.target;
  for (Eigen::Vector3d& p : src) p += offset;
  for (Eigen::Vector3d& p : tgt) p += offset;
  const Eigen::Isometry3d shift = core_test::make_pose(Eigen::Vector3d::UnitZ(), 0.0, offset);
  const Eigen::Isometry3d T_true_far = shift * sc.T_true * shift.inverse();
  const RegistrationResult near = ppcr::align(sc.source, sc.target, scene_options());
  const RegistrationResult far = ppcr::align(src, tgt, scene_options());
  INFO("near: " << describe(near) << "\nfar: " << describe(far));
  REQUIRE(far.status.ok());
  CHECK(far.converged());
  const double e_near = rms_error(sc.source, near.T_target_source, sc.T_true);
  const double e_far = rms_error(src, far.T_target_source, T_true_far);
  INFO("RMS error near " << e_near << ", far " << e_far);
  CHECK(e_far < 1e-3);
  CHECK(e_far < 10.0 * e_near + 1e-6);
  CHECK(rotation_error_deg(far.T_target_source, T_true_far) < 0.05);
  CHECK(std::abs(far.iterations - near.iterations) <= 2);
}

// ------------------------------------------------------------------------------ determinism

TEST_CASE("bit-identical T_target_source with num_threads 1 and 2", "[registration]") {
  const Scene sc = make_scene(2500, 6000, false);
  RegistrationOptions o = scene_options();
  for (bool source_normals : {false, true}) {
    INFO("source normals " << source_normals);
    o.expert.source_normals = source_normals;
    o.num_threads = 1;
    const RegistrationResult one = ppcr::align(sc.source, sc.target, o);
    o.num_threads = 2;
    const RegistrationResult two = ppcr::align(sc.source, sc.target, o);
    REQUIRE(one.status.ok());
    CHECK(one.T_target_source.matrix() == two.T_target_source.matrix());
    CHECK(one.iterations == two.iterations);
    CHECK(one.final_cost == two.final_cost);
    CHECK(one.information == two.information);
  }
}

TEST_CASE("the order of the input points changes nothing (internal Z-order), both models",
          "[registration]") {
  // Both clouds are sorted along a Z-order curve inside (spatial_order.hpp): reversed or
  // shuffled inputs of distinct points give the same internal clouds, hence the same
  // result to the bit. The second scene is a lattice (three orthogonal grids): its normal fits
  // meet many neighbours at exactly equal distances, where the k-d tree's visiting order, i.e.
  // the target's order, decides which are kept.
  const Scene sc = make_scene(2500, 6000, false);
  PointCloud lattice;
  for (int u = 0; u < 40; ++u) {
    for (int v = 0; v < 40; ++v) {
      lattice.emplace_back(0.02 * u, 0.02 * v, 0.0);
      lattice.emplace_back(0.02 * u, 0.0, 0.02 * v + 0.01);
      lattice.emplace_back(0.0, 0.02 * u + 0.01, 0.02 * v + 0.01);
    }
  }
  const Eigen::Isometry3d M = core_test::make_pose(
      Eigen::Vector3d(1, 2, 3), core_test::deg2rad(2.0), Eigen::Vector3d(0.01, -0.005, 0.008));
  const PointCloud lattice_source = core_test::transformed(lattice, M);
  core_test::Rng rng(93);
  for (int scene = 0; scene < 2; ++scene) {
    const PointCloud& source = scene == 0 ? sc.source : lattice_source;
    const PointCloud& target = scene == 0 ? sc.target : lattice;
    PointCloud source_shuffled = source, target_reversed(target.rbegin(), target.rend());
    for (std::size_t i = source_shuffled.size() - 1; i > 0; --i) {
      const std::size_t j = static_cast<std::size_t>(core_test::uniform(rng, 0.0, 1.0) * (i + 1));
      std::swap(source_shuffled[i], source_shuffled[std::min(j, i)]);
    }
    RegistrationOptions o = scene_options();
    if (scene == 1) o.radius = 0.1;
    for (ppcr::ErrorModel model : {ppcr::ErrorModel::kPlane, ppcr::ErrorModel::kPoint}) {
      INFO("scene " << scene << ", model " << static_cast<int>(model));
      o.error_model = model;
      const RegistrationResult a = ppcr::align(source, target, o);
      const RegistrationResult b = ppcr::align(source_shuffled, target_reversed, o);
      REQUIRE(a.status.ok());
      CHECK(a.T_target_source.matrix() == b.T_target_source.matrix());
      CHECK(a.iterations == b.iterations);
      CHECK(a.final_cost == b.final_cost);
      CHECK(a.information == b.information);
    }
  }
}

TEST_CASE("two registrations run concurrently give the sequential results", "[registration]") {
  const Scene a = make_scene(1500, 3000, false, 200);
  const Scene b = make_scene(1500, 3000, false, 300);
  const RegistrationOptions o = scene_options();
  const RegistrationResult seq_a = ppcr::align(a.source, a.target, o);
  const RegistrationResult seq_b = ppcr::align(b.source, b.target, o);
  RegistrationResult par_a, par_b;
  std::thread ta([&] { par_a = ppcr::align(a.source, a.target, o); });
  std::thread tb([&] { par_b = ppcr::align(b.source, b.target, o); });
  ta.join();
  tb.join();
  CHECK(par_a.T_target_source.matrix() == seq_a.T_target_source.matrix());
  CHECK(par_b.T_target_source.matrix() == seq_b.T_target_source.matrix());
  CHECK(par_a.iterations == seq_a.iterations);
  CHECK(par_b.iterations == seq_b.iterations);
  CHECK(seq_a.T_target_source.matrix() != seq_b.T_target_source.matrix());
}

TEST_CASE("a Registration reused for several sources equals one-shot align", "[registration]") {
  const Scene sc = make_scene(1500, 3000, false);
  const RegistrationOptions o = scene_options();
  ppcr::Registration reg(o);
  REQUIRE(reg.set_target(sc.target).ok());
  PointCloud smaller(sc.source.begin(), sc.source.begin() + 800);
  const RegistrationResult r1 = reg.align(sc.source);
  const RegistrationResult r2 = reg.align(smaller);
  const RegistrationResult r3 = reg.align(sc.source);  // buffers resized back
  CHECK(r1.T_target_source.matrix() ==
        ppcr::align(sc.source, sc.target, o).T_target_source.matrix());
  CHECK(r2.T_target_source.matrix() == ppcr::align(smaller, sc.target, o).T_target_source.matrix());
  CHECK(r3.T_target_source.matrix() == r1.T_target_source.matrix());
  // A moved-from-into Registration keeps working.
  ppcr::Registration moved(std::move(reg));
  CHECK(moved.align(sc.source).T_target_source.matrix() == r1.T_target_source.matrix());
  CHECK(moved.options().radius == o.radius);
}

TEST_CASE("align taking the source empties it and gives the same result, also when refused",
          "[registration]") {
  const Scene sc = make_scene(1500, 3000, false);
  const RegistrationOptions o = scene_options();
  ppcr::Registration reg(o);
  REQUIRE(reg.set_target(sc.target).ok());
  const RegistrationResult kept = reg.align(sc.source);
  PointCloud taken = sc.source;
  const RegistrationResult r = reg.align(std::move(taken));
  CHECK(taken.empty());
  CHECK(taken.capacity() == 0);  // freed, not only cleared
  test_checks::check_identical(kept, r);
  // A refused source: the same status, and the cloud is freed all the same.
  PointCloud two(sc.source.begin(), sc.source.begin() + 2);
  const RegistrationResult refused_kept = reg.align(two);
  const RegistrationResult refused = reg.align(std::move(two));
  CHECK(two.empty());
  CHECK(refused.status.code() == StatusCode::kEmptyCloud);
  CHECK(refused.status.message() == refused_kept.status.message());
}

// ------------------------------------------------------------------------------ trace

TEST_CASE("history: one finite row per iteration, consistent with the result", "[registration]") {
  const Scene sc = make_scene(1500, 4000, false);
  const RegistrationOptions o = scene_options();
  // The source as the registration sees it (no filtering here).
  const Eigen::Isometry3d T_gt = sc.T_true;
  const RegistrationResult r = ppcr::align(sc.source, sc.target, o);
  INFO(describe(r));
  REQUIRE(r.status.ok());
  REQUIRE(r.iterations >= 1);
  REQUIRE(static_cast<int>(r.history.size()) == r.iterations);
  int lm_iterations = 0, lm_successful = 0;
  Eigen::Isometry3d previous = Eigen::Isometry3d::Identity();
  for (std::size_t i = 0; i < r.history.size(); ++i) {
    const ppcr::IterationRecord& h = r.history[i];
    INFO("row " << i);
    CHECK(h.iteration == static_cast<int>(i) + 1);
    CHECK(h.successful_steps >= 0);
    CHECK(h.unsuccessful_steps >= 0);
    CHECK(std::isfinite(h.initial_cost));
    CHECK(std::isfinite(h.final_cost));
    CHECK(h.initial_cost > 0.0);
    CHECK(std::isfinite(h.cost_drop));
    CHECK(h.cost_drop == Approx((h.initial_cost - h.final_cost) / h.initial_cost).margin(1e-15));
    CHECK(std::isfinite(h.scale));
    CHECK(h.scale > 0.0);
    CHECK(h.correspondences >= h.matched_source_points);
    CHECK(h.matched_source_points <= sc.source.size());
    CHECK(h.correspondences <=
          h.matched_source_points * static_cast<std::size_t>(o.max_neighbours));
    CHECK(h.T_target_source.matrix().allFinite());
    CHECK(h.time_ms >= 0.0);
    // The MSE rows against brute force over the source; ppcr::evaluate's against a ground truth.
    double mse_prev = 0.0, mse_gt = 0.0;
    for (const Eigen::Vector3d& x : sc.source) {
      mse_prev += (h.T_target_source * x - previous * x).squaredNorm();
      mse_gt += (h.T_target_source * x - T_gt * x).squaredNorm();
    }
    // Compared as RMS: the brute-force differences of nearly equal poses carry ~1e-16 m.
    const double n = static_cast<double>(sc.source.size());
    CHECK(std::abs(std::sqrt(h.mse_prev) - std::sqrt(mse_prev / n)) <
          1e-7 * std::sqrt(mse_prev / n) + 1e-14);
    const ppcr::PoseErrors e = ppcr::evaluate(sc.source, h.T_target_source, T_gt);
    CHECK(std::abs(std::sqrt(e.mse) - std::sqrt(mse_gt / n)) <
          1e-7 * std::sqrt(mse_gt / n) + 1e-14);
    CHECK(e.benchmark_error == ppcr::benchmark_error(sc.source, T_gt, h.T_target_source));
    CHECK(e.rotation_error_deg == ppcr::rotation_error_deg(h.T_target_source, T_gt));
    CHECK(e.translation_error == ppcr::translation_error(h.T_target_source, T_gt));
    lm_iterations += h.successful_steps + h.unsuccessful_steps;
    lm_successful += h.successful_steps;
    previous = h.T_target_source;
  }
  CHECK(r.lm_iterations == lm_iterations);
  CHECK(r.lm_successful_steps == lm_successful);
  CHECK(r.initial_cost == r.history.front().initial_cost);
  CHECK(r.final_cost == r.history.back().final_cost);
  CHECK(r.history.back().T_target_source.matrix() == r.T_target_source.matrix());
  CHECK(r.correspondences == r.history.back().correspondences);
  CHECK(r.matched_source_points == r.history.back().matched_source_points);
  CHECK(r.scale > 0.0);
  // The ground-truth error went down over the run.
  CHECK(ppcr::evaluate(sc.source, r.history.back().T_target_source, T_gt).mse <
        ppcr::evaluate(sc.source, r.history.front().T_target_source, T_gt).mse);
  SECTION("record_history = false: no rows, the same result") {
    RegistrationOptions o2 = o;
    o2.record_history = false;
    const RegistrationResult r3 = ppcr::align(sc.source, sc.target, o2);
    CHECK(r3.history.empty());
    CHECK(r3.iterations == r.iterations);
    CHECK(r3.T_target_source.matrix() == r.T_target_source.matrix());
  }
}

TEST_CASE("termination options reach the loop: fixed iterations and the hard cap",
          "[registration]") {
  const Scene sc = make_scene(0, 1000, true);
  RegistrationOptions o = scene_options();
  o.criteria = ppcr::kCriterionFixed;
  o.expert.fixed_iterations = 7;
  RegistrationResult r = ppcr::align(sc.source, sc.target, o);
  CHECK(r.iterations == 7);
  CHECK(r.stop_reason == StopReason::kFixedIterations);
  CHECK(r.converged());
  o.criteria = 0;
  o.max_iterations = 4;
  r = ppcr::align(sc.source, sc.target, o);
  CHECK(r.iterations == 4);
  CHECK(r.stop_reason == StopReason::kMaxIterations);
  CHECK(r.status.ok());
  CHECK_FALSE(r.converged());
  CHECK(r.history.size() == 4u);
}

namespace {

// Plane model registration of a target onto itself, moved slightly (an exact solution exists).
RegistrationResult plane_model_run(const PointCloud& target) {
  RegistrationOptions o = scene_options();
  o.error_model = ppcr::ErrorModel::kPlane;
  const Eigen::Isometry3d T =
      core_test::make_pose(Eigen::Vector3d(1, 2, 3), 0.02, Eigen::Vector3d(0.01, -0.01, 0.005));
  return ppcr::align(core_test::transformed(target, T.inverse()), target, o);
}

}  // namespace

TEST_CASE("degenerate directions with the plane model: a plane 3, the scene 0", "[registration]") {
  Rng rng(8);
  PointCloud plane;
  for (int i = 0; i < 3000; ++i) {
    plane.emplace_back(core_test::uniform(rng, -1, 1), core_test::uniform(rng, -1, 1), 0.0);
  }
  const RegistrationResult rp = plane_model_run(plane);
  INFO("plane: " << describe(rp));
  CHECK(rp.status.ok());
  CHECK(rp.degenerate_directions == 3);
  const RegistrationResult rs = plane_model_run(make_scene(0, 3000, true).target);
  INFO("scene: " << describe(rs));
  CHECK(rs.status.ok());
  CHECK(rs.degenerate_directions == 0);
}

// A cylinder leaves two motions free (translation along and rotation about its axis); their
// eigenvalues are ~3e-4 of the largest with PCA normals, under the 1e-2 threshold.
TEST_CASE("degenerate directions with the plane model: a cylinder 2", "[registration]") {
  Rng rng(9);
  PointCloud cylinder;
  for (int i = 0; i < 3000; ++i) {
    const double a = core_test::uniform(rng, 0.0, 2.0 * core_test::kPi);
    cylinder.emplace_back(0.5 * std::cos(a), 0.5 * std::sin(a), core_test::uniform(rng, -1, 1));
  }
  const RegistrationResult rc = plane_model_run(cylinder);
  INFO("cylinder: " << describe(rc));
  CHECK(rc.status.ok());
  CHECK(rc.degenerate_directions == 2);
}

TEST_CASE("the plane model recovers the pose on the synthetic scene", "[registration]") {
  const Scene sc = make_scene(3000, 20000, false);
  RegistrationOptions o = scene_options();
  o.error_model = ppcr::ErrorModel::kPlane;
  Eigen::Matrix4d pose[2];
  for (bool source_normals : {false, true}) {
    o.expert.source_normals = source_normals;
    const RegistrationResult r = ppcr::align(sc.source, sc.target, o);
    INFO((source_normals ? "source normals: " : "")
         << describe(r) << " rotation error " << rotation_error_deg(r.T_target_source, sc.T_true)
         << " translation error " << ppcr::translation_error(r.T_target_source, sc.T_true));
    REQUIRE(r.status.ok());
    CHECK(r.converged());
    CHECK(rotation_error_deg(r.T_target_source, sc.T_true) < 0.1);
    CHECK(ppcr::translation_error(r.T_target_source, sc.T_true) < 2e-3);
    pose[source_normals] = r.T_target_source.matrix();
  }
  // The option reaches the solver: source normals change the result.
  CHECK(pose[0] != pose[1]);
}

TEST_CASE("lm.fine_function_tolerance loosens the inner solves of the EM fine phase only",
          "[registration]") {
  const Scene sc = make_scene(3000, 20000, false);
  RegistrationOptions o = scene_options();
  o.error_model = ppcr::ErrorModel::kPlane;
  o.expert.lm_fine_function_tolerance = 0.0;
  const RegistrationResult tight = ppcr::align(sc.source, sc.target, o);
  o.expert.lm_fine_function_tolerance = 1e-2;
  const RegistrationResult loose = ppcr::align(sc.source, sc.target, o);
  INFO("tight: " << describe(tight) << ", " << tight.lm_iterations << " LM steps; loose: "
                 << describe(loose) << ", " << loose.lm_iterations << " LM steps");
  REQUIRE(tight.status.ok());
  REQUIRE(loose.status.ok());
  // The coarse phase runs at the coarse scale (radius / 2): those rows, up to the first one at a
  // smaller scale, are the same computation in both runs, bit for bit. (With the default
  // em_min_shrink < 1 the first fine row has a smaller scale; the REQUIREs below say so if not.)
  const double coarse_scale = tight.history.front().scale;
  std::size_t coarse_rows = 0;
  while (coarse_rows < tight.history.size() && tight.history[coarse_rows].scale == coarse_scale) {
    ++coarse_rows;
  }
  REQUIRE(coarse_rows >= 1);
  REQUIRE(coarse_rows < tight.history.size());  // the run reached the fine phase
  REQUIRE(loose.history.size() > coarse_rows);
  for (std::size_t t = 0; t < coarse_rows; ++t) {
    INFO("iteration " << t + 1);
    CHECK(loose.history[t].scale == tight.history[t].scale);
    CHECK(loose.history[t].successful_steps == tight.history[t].successful_steps);
    CHECK(loose.history[t].T_target_source.matrix() == tight.history[t].T_target_source.matrix());
  }
  CHECK(loose.history[coarse_rows].scale < coarse_scale);
  // The fine phase's inner solves stop earlier: fewer LM steps per fine iteration on average.
  auto fine_steps_per_iteration = [&](const RegistrationResult& r) {
    double steps = 0.0;
    for (std::size_t t = coarse_rows; t < r.history.size(); ++t) {
      steps += r.history[t].successful_steps + r.history[t].unsuccessful_steps;
    }
    return steps / static_cast<double>(r.history.size() - coarse_rows);
  };
  CHECK(fine_steps_per_iteration(loose) < fine_steps_per_iteration(tight));
  CHECK(loose.lm_iterations < tight.lm_iterations);
  // Same accuracy bar as the plane model's own test.
  CHECK(loose.converged());
  CHECK(rotation_error_deg(loose.T_target_source, sc.T_true) < 0.1);
  CHECK(ppcr::translation_error(loose.T_target_source, sc.T_true) < 2e-3);

  // A fixed scale has no EM phases: the option changes nothing.
  o.expert.scale_mode = ppcr::ScaleMode::kFixed;
  o.expert.scale = 0.05;
  const RegistrationResult fixed_loose = ppcr::align(sc.source, sc.target, o);
  o.expert.lm_fine_function_tolerance = 0.0;
  const RegistrationResult fixed_tight = ppcr::align(sc.source, sc.target, o);
  REQUIRE(fixed_loose.status.ok());
  REQUIRE(fixed_tight.status.ok());
  CHECK(fixed_loose.lm_iterations == fixed_tight.lm_iterations);
  CHECK(fixed_loose.T_target_source.matrix() == fixed_tight.T_target_source.matrix());
}

TEST_CASE(
    "the automatic fine tolerance is 1e-2 capped at the cost-drop threshold with the plane "
    "model, and off with the point model",
    "[registration]") {
  const Scene sc = make_scene(3000, 20000, false);
  auto pose_with = [&](ppcr::ErrorModel model, double fine, double cost_drop_threshold,
                       std::uint32_t criteria = ppcr::kCriterionCostDrop,
                       double function_tolerance = ppcr::ExpertOptions().lm_function_tolerance) {
    RegistrationOptions o = scene_options();
    o.error_model = model;
    o.expert.lm_function_tolerance = function_tolerance;
    o.expert.lm_fine_function_tolerance = fine;
    o.expert.cost_drop_threshold = cost_drop_threshold;
    o.criteria = criteria;
    const RegistrationResult r = ppcr::align(sc.source, sc.target, o);
    REQUIRE(r.status.ok());
    return std::make_pair(r.T_target_source.matrix(), r.lm_iterations);
  };
  REQUIRE(RegistrationOptions().expert.lm_fine_function_tolerance ==
          ppcr::ExpertOptions::kAutomatic);
  const double kAuto = ppcr::ExpertOptions::kAutomatic;
  using ppcr::ErrorModel;
  // Plane model: the same run as 1e-2 given explicitly, to the bit; not the run with it off.
  const auto plane_auto = pose_with(ErrorModel::kPlane, kAuto, 0.01);
  const auto plane_1e2 = pose_with(ErrorModel::kPlane, 1e-2, 0.01);
  const auto plane_off = pose_with(ErrorModel::kPlane, 0.0, 0.01);
  CHECK(plane_auto.first == plane_1e2.first);
  CHECK(plane_auto.second == plane_1e2.second);
  CHECK(plane_auto.second < plane_off.second);
  CHECK(plane_auto.first != plane_off.first);
  // A stricter cost-drop threshold caps it: the run of 1e-4 given explicitly.
  const auto capped_auto = pose_with(ErrorModel::kPlane, kAuto, 1e-4);
  const auto capped_1e4 = pose_with(ErrorModel::kPlane, 1e-4, 1e-4);
  const auto capped_1e2 = pose_with(ErrorModel::kPlane, 1e-2, 1e-4);
  CHECK(capped_auto.first == capped_1e4.first);
  CHECK(capped_auto.second == capped_1e4.second);
  CHECK(capped_auto.first != capped_1e2.first);
  // Never stricter than function_tolerance: with a threshold of 1e-4 and function_tolerance
  // 1e-3, the run with the fine tolerance off, not the one with 1e-4.
  const std::uint32_t cost_drop = ppcr::kCriterionCostDrop;
  const auto loose_auto = pose_with(ErrorModel::kPlane, kAuto, 1e-4, cost_drop, 1e-3);
  const auto loose_off = pose_with(ErrorModel::kPlane, 0.0, 1e-4, cost_drop, 1e-3);
  const auto loose_1e4 = pose_with(ErrorModel::kPlane, 1e-4, 1e-4, cost_drop, 1e-3);
  CHECK(loose_auto.first == loose_off.first);
  CHECK(loose_auto.second == loose_off.second);
  CHECK(loose_auto.first != loose_1e4.first);
  // Another criterion beside (or instead of) the cost drop: the run with it off.
  const std::uint32_t with_mse = ppcr::kCriterionCostDrop | ppcr::kCriterionMsePrev;
  const auto mse_auto = pose_with(ErrorModel::kPlane, kAuto, 0.01, with_mse);
  const auto mse_off = pose_with(ErrorModel::kPlane, 0.0, 0.01, with_mse);
  const auto mse_1e2 = pose_with(ErrorModel::kPlane, 1e-2, 0.01, with_mse);
  CHECK(mse_auto.first == mse_off.first);
  CHECK(mse_auto.second == mse_off.second);
  CHECK(mse_auto.first != mse_1e2.first);
  // Point model: the run with it off.
  const auto point_auto = pose_with(ErrorModel::kPoint, kAuto, 0.01);
  const auto point_off = pose_with(ErrorModel::kPoint, 0.0, 0.01);
  const auto point_1e2 = pose_with(ErrorModel::kPoint, 1e-2, 0.01);
  CHECK(point_auto.first == point_off.first);
  CHECK(point_auto.second == point_off.second);
  CHECK(point_auto.first != point_1e2.first);
}

TEST_CASE(
    "coarse_stride: every stride-th point is registered while the EM scale settles (coarse, then "
    "halving), every point from then on",
    "[registration]") {
  const Scene sc = make_scene(3000, 20000, false);
  RegistrationOptions o = scene_options();
  o.expert.coarse_stride = 3;
  const RegistrationResult r = ppcr::align(sc.source, sc.target, o);
  INFO(describe(r));
  REQUIRE(r.status.ok());
  REQUIRE(r.source_points == 3000);
  // The coarse phase holds the scale at radius / 2 (e_step.hpp), then the scale halves while
  // the EM estimate is below its shrink limit (em_min_shrink = 1/4 of s^2): those iterations
  // registered the 1000 points of the coarse level; from the first that neither holds nor halves
  // the scale on, every iteration registers more (all 3000 in range here).
  const double coarse_scale = 0.5 * o.radius;
  int coarse_rows = 0;
  int halving_rows = 0;
  bool settling = true;
  double previous_scale = 0.0;
  for (const ppcr::IterationRecord& h : r.history) {
    INFO("iteration " << h.iteration << " scale " << h.scale);
    const bool held = std::abs(h.scale - coarse_scale) < 1e-12;
    const bool halved = !held && std::abs(h.scale - 0.5 * previous_scale) < 1e-12 * coarse_scale;
    settling = settling && (held || halved);
    coarse_rows += held ? 1 : 0;
    halving_rows += settling && halved ? 1 : 0;
    if (settling) {
      CHECK(h.matched_source_points <= 1000);
      CHECK(h.matched_source_points > 900);
    } else {
      CHECK(h.matched_source_points > 2700);
    }
    previous_scale = h.scale;
  }
  CHECK(coarse_rows >= 2);
  CHECK(halving_rows >= 1);
  CHECK(coarse_rows + halving_rows < r.iterations);
  CHECK(r.matched_source_points > 2700);
  CHECK((r.T_target_source.linear() - sc.T_true.linear()).norm() < 1e-3);
  CHECK((r.T_target_source.translation() - sc.T_true.translation()).norm() < 1e-3);

  SECTION("stopped in the coarse phase: the result describes the coarse level") {
    RegistrationOptions o2 = o;
    o2.max_iterations = 2;
    const RegistrationResult r2 = ppcr::align(sc.source, sc.target, o2);
    REQUIRE(r2.stop_reason == StopReason::kMaxIterations);
    REQUIRE(std::abs(r2.history.back().scale - coarse_scale) < 1e-12);
    CHECK(r2.matched_source_points <= 1000);
    CHECK(r2.information.allFinite());
    CHECK(r2.information.trace() > 0.0);
    CHECK(r2.degenerate_directions == 0);
  }
}

TEST_CASE(
    "the automatic coarse stride is 2 with the plane model and 1 with the point model, lowered "
    "to keep 1000 points",
    "[registration]") {
  REQUIRE(RegistrationOptions().expert.coarse_stride == ppcr::ExpertOptions::kAutomatic);

  // A run's pose, LM steps and first iteration's pairs (the coarse level's, if it had one).
  struct Run {
    Eigen::Matrix4d pose;
    int lm_iterations;
    std::size_t first_pairs;
    bool operator==(const Run& b) const {
      return pose == b.pose && lm_iterations == b.lm_iterations && first_pairs == b.first_pairs;
    }
  };
  auto run_with = [](const Scene& sc, ppcr::ErrorModel model, int stride,
                     ppcr::ScaleMode scale = ppcr::ScaleMode::kEM) {
    RegistrationOptions o = scene_options();
    o.error_model = model;
    o.expert.coarse_stride = stride;
    o.expert.scale_mode = scale;
    if (scale == ppcr::ScaleMode::kFixed) o.expert.scale = 0.02;
    const RegistrationResult r = ppcr::align(sc.source, sc.target, o);
    REQUIRE(r.status.ok());
    REQUIRE(!r.history.empty());
    return Run{r.T_target_source.matrix(), r.lm_iterations, r.history.front().correspondences};
  };
  using ppcr::ErrorModel;
  const int kAuto = ppcr::ExpertOptions::kAutomatic;
  const Scene sc = make_scene(3000, 20000, false);
  // Plane model: the run of stride 2, to the bit; not the run of stride 1.
  const Run plane_auto = run_with(sc, ErrorModel::kPlane, kAuto);
  const Run plane_2 = run_with(sc, ErrorModel::kPlane, 2);
  const Run plane_1 = run_with(sc, ErrorModel::kPlane, 1);
  CHECK(plane_auto == plane_2);
  CHECK(plane_auto.pose != plane_1.pose);
  CHECK(plane_2.first_pairs < plane_1.first_pairs * 6 / 10);  // about half the points
  // Point model: the run of stride 1.
  const Run point_auto = run_with(sc, ErrorModel::kPoint, kAuto);
  const Run point_1 = run_with(sc, ErrorModel::kPoint, 1);
  const Run point_2 = run_with(sc, ErrorModel::kPoint, 2);
  CHECK(point_auto == point_1);
  CHECK(point_auto.pose != point_2.pose);
  // 3000 points keep stride 3 (1000 points), lower stride 4 to 3.
  const Run plane_3 = run_with(sc, ErrorModel::kPlane, 3);
  const Run plane_4 = run_with(sc, ErrorModel::kPlane, 4);
  CHECK(plane_4 == plane_3);
  CHECK(plane_3.pose != plane_2.pose);
  // Without the EM scale there is no coarse phase: any stride is the run of stride 1 (the same
  // pairs from the first iteration on).
  const Run fixed_4 = run_with(sc, ErrorModel::kPlane, 4, ppcr::ScaleMode::kFixed);
  const Run fixed_1 = run_with(sc, ErrorModel::kPlane, 1, ppcr::ScaleMode::kFixed);
  CHECK(fixed_4 == fixed_1);
  // Below 2000 points, the whole source: automatic is the run of stride 1.
  const Scene small = make_scene(1999, 20000, false);
  CHECK(run_with(small, ErrorModel::kPlane, kAuto) == run_with(small, ErrorModel::kPlane, 1));
}

TEST_CASE(
    "a Registration reused across sizes, and after a run cancelled in the coarse phase, equals "
    "one-shot align with the coarse level",
    "[registration]") {
  const Scene a = make_scene(3000, 20000, false, 101);
  const Scene b = make_scene(2500, 20000, false, 102);
  bool cancel = false;
  RegistrationOptions o = scene_options();  // the automatic stride: 2 for both sources
  o.on_iteration = [&cancel](const ppcr::IterationRecord& r) {
    return !(cancel && r.iteration >= 2);
  };
  const RegistrationResult a_once = ppcr::align(a.source, a.target, o);
  const RegistrationResult b_once = ppcr::align(b.source, a.target, o);
  REQUIRE(a_once.status.ok());
  REQUIRE(b_once.status.ok());
  for (bool cancel_first : {false, true}) {
    INFO("first run " << (cancel_first ? "cancelled in the coarse phase" : "complete"));
    ppcr::Registration reg(o);
    REQUIRE(reg.set_target(a.target).ok());
    cancel = cancel_first;
    const RegistrationResult a1 = reg.align(a.source);
    cancel = false;
    if (cancel_first) {
      REQUIRE(a1.stop_reason == StopReason::kCancelled);
      CHECK(a1.matched_source_points <= 1500);  // the coarse level's rows
    } else {
      CHECK(a1.T_target_source.matrix() == a_once.T_target_source.matrix());
    }
    const RegistrationResult b1 = reg.align(b.source);
    const RegistrationResult a2 = reg.align(a.source);
    CHECK(b1.T_target_source.matrix() == b_once.T_target_source.matrix());
    CHECK(b1.iterations == b_once.iterations);
    CHECK(a2.T_target_source.matrix() == a_once.T_target_source.matrix());
    CHECK(a2.iterations == a_once.iterations);
    CHECK(a2.correspondences == a_once.correspondences);
  }
}

TEST_CASE("a coarse level that finds no pair gives way to every point", "[registration]") {
  // One source point lies in the target's reach, 4000 others far from it: a coarse level that
  // leaves that point out finds no pair. The run must not stop for want of correspondences, as
  // the run with every point does not, and then equals it.
  Rng rng(9);
  const PointCloud target = core_test::uniform_cloud(rng, 2000, -0.5, 0.5);
  PointCloud source;
  for (int i = 0; i < 2000; ++i) {
    const double x = -10.0 + 20.0 * (i % 50) / 49.0, y = -10.0 + 20.0 * (i / 50) / 39.0;
    source.emplace_back(x, y, 50.0);
    source.emplace_back(x, y, -50.0);
  }
  source.emplace_back(0.01, -0.02, 0.03);  // the one near point, mid-cloud in Z-order
  RegistrationOptions o;
  o.radius = 0.2;
  o.expert.coarse_stride = 1;
  const RegistrationResult every = ppcr::align(source, target, o);
  REQUIRE(every.status.code() != StatusCode::kNoCorrespondences);
  REQUIRE(every.matched_source_points == 1);
  for (int stride = 2; stride <= 4; ++stride) {  // 4001 points: none lowered
    INFO("stride " << stride);
    o.expert.coarse_stride = stride;
    const RegistrationResult r = ppcr::align(source, target, o);
    CHECK(r.status.code() == every.status.code());
    CHECK(r.stop_reason == every.stop_reason);
    CHECK(r.matched_source_points == 1);
  }
}

TEST_CASE("the noise floor holds the EM scale at a multiple of the target's surface noise",
          "[registration]") {
  // The scene's surfaces, each point moved by isotropic noise of std 2 mm.
  Scene sc = make_scene(3000, 20000, false);
  Rng rng(7);
  for (PointCloud* cloud : {&sc.source, &sc.target}) {
    for (Eigen::Vector3d& p : *cloud) {
      p += Eigen::Vector3d(core_test::gaussian(rng, 0.002), core_test::gaussian(rng, 0.002),
                           core_test::gaussian(rng, 0.002));
    }
  }
  RegistrationOptions o = scene_options();
  o.error_model = ppcr::ErrorModel::kPlane;
  // Reference: the target's surface noise from its own normal fits (the registration fits the
  // same points shifted by their median, so equal up to rounding).
  ppcr::detail::KdTree tree;
  REQUIRE(tree.build(sc.target).ok());
  std::vector<Eigen::Vector3d> normals;
  ppcr::detail::Buffer<double> spread;
  ppcr::detail::compute_normals(sc.target, tree, o.expert.normal_neighbours, nullptr, &normals,
                                &spread);
  const double noise = ppcr::detail::upper_median(&spread);
  REQUIRE(noise > 0.0);

  const RegistrationResult free_scale = ppcr::align(sc.source, sc.target, o);
  REQUIRE(free_scale.status.ok());
  CHECK(free_scale.target_surface_noise == Approx(noise).epsilon(1e-9));
  INFO("surface noise " << noise << ", EM scale without a floor " << free_scale.scale);
  // Without the floor the EM scale ends below 2x the surface noise, so the floor below binds.
  REQUIRE(free_scale.scale < 2.0 * noise);

  o.expert.noise_floor = 2.0;
  const RegistrationResult floored = ppcr::align(sc.source, sc.target, o);
  INFO(describe(floored));
  REQUIRE(floored.status.ok());
  CHECK(floored.converged());
  CHECK(floored.scale == Approx(2.0 * floored.target_surface_noise).epsilon(1e-12));
  for (const ppcr::IterationRecord& h : floored.history) {
    CHECK(h.scale >= 0.999 * 2.0 * floored.target_surface_noise);
  }
  CHECK(rotation_error_deg(floored.T_target_source, sc.T_true) < 0.1);
  CHECK(ppcr::translation_error(floored.T_target_source, sc.T_true) < 2e-3);
  // em_min_scale still applies when it is the larger floor.
  o.expert.em_min_scale = 3.0 * noise;
  CHECK(ppcr::align(sc.source, sc.target, o).scale == Approx(3.0 * noise).epsilon(1e-12));
  // Raw and fixed scales have no EM schedule: the option changes nothing there.
  o.expert.em_min_scale = 0.0;
  o.expert.scale_mode = ppcr::ScaleMode::kFixed;
  o.expert.scale = 0.05;
  const RegistrationResult fixed_floor = ppcr::align(sc.source, sc.target, o);
  o.expert.noise_floor = 0.0;
  const RegistrationResult fixed_none = ppcr::align(sc.source, sc.target, o);
  CHECK(fixed_floor.scale == Approx(0.05).epsilon(1e-15));
  CHECK(fixed_floor.T_target_source.matrix() == fixed_none.T_target_source.matrix());
  o.expert.scale_mode = ppcr::ScaleMode::kEM;
  o.expert.scale = 0.0;
  o.expert.noise_floor = 2.0;

  // The point model reports no surface noise and ignores the option.
  o.error_model = ppcr::ErrorModel::kPoint;
  o.expert.em_min_scale = 0.0;
  const RegistrationResult point = ppcr::align(sc.source, sc.target, o);
  CHECK(point.target_surface_noise == 0.0);
  o.expert.noise_floor = 0.0;
  CHECK(ppcr::align(sc.source, sc.target, o).T_target_source.matrix() ==
        point.T_target_source.matrix());
}

TEST_CASE("the plane model with source normals recovers the pose on the synthetic scene",
          "[registration]") {
  RegistrationOptions o = scene_options();
  o.error_model = ppcr::ErrorModel::kPlane;
  o.expert.source_normals = true;
  SECTION("noise-free, the same points: exact") {
    const Scene sc = make_scene(0, 3000, true);
    const RegistrationResult r = ppcr::align(sc.source, sc.target, o);
    INFO(describe(r));
    REQUIRE(r.status.ok());
    CHECK(r.converged());
    CHECK(rotation_error_deg(r.T_target_source, sc.T_true) < 0.05);
    CHECK(rms_error(sc.source, r.T_target_source, sc.T_true) < 1e-3);
  }
  // Independent samples of the surfaces, and 1 vs 2 threads: with the target normals' tests
  // ("the plane model recovers ...", "bit-identical ...").
  SECTION("a reused Registration (other sizes) and the cache off give the one-shot pose") {
    const Scene sc = make_scene(1500, 4000, false);
    ppcr::Registration reg(o);
    REQUIRE(reg.set_target(sc.target).ok());
    const PointCloud smaller(sc.source.begin(), sc.source.begin() + 700);
    const RegistrationResult r1 = reg.align(sc.source);
    const RegistrationResult r2 = reg.align(smaller);    // buffers sized down
    const RegistrationResult r3 = reg.align(sc.source);  // and back up
    REQUIRE(r1.status.ok());
    CHECK(r1.T_target_source.matrix() ==
          ppcr::align(sc.source, sc.target, o).T_target_source.matrix());
    CHECK(r2.T_target_source.matrix() ==
          ppcr::align(smaller, sc.target, o).T_target_source.matrix());
    CHECK(r3.T_target_source.matrix() == r1.T_target_source.matrix());
    // Without the neighbour cache: the same associations, so the same pose.
    o.expert.neighbour_cache = 0;
    const RegistrationResult plain = ppcr::align(sc.source, sc.target, o);
    CHECK(plain.iterations == r1.iterations);
    CHECK((plain.T_target_source.matrix() - r1.T_target_source.matrix()).cwiseAbs().maxCoeff() <
          1e-12);
  }
}

TEST_CASE("on_iteration sees every record and can cancel", "[registration]") {
  const Scene sc = make_scene(0, 1500, true);
  RegistrationOptions o = scene_options();
  std::vector<ppcr::IterationRecord> seen;
  o.on_iteration = [&](const ppcr::IterationRecord& r) {
    seen.push_back(r);
    return true;
  };
  const RegistrationResult all = ppcr::align(sc.source, sc.target, o);
  REQUIRE(all.status.ok());
  REQUIRE(seen.size() == all.history.size());
  for (std::size_t i = 0; i < seen.size(); ++i) {
    CHECK(seen[i].iteration == all.history[i].iteration);
    CHECK(seen[i].T_target_source.matrix() == all.history[i].T_target_source.matrix());
    CHECK(seen[i].final_cost == all.history[i].final_cost);
  }
  // Cancel after the third iteration; without a history the callback still runs.
  int calls = 0;
  o.record_history = false;
  o.on_iteration = [&](const ppcr::IterationRecord& r) {
    ++calls;
    return r.iteration < 3;
  };
  const RegistrationResult cut = ppcr::align(sc.source, sc.target, o);
  CHECK(calls == 3);
  CHECK(cut.iterations == 3);
  CHECK(cut.stop_reason == StopReason::kCancelled);
  CHECK(cut.status.ok());
  CHECK_FALSE(cut.converged());
  CHECK(cut.history.empty());
  CHECK(cut.T_target_source.matrix() == all.history[2].T_target_source.matrix());
}

TEST_CASE("after the change to the fine phase's tolerance the inner LM evaluates a step",
          "[registration]") {
  // With the plane model the EM fine phase loosens the inner tolerance (1e-2). A solve may end on
  // a step predicted to lower the cost by less than that, taken unevaluated, whose drop then
  // reads 0. The first solve after the change evaluates at least one step, so the drop the
  // criterion reads there is a measured one (a drop of 0 could stop a pose still far from the
  // fine problem's optimum).
  for (std::uint64_t seed : {100u, 101u, 102u, 103u}) {
    const Scene sc = make_scene(3000, 20000, false, seed);
    RegistrationOptions o = scene_options();
    o.expert.lm_fine_function_tolerance = 1e-2;
    const RegistrationResult r = ppcr::align(sc.source, sc.target, o);
    INFO("seed " << seed << ": " << describe(r));
    REQUIRE(r.status.ok());
    std::size_t first_fine = 0;
    while (first_fine < r.history.size() && r.history[first_fine].coarse) ++first_fine;
    REQUIRE(first_fine > 0);
    REQUIRE(first_fine < r.history.size());
    const ppcr::IterationRecord& h = r.history[first_fine];
    CHECK(h.successful_steps + h.unsuccessful_steps >= 1);
    CHECK(h.final_cost < h.initial_cost);  // evaluated: the cost before the step is not reported
    CHECK(h.cost_drop > 0.0);
  }
}

// An open limitation, not run by default (hidden tag; docs/TERMINATION.md, "Slow creep"): on a
// weakly constrained surface the pose creeps in the fine phase, where the pose is not
// accelerated, each iteration moving far less than the motion guard and dropping the cost by
// less than 1 %, so the cost-drop criterion stops after 22-23 iterations 0.25-0.30 degrees off
// where 100 fixed iterations reach 0.14 degrees (seed 1; seed 6: 0.28); the verdict cannot see
// it (the points lie on the surface). Fails (open); the INFO gives the figures of
// docs/TERMINATION.md:
//   ppcr_core_registration_test "[limitation]"
TEST_CASE("cost drop on a slowly creeping pose stops near 100 fixed iterations' pose",
          "[.][limitation]") {
  for (std::uint64_t seed : {1u, 6u}) {
    Rng rng(seed);
    // A gentle bowl with a ripple along x, 2 m across: rotations about its axis and slides
    // along it change the point-to-surface distances only a little.
    auto bowl = [&rng](std::size_t n) {
      PointCloud out;
      for (std::size_t i = 0; i < n; ++i) {
        const double x = core_test::uniform(rng, -1.0, 1.0), y = core_test::uniform(rng, -1.0, 1.0);
        out.emplace_back(x, y, 0.3 * (x * x + 0.5 * y * y) + 0.02 * std::sin(3.0 * x));
      }
      return out;
    };
    const PointCloud target = bowl(20000);
    PointCloud world = bowl(5000);
    for (Eigen::Vector3d& p : world) p.z() += 0.005 * core_test::uniform(rng, -1.0, 1.0);
    const Eigen::Vector3d axis(core_test::uniform(rng, -1.0, 1.0),
                               core_test::uniform(rng, -1.0, 1.0),
                               core_test::uniform(rng, -1.0, 1.0));
    const Eigen::Isometry3d T_true =
        core_test::make_pose(axis, core_test::deg2rad(5.0), Eigen::Vector3d(0.05, -0.03, 0.02));
    const PointCloud source = core_test::transformed(world, T_true.inverse());
    RegistrationOptions o;
    o.radius = 0.3;
    const RegistrationResult r = ppcr::align(source, target, o);
    RegistrationOptions tight = o;
    tight.expert.lm_fine_function_tolerance = 0.0;
    const RegistrationResult r_tight = ppcr::align(source, target, tight);
    o.criteria = ppcr::kCriterionFixed;
    const RegistrationResult fixed = ppcr::align(source, target, o);
    auto errors = [&T_true](const RegistrationResult& x) {
      return std::to_string(rotation_error_deg(x.T_target_source, T_true)) + " deg, " +
             std::to_string((x.T_target_source.translation() - T_true.translation()).norm()) +
             " m, " + std::to_string(x.iterations) + " iterations, " + ppcr::to_string(x.quality);
    };
    INFO("seed " << seed << ": cost drop " << errors(r) << "; --lm-fine-tolerance 0 "
                 << errors(r_tight) << "; fixed 100 " << errors(fixed));
    REQUIRE(r.status.ok());
    REQUIRE(rotation_error_deg(fixed.T_target_source, T_true) < 0.15);
    CHECK(rotation_error_deg(r.T_target_source, fixed.T_target_source) < 0.2);
  }
}

// The frozen-pose stop (docs/TERMINATION.md, "Slow creep"), reproduced and shown gone: a tabletop
// (a noisy elliptical plane holding 81 % of the points, three boxes clustered off-centre the only
// hold on rotation about its normal) 20 degrees off about an axis near the normal. Without the
// coarse phase's pose acceleration (expert.acceleration_memory = 0, the paper's plain loop) the
// pose creeps a fraction of a degree per iteration; the coarse phase settles 6-9 degrees off, every
// fine solve ends on one unevaluated step predicted to drop the cost by less than 1 %, and the
// cost drop stops there with the verdict good. With the default acceleration the coarse phase
// reaches the optimum that 100 fixed iterations reach. The same mechanism stopped registrations of
// a real Kinect tabletop (PCL's milk_cartoon_all_small_clorox.pcd).
TEST_CASE("cost drop on a tabletop turned about its normal stops where 100 fixed iterations do",
          "[registration]") {
  for (std::uint64_t seed : {1u, 2u}) {
    Rng rng(seed);
    PointCloud target;
    const double noise = 0.003;
    while (target.size() < 16200) {  // the table: an ellipse 2.2 x 1.4 m at z = 0
      const double x = core_test::uniform(rng, -1.1, 1.1), y = core_test::uniform(rng, -0.7, 0.7);
      if ((x / 1.1) * (x / 1.1) + (y / 0.7) * (y / 0.7) <= 1.0) {
        target.emplace_back(x, y, core_test::gaussian(rng, noise));
      }
    }
    // Three boxes within 6 cm of (0.3, 0): sides and top, sampled by area.
    for (int b = 0; b < 3; ++b) {
      const Eigen::Vector2d centre(0.3 + core_test::uniform(rng, -0.06, 0.06),
                                   core_test::uniform(rng, -0.06, 0.06));
      const double w = 0.1 * core_test::uniform(rng, 0.8, 1.2);
      const double h = core_test::uniform(rng, 0.10, 0.26);
      for (int i = 0; i < 1267; ++i) {
        const double a = core_test::uniform(rng, -0.5, 0.5) * w,
                     e = core_test::gaussian(rng, noise);
        const int face =
            core_test::uniform(rng, 0.0, 4.0 * h + w) < w ? 4 : static_cast<int>(i % 4);
        const double z = core_test::uniform(rng, 0.0, h), side = face % 2 == 0 ? -0.5 : 0.5;
        Eigen::Vector3d q;
        if (face == 4) {
          q = Eigen::Vector3d(a, core_test::uniform(rng, -0.5, 0.5) * w, h + e);
        } else if (face < 2) {
          q = Eigen::Vector3d(side * w + e, a, z);
        } else {
          q = Eigen::Vector3d(a, side * w + e, z);
        }
        target.emplace_back(centre.x() + q.x(), centre.y() + q.y(), q.z());
      }
    }
    Eigen::Vector3d lo = target[0], hi = target[0], centroid = Eigen::Vector3d::Zero();
    for (const Eigen::Vector3d& p : target) {
      lo = lo.cwiseMin(p);
      hi = hi.cwiseMax(p);
      centroid += p;
    }
    centroid /= static_cast<double>(target.size());
    const double extent = (hi - lo).norm(),
                 azimuth = core_test::uniform(rng, 0.0, 2.0 * core_test::kPi);
    const double tilt = core_test::deg2rad(16.0);
    const Eigen::Vector3d axis(std::sin(tilt) * std::cos(azimuth),
                               std::sin(tilt) * std::sin(azimuth), std::cos(tilt));
    // The source: the same points turned 20 degrees about the centroid and shifted 7 % of the
    // extent; T_true maps it back.
    const Eigen::Isometry3d T_move =
        Eigen::Translation3d(centroid + 0.07 * extent * core_test::random_unit_vector(rng)) *
        core_test::make_pose(axis, core_test::deg2rad(20.0), Eigen::Vector3d::Zero()) *
        Eigen::Translation3d(-centroid);
    const Eigen::Isometry3d T_true = T_move.inverse();
    const PointCloud source = core_test::transformed(target, T_move);
    RegistrationOptions o;
    o.radius = 0.05 * extent;
    const RegistrationResult r = ppcr::align(source, target, o);
    RegistrationOptions plain = o;
    plain.expert.acceleration_memory = 0;
    const RegistrationResult r_plain = ppcr::align(source, target, plain);
    o.criteria = ppcr::kCriterionFixed;
    const RegistrationResult fixed = ppcr::align(source, target, o);
    auto errors = [&T_true](const RegistrationResult& x) {
      return std::to_string(rotation_error_deg(x.T_target_source, T_true)) + " deg, " +
             std::to_string(x.iterations) + " iterations, " + ppcr::to_string(x.stop_reason) +
             ", " + ppcr::to_string(x.quality);
    };
    INFO("seed " << seed << ": cost drop " << errors(r) << "; without acceleration "
                 << errors(r_plain) << "; fixed 100 " << errors(fixed));
    REQUIRE(r.status.ok());
    REQUIRE(rotation_error_deg(fixed.T_target_source, T_true) < 0.1);
    // The stop is reproduced by the plain loop: converged by the cost drop, degrees off.
    CHECK(r_plain.stop_reason == ppcr::StopReason::kCostDrop);
    CHECK(rotation_error_deg(r_plain.T_target_source, T_true) > 3.0);
    // ...and gone with the default.
    CHECK(r.stop_reason == ppcr::StopReason::kCostDrop);
    CHECK(rotation_error_deg(r.T_target_source, T_true) < 0.1);
  }
}

TEST_CASE("fitness, inlier RMSE and overlap: brute force at the final pose", "[registration]") {
  for (bool source_normals : {false, true}) {
    INFO("source normals " << source_normals);
    const Scene sc = make_scene(2000, 8000, false);
    RegistrationOptions o = scene_options();
    o.expert.source_normals = source_normals;
    const RegistrationResult r = ppcr::align(sc.source, sc.target, o);
    REQUIRE(r.status.ok());
    const double radius_sq = o.radius * o.radius;
    // Nearest target point within the radius of each moved source point, and back.
    auto matched = [&](const PointCloud& from, const PointCloud& to, const Eigen::Isometry3d& T,
                       double* sum_sq) {
      std::size_t count = 0;
      for (const Eigen::Vector3d& x : from) {
        double best = HUGE_VAL;
        for (const Eigen::Vector3d& y : to) best = std::min(best, (y - T * x).squaredNorm());
        if (best <= radius_sq) ++count, *sum_sq += best;
      }
      return count;
    };
    double sum_sq = 0.0, unused = 0.0;
    const std::size_t n = matched(sc.source, sc.target, r.T_target_source, &sum_sq);
    CHECK(r.fitness == Approx(static_cast<double>(n) / sc.source.size()).epsilon(1e-12));
    CHECK(r.inlier_rmse == Approx(std::sqrt(sum_sq / n)).epsilon(1e-9));
    const std::size_t back = matched(sc.target, sc.source, r.T_target_source.inverse(), &unused);
    const double both = std::min(r.fitness, static_cast<double>(back) / sc.target.size());
    CHECK(r.overlap == Approx(source_normals ? both : r.fitness).epsilon(1e-12));
    CHECK(r.fitness > 0.9);  // a correct registration of overlapping samples
    CHECK(r.quality_ms >= 0.0);
    // The target's spacing (8000 <= 2 x 4096 samples: every point), then the matched source
    // points within twice that of the target's surface: along the nearest target point's normal,
    // that point within the normal fits' reach.
    const double spacing = brute_force_spacing(sc.target);
    CHECK(r.target_spacing == Approx(spacing).epsilon(1e-9));
    // ... over the source points within min(radius, 8 spacings) of the target.
    const double near = std::min(o.radius, 8.0 * spacing);
    const double reach = brute_force_reach(sc.target, o.expert.normal_neighbours);
    std::size_t close = 0, near_count = 0, along_normal = 0;
    for (const Eigen::Vector3d& x : sc.source) {
      const Eigen::Vector3d p = r.T_target_source * x;
      double best = HUGE_VAL;
      std::size_t nearest = 0;
      for (std::size_t k = 0; k < sc.target.size(); ++k) {
        const double d_sq = (sc.target[k] - p).squaredNorm();
        if (d_sq < best) best = d_sq, nearest = k;
      }
      if (best > radius_sq || best > near * near) continue;
      ++near_count;
      const Eigen::Vector3d normal =
          brute_force_normal(sc.target, nearest, o.expert.normal_neighbours);
      const double along = normal.dot(p - sc.target[nearest]);
      along_normal += !normal.isZero();
      const double reach_or_close = std::max(reach, 2.0 * spacing);  // never stricter
      const bool on_plane =
          along * along <= 4.0 * spacing * spacing && best <= reach_or_close * reach_or_close;
      close += normal.isZero() ? best <= 4.0 * spacing * spacing : on_plane;
    }
    CHECK(along_normal > near_count / 2);  // the plane distance is the one tested
    CHECK(r.close_fraction == Approx(static_cast<double>(close) / near_count).epsilon(1e-12));
    CHECK(r.quality == ppcr::Quality::kGood);
  }
  // A registration that found nothing measures nothing.
  const Scene sc = make_scene(500, 2000, false);
  RegistrationOptions o = scene_options();
  Eigen::Isometry3d far = Eigen::Isometry3d::Identity();
  far.translation() << 50, 0, 0;
  const RegistrationResult r = ppcr::align(sc.source, sc.target, o, far);
  CHECK(r.fitness == 0.0);
  CHECK(r.inlier_rmse == 0.0);
  CHECK(r.quality == ppcr::Quality::kFailed);
}

// A wavy surface on a 0.02 grid; the target keeps the points with x <= cut, the source is the
// whole surface shifted by (dx, dy). The wide coarse kernel first draws the source along x toward
// more overlap; the fine phase must bring it back.
namespace {
struct CutPair {
  PointCloud source, target;
  Eigen::Isometry3d T_true = Eigen::Isometry3d::Identity();
};
CutPair cut_pair(double cut, double dx, double dy) {
  CutPair c;
  for (double x = -0.5; x <= 0.5; x += 0.02) {
    for (double y = -0.5; y <= 0.5; y += 0.02) {
      const double z = 0.1 * std::sin(4 * x) * std::cos(3 * y);
      if (x <= cut) c.target.emplace_back(x, y, z);
      c.source.emplace_back(x + dx, y + dy, z);
    }
  }
  c.T_true.translation() = Eigen::Vector3d(-dx, -dy, 0.0);
  return c;
}
const std::vector<std::pair<double, double>> kCutShifts = {
    {0.01, -0.01},  {0.015, 0.0}, {0.02, 0.01}, {-0.01, 0.01},
    {0.005, 0.005}, {0.03, 0.0},  {0.0, 0.02},  {-0.02, -0.01}};
}  // namespace

TEST_CASE("a target covering 86 % or more of its source: registered to the truth from 8 starts",
          "[registration]") {
  // Measured: every translation error under 5e-6 m (the truth's residuals are zero).
  RegistrationOptions o;
  o.radius = 0.1;
  for (double cut : {0.3, 0.4}) {
    for (const auto& [dx, dy] : kCutShifts) {
      const CutPair c = cut_pair(cut, dx, dy);
      const RegistrationResult r = ppcr::align(c.source, c.target, o);
      INFO("cut " << cut << ", shift " << dx << ", " << dy << ": " << describe(r)
                  << ", translation " << r.T_target_source.translation().transpose());
      REQUIRE(r.status.ok());
      CHECK(r.converged());
      CHECK(ppcr::translation_error(r.T_target_source, c.T_true) < 1e-4);
      CHECK(rotation_error_deg(r.T_target_source, c.T_true) < 0.01);
    }
  }
}

// An open limitation, not run by default (hidden tag; docs/RELIABILITY.md, "Partial overlap on a
// weakly curved surface"): with the target covering 78 % of the source (x <= 0.2; the share of
// source points with a target point within the radius at the truth) the coarse phase
// leaves the source about one grid spacing (0.019 m) toward more overlap, and the fine phase
// stays there from 2 of the 8 starts (7 with every row kept and patience 6; fitness 0.80 against
// the truth's 0.78, verdict good); 100 fixed iterations with tight inner solves stay there from
// some starts too. Fails (open):
//   ppcr_core_registration_test "[limitation]"
TEST_CASE("a target covering 78 % of its source: registered to the truth from 8 starts",
          "[.][limitation]") {
  RegistrationOptions o;
  o.radius = 0.1;
  for (const auto& [dx, dy] : kCutShifts) {
    const CutPair c = cut_pair(0.2, dx, dy);
    const RegistrationResult r = ppcr::align(c.source, c.target, o);
    INFO("shift " << dx << ", " << dy << ": " << describe(r) << ", translation error "
                  << ppcr::translation_error(r.T_target_source, c.T_true) << ", fitness "
                  << r.fitness << ", " << ppcr::to_string(r.quality));
    REQUIRE(r.status.ok());
    CHECK(ppcr::translation_error(r.T_target_source, c.T_true) < 1e-3);
  }
}

TEST_CASE("partial overlap, sampled at random: rows beyond the target's boundary left out",
          "[registration]") {
  // The wavy surface sampled at random (2500 points each, 1 mm noise), the target cut to
  // x <= 0.3 (about 80 % of the source), the source shifted by the 8 offsets. The source points
  // past the cut but within the radius (0.1) of it have target points within the radius, and
  // pull the source toward more overlap; leaving out the rows whose nearest target point lies on
  // the target's boundary (boundary.hpp) takes part of that pull away (docs/RELIABILITY.md).
  // Measured: median error 4.8 mm, largest 5.0 mm, against 7.9 and 8.6 mm with every row kept.
  auto surface = [](core_test::Rng& rng, double x_max) {
    PointCloud cloud;
    while (cloud.size() < 2500) {
      const double x = core_test::uniform(rng, -0.5, 0.5), y = core_test::uniform(rng, -0.5, 0.5);
      const Eigen::Vector3d p(
          x, y, 0.1 * std::sin(4 * x) * std::cos(3 * y) + core_test::gaussian(rng, 0.001));
      cloud.push_back(p);
    }
    PointCloud cut;
    for (const Eigen::Vector3d& p : cloud) {
      if (p.x() <= x_max) cut.push_back(p);
    }
    return cut;
  };
  std::vector<double> left_out, kept;
  for (std::size_t i = 0; i < kCutShifts.size(); ++i) {
    core_test::Rng rng(700 + i);
    const auto [dx, dy] = kCutShifts[i];
    PointCloud source = surface(rng, 1.0);
    const PointCloud target = surface(rng, 0.3);
    for (Eigen::Vector3d& p : source) p += Eigen::Vector3d(dx, dy, 0.0);
    Eigen::Isometry3d T_true = Eigen::Isometry3d::Identity();
    T_true.translation() = Eigen::Vector3d(-dx, -dy, 0.0);
    RegistrationOptions o;
    o.radius = 0.1;
    const RegistrationResult with = ppcr::align(source, target, o);
    o.expert.reject_boundary = false;
    const RegistrationResult without = ppcr::align(source, target, o);
    REQUIRE(with.status.ok());
    REQUIRE(without.status.ok());
    left_out.push_back(ppcr::translation_error(with.T_target_source, T_true));
    kept.push_back(ppcr::translation_error(without.T_target_source, T_true));
    INFO("shift " << dx << ", " << dy << ": translation error " << left_out.back()
                  << " (rows kept: " << kept.back() << "), " << describe(with));
    CHECK(with.converged());
  }
  std::sort(left_out.begin(), left_out.end());
  std::sort(kept.begin(), kept.end());
  INFO("translation errors, rows left out: median "
       << left_out[4] << ", largest " << left_out.back() << "; rows kept: median " << kept[4]
       << ", largest " << kept.back());
  CHECK(left_out.back() < 0.006);
  CHECK(left_out[4] < 0.75 * kept[4]);
}

TEST_CASE("a wrong result is not called good: the scene registered from 120 degrees off",
          "[registration]") {
  // The local method cannot undo 120 degrees about the vertical: it ends in a wrong minimum. The
  // verdict must flag it, whatever the criterion said.
  const Scene sc = make_scene(2000, 8000, false);
  const RegistrationOptions o = scene_options();
  const Eigen::Isometry3d off = core_test::make_pose(
      Eigen::Vector3d::UnitZ(), core_test::deg2rad(120.0), Eigen::Vector3d::Zero());
  const RegistrationResult r = ppcr::align(sc.source, sc.target, o, sc.T_true * off);
  INFO("rotation error " << rotation_error_deg(r.T_target_source, sc.T_true) << " deg, fitness "
                         << r.fitness << ", close " << r.close_fraction << ", "
                         << ppcr::to_string(r.quality) << ": " << r.quality_reason);
  REQUIRE(rotation_error_deg(r.T_target_source, sc.T_true) > 10.0);
  CHECK(r.quality != ppcr::Quality::kGood);
  CHECK(std::string(r.quality_reason).size() > 0);
}

TEST_CASE("automatic radius: 8 target point spacings, reported, none without a spacing",
          "[registration]") {
  const Scene sc = make_scene(1500, 4000, false);
  RegistrationOptions o;  // radius: automatic by default
  REQUIRE(o.radius == RegistrationOptions::kAutomaticRadius);
  const RegistrationResult r = ppcr::align(sc.source, sc.target, o);
  REQUIRE(r.status.ok());
  const double spacing = brute_force_spacing(sc.target);
  CHECK(r.target_spacing == Approx(spacing).epsilon(1e-9));
  CHECK(r.radius == Approx(8.0 * spacing).epsilon(1e-9));
  CHECK(r.converged());
  CHECK(rms_error(sc.source, r.T_target_source, sc.T_true) < 1e-3);
  // A user's radius is reported as given.
  o.radius = 0.2;
  CHECK(ppcr::align(sc.source, sc.target, o).radius == 0.2);
  // A target of one repeated point has no spacing: an error naming the radius.
  o.radius = RegistrationOptions::kAutomaticRadius;
  const PointCloud same(50, Eigen::Vector3d(1, 2, 3));
  const RegistrationResult none = ppcr::align(sc.source, same, o);
  CHECK(none.status.code() == StatusCode::kInvalidArgument);
  CHECK(contains(none.status.message(), "radius"));
  CHECK(none.quality == ppcr::Quality::kFailed);
}

TEST_CASE("the verdict does not fall with a radius far larger than the scene", "[registration]") {
  // A target that covers part of the source, registered with the scene's radius and with 1000 m
  // ("no radius"): every source point is then within the radius, most far from the target, but
  // the share on the target's surface is taken within 8 spacings, so a right partial-overlap
  // result stays right.
  const Scene sc = make_scene(3000, 8000, false);
  PointCloud part;
  for (const Eigen::Vector3d& y : sc.target) {
    if (y.x() < 0.2) part.push_back(y);
  }
  REQUIRE(part.size() > 2000);
  RegistrationOptions o = scene_options();
  const RegistrationResult scene_radius = ppcr::align(sc.source, part, o);
  o.radius = 1000.0;
  const RegistrationResult huge = ppcr::align(sc.source, part, o);
  for (const RegistrationResult* r : {&scene_radius, &huge}) {
    INFO("radius " << r->radius << ": " << ppcr::to_string(r->quality) << " " << r->quality_reason
                   << ", close " << r->close_fraction << ", fitness " << r->fitness);
    REQUIRE(r->status.ok());
    CHECK(rms_error(sc.source, r->T_target_source, sc.T_true) < 5e-3);  // 0.3 / 2 mm
    CHECK(r->quality == ppcr::Quality::kGood);
    CHECK(r->close_fraction > 0.75);
  }
  CHECK(huge.fitness == 1.0);
  CHECK(scene_radius.fitness < 0.9);
}

// A corner (floor and two walls) sampled like a spinning scanner: rows 5 mm apart across, points
// 1 mm apart along, 1 mm of noise normal to the surface; the source's rows fall halfway between
// the target's, 2.5 mm (about 2.5 spacings) from the nearest target row.
PointCloud scanned_corner(double row_offset, Rng* rng) {
  PointCloud cloud;
  constexpr double kAlong = 0.001, kAcross = 0.005, kNoise = 0.001;
  for (double u = 0.0; u < 0.3; u += kAlong) {
    for (double v = row_offset; v < 0.3; v += kAcross) {
      cloud.emplace_back(u, v, core_test::gaussian(*rng, kNoise));  // floor
      cloud.emplace_back(u, core_test::gaussian(*rng, kNoise), v);  // wall y = 0
      cloud.emplace_back(core_test::gaussian(*rng, kNoise), u, v);  // wall x = 0
    }
  }
  return cloud;
}

TEST_CASE("a right registration of ring-sampled scans is not flagged", "[registration]") {
  // The verdict's close share measures the distance to the target's surface along the nearest
  // target point's normal: to that point itself, most of these right results would lie farther
  // than 2 spacings and read as surfaces that do not coincide.
  Rng rng(7);
  const PointCloud target = scanned_corner(0.0, &rng);
  const PointCloud source_true = scanned_corner(0.0025, &rng);
  Eigen::Isometry3d T_true = Eigen::Isometry3d::Identity();
  T_true.linear() = Eigen::AngleAxisd(0.05, Eigen::Vector3d(1, 2, 3).normalized()).matrix();
  T_true.translation() = Eigen::Vector3d(0.004, -0.003, 0.002);
  PointCloud source;  // source = T_true^-1 source_true: registering it gives T_true
  for (const Eigen::Vector3d& x : source_true) source.push_back(T_true.inverse() * x);
  RegistrationOptions o;
  o.radius = 0.03;
  const RegistrationResult r = ppcr::align(source, target, o);
  INFO(ppcr::to_string(r.quality) << " " << r.quality_reason << ", close " << r.close_fraction
                                  << ", spacing " << r.target_spacing);
  REQUIRE(r.status.ok());
  REQUIRE(rms_error(source, r.T_target_source, T_true) < 1e-3);
  REQUIRE(r.target_spacing == Approx(0.001).epsilon(0.2));
  // To the nearest point, the share within 2 spacings is low (the rows' gap), so the test is one
  // the point distance would fail (sampled: every 20th source point).
  std::size_t near = 0, close = 0;
  for (std::size_t j = 0; j < source.size(); j += 20) {
    const Eigen::Vector3d p = r.T_target_source * source[j];
    double d_sq = HUGE_VAL;
    for (const Eigen::Vector3d& y : target) d_sq = std::min(d_sq, (y - p).squaredNorm());
    if (d_sq > 64.0 * r.target_spacing * r.target_spacing) continue;
    ++near;
    close += d_sq <= 4.0 * r.target_spacing * r.target_spacing;
  }
  CHECK(static_cast<double>(close) / near < 0.5);
  CHECK(r.close_fraction > 0.9);
  CHECK(r.quality == ppcr::Quality::kGood);
}

TEST_CASE("exact duplicates are registered once: the clean clouds' pose, and counted",
          "[registration]") {
  const Scene sc = make_scene(2000, 4000, false);
  const RegistrationOptions o = scene_options();
  // Copies as a scanner leaves them: hundreds of invalid returns at its origin (in each cloud's
  // own frame), and points written twice; shuffled in.
  auto with_copies = [](const PointCloud& clean, std::size_t at_origin, std::uint64_t seed) {
    Rng rng(seed);
    PointCloud out = clean;
    out.push_back(Eigen::Vector3d::Zero());  // the origin once: a real point the copies repeat
    for (std::size_t i = 0; i < at_origin; ++i) out.push_back(Eigen::Vector3d::Zero());
    for (std::size_t i = 0; i < clean.size(); i += 3) out.push_back(clean[i]);
    for (std::size_t i = out.size() - 1; i > 0; --i) {
      std::swap(out[i], out[static_cast<std::size_t>(rng() % (i + 1))]);
    }
    return out;
  };
  PointCloud clean_source = sc.source, clean_target = sc.target;
  clean_source.push_back(Eigen::Vector3d::Zero());
  clean_target.push_back(Eigen::Vector3d::Zero());
  const RegistrationResult clean = ppcr::align(clean_source, clean_target, o);
  const RegistrationResult r =
      ppcr::align(with_copies(sc.source, 500, 1), with_copies(sc.target, 300, 2), o);
  REQUIRE(clean.status.ok());
  REQUIRE(r.status.ok());
  CHECK(clean.source_duplicates == 0);
  CHECK(clean.target_duplicates == 0);
  CHECK(r.source_duplicates == 500 + (sc.source.size() + 2) / 3);
  CHECK(r.target_duplicates == 300 + (sc.target.size() + 2) / 3);
  CHECK(r.source_points == clean.source_points);
  CHECK(r.target_points == clean.target_points);
  // The same points, centred on another median (the copies move it): equal to rounding.
  CHECK(rms_error(sc.source, r.T_target_source, clean.T_target_source) < 1e-9);
  CHECK(r.fitness == clean.fitness);
  CHECK(r.iterations == clean.iterations);
  CHECK(rms_error(sc.source, r.T_target_source, sc.T_true) < 1e-3);
}
