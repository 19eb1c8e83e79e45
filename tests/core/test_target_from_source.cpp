// Tests of Registration::set_target_to_source(): the source of the last align() made the target
// without preparing it again. The reference is a fresh Registration given the same clouds with
// set_target(), scan after scan of a short synthetic sequence.
#include <catch2/catch.hpp>
#include <cstdint>
#include <limits>
#include <string>
#include <vector>

#include "core_test_util.hpp"
#include "ppcr/registration.hpp"
#include "result_checks.hpp"

using ppcr::PointCloud;
using ppcr::RegistrationOptions;
using ppcr::RegistrationResult;
using ppcr::StatusCode;

namespace {

// Five scans of the analytic scene (independent samples), each moved by 4 degrees and a few
// centimetres more than the last: scan i is in its own frame, T_world_scan(i) known.
struct Sequence {
  std::vector<PointCloud> scans;
  std::vector<Eigen::Isometry3d> T_world_scan;
};

Sequence make_sequence(std::uint64_t seed) {
  core_test::Rng rng(seed);
  Sequence s;
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  const Eigen::Isometry3d step = core_test::make_pose(
      Eigen::Vector3d(0.2, -0.3, 1.0), core_test::deg2rad(4.0), Eigen::Vector3d(0.03, 0.01, -0.01));
  for (int i = 0; i < 5; ++i) {
    const PointCloud world = core_test::analytic_scene(rng, 4000);
    s.scans.push_back(core_test::transformed(world, T.inverse()));
    // Copies (counted by each result, also when the source becomes the target).
    for (int k = 0; k < 20 + i; ++k) s.scans.back().push_back(s.scans.back()[10 * k]);
    s.T_world_scan.push_back(T);
    T = T * step;
  }
  return s;
}

// Registers scan i onto scan i-1 for every i, from the previous motion: `reused` makes each
// source the next target with set_target_to_source(), the reference calls set_target(scan i-1).
std::vector<RegistrationResult> run(const Sequence& seq, const RegistrationOptions& o,
                                    bool reused) {
  ppcr::Registration reg(o);
  std::vector<RegistrationResult> out;
  Eigen::Isometry3d motion = Eigen::Isometry3d::Identity();
  for (std::size_t i = 1; i < seq.scans.size(); ++i) {
    const ppcr::Status s =
        reused && i > 1 ? reg.set_target_to_source() : reg.set_target(seq.scans[i - 1]);
    REQUIRE(s.ok());
    out.push_back(reg.align(seq.scans[i], motion));
    REQUIRE(out.back().status.ok());
    motion = out.back().T_target_source;
  }
  return out;
}

double max_difference(const Eigen::Isometry3d& a, const Eigen::Isometry3d& b) {
  return (a.matrix() - b.matrix()).cwiseAbs().maxCoeff();
}

}  // namespace

TEST_CASE("set_target_to_source: the same results as set_target with the same cloud",
          "[registration][sequence]") {
  const Sequence seq = make_sequence(7);
  struct Case {
    const char* name;
    ppcr::ErrorModel model;
    bool source_normals;
    double voxel;
  };
  // With source normals the source's tree and fits are taken over; without them (or with the
  // point model) the target's tree and fits are made from the prepared source.
  for (const Case& c : {Case{"plane, source normals", ppcr::ErrorModel::kPlane, true, 0.0},
                        Case{"plane, source normals, voxel", ppcr::ErrorModel::kPlane, true, 0.03},
                        Case{"plane, target normals", ppcr::ErrorModel::kPlane, false, 0.0},
                        Case{"point", ppcr::ErrorModel::kPoint, false, 0.03}}) {
    INFO(c.name);
    RegistrationOptions o;
    o.radius = 0.2;  // smaller than every scan's extent: both ways use the unit 0.2
    o.error_model = c.model;
    o.expert.source_normals = c.source_normals;
    o.source_voxel = o.target_voxel = c.voxel;
    const std::vector<RegistrationResult> fresh = run(seq, o, false);
    const std::vector<RegistrationResult> reused = run(seq, o, true);
    for (std::size_t i = 0; i < fresh.size(); ++i) {
      INFO("scan " << i + 1);
      const RegistrationResult& a = fresh[i];
      const RegistrationResult& b = reused[i];
      test_checks::check_identical(a, b);
      CHECK(b.target_duplicates == (c.voxel > 0.0 ? 0u : 20u + i));
      // And right: scan i + 1 onto scan i is T_world_scan(i)^-1 T_world_scan(i + 1).
      const Eigen::Isometry3d truth = seq.T_world_scan[i].inverse() * seq.T_world_scan[i + 1];
      CHECK(core_test::angle_between_deg(b.T_target_source.linear(), truth.linear()) < 0.2);
      CHECK((b.T_target_source.translation() - truth.translation()).norm() < 0.005);
    }
  }
}

TEST_CASE("set_target_to_source: within rounding when the internal unit differs",
          "[registration][sequence]") {
  // The automatic radius: set_target() takes the unit from each target's extent, the reused
  // target keeps the previous one's.
  const Sequence seq = make_sequence(8);
  const RegistrationOptions o;
  const std::vector<RegistrationResult> fresh = run(seq, o, false);
  const std::vector<RegistrationResult> reused = run(seq, o, true);
  for (std::size_t i = 0; i < fresh.size(); ++i) {
    INFO("scan " << i + 1);
    CHECK(max_difference(reused[i].T_target_source, fresh[i].T_target_source) < 1e-9);
    CHECK(reused[i].radius == Approx(fresh[i].radius).epsilon(1e-12));
    CHECK(reused[i].target_spacing == Approx(fresh[i].target_spacing).epsilon(1e-12));
    CHECK(reused[i].quality == fresh[i].quality);
  }
}

TEST_CASE(
    "set_target_to_source: a source at another scale than the last target is prepared "
    "again in its own unit",
    "[registration][sequence]") {
  // The automatic radius takes the unit from each target's extent: a room-sized target, then a
  // piece of it within 0.35 m of a point as the next target (its own unit about 3.5x smaller,
  // beyond the 2x a kept unit may be off).
  core_test::Rng rng(10);
  const PointCloud room = core_test::analytic_scene(rng, 20000);
  auto piece = [&rng](const Eigen::Isometry3d& T_scan_world) {
    const Eigen::Vector3d centre(0.3, -0.2, 0.25);  // the sphere's lower half and the floor
    PointCloud out;
    for (const Eigen::Vector3d& p : core_test::analytic_scene(rng, 60000)) {
      if ((p - centre).norm() < 0.35) out.push_back(T_scan_world * p);
    }
    return out;
  };
  const Eigen::Isometry3d step = core_test::make_pose(
      Eigen::Vector3d(0.0, 0.0, 1.0), core_test::deg2rad(2.0), Eigen::Vector3d(0.01, 0.0, 0.0));
  const PointCloud b = piece(step.inverse());
  const PointCloud c = piece((step * step).inverse());
  const RegistrationOptions o;
  ppcr::Registration reused(o);
  REQUIRE(reused.set_target(room).ok());
  REQUIRE(reused.align(b, step).status.ok());
  REQUIRE(reused.set_target_to_source().ok());
  const RegistrationResult r = reused.align(c, step);
  ppcr::Registration fresh(o);
  REQUIRE(fresh.set_target(b).ok());
  const RegistrationResult f = fresh.align(c, step);
  // Prepared again from its filtered points (mapped back from the internal frame, to rounding)
  // in its own unit: set_target()'s results within rounding.
  REQUIRE(r.status.ok());
  CHECK(max_difference(r.T_target_source, f.T_target_source) < 1e-9);
  CHECK(r.radius == Approx(f.radius).epsilon(1e-12));
  CHECK(r.target_spacing == Approx(f.target_spacing).epsilon(1e-12));
  CHECK(r.target_points == f.target_points);
  CHECK(r.quality == f.quality);
  // Copies in b: counted when b, prepared again, is the target (the copies move b's median, so
  // the pose is not compared here).
  PointCloud b_copies = b;
  for (std::size_t k = 0; k < 30; ++k) b_copies.push_back(b[7 * k]);
  ppcr::Registration with_copies(o);
  REQUIRE(with_copies.set_target(room).ok());
  REQUIRE(with_copies.align(b_copies, step).source_duplicates == 30);
  REQUIRE(with_copies.set_target_to_source().ok());
  const RegistrationResult rc = with_copies.align(c, step);
  REQUIRE(rc.status.ok());
  CHECK(rc.target_duplicates == 30);
  CHECK(rc.target_points == r.target_points);
}

TEST_CASE("set_target_to_source: refusals", "[registration][sequence]") {
  const Sequence seq = make_sequence(9);
  RegistrationOptions o;
  o.radius = 0.2;
  SECTION("no align() yet") {
    ppcr::Registration reg(o);
    CHECK(reg.set_target_to_source().code() == StatusCode::kEmptyCloud);
    REQUIRE(reg.set_target(seq.scans[0]).ok());
    const ppcr::Status s = reg.set_target_to_source();
    CHECK(s.code() == StatusCode::kEmptyCloud);
    CHECK(s.message().find("align()") != std::string::npos);
  }
  SECTION("once per align()") {
    ppcr::Registration reg(o);
    REQUIRE(reg.set_target(seq.scans[0]).ok());
    REQUIRE(reg.align(seq.scans[1]).status.ok());
    REQUIRE(reg.set_target_to_source().ok());
    CHECK(reg.align(seq.scans[2]).status.ok());
    REQUIRE(reg.set_target_to_source().ok());  // scan 2's turn
    CHECK(reg.set_target_to_source().code() == StatusCode::kEmptyCloud);
  }
  SECTION("the last align() prepared no source") {
    ppcr::Registration reg(o);
    REQUIRE(reg.set_target(seq.scans[0]).ok());
    REQUIRE(reg.align(seq.scans[1]).status.ok());  // a source to take, until...
    SECTION("an empty source") { REQUIRE_FALSE(reg.align(PointCloud()).status.ok()); }
    SECTION("a non-finite guess") {
      Eigen::Isometry3d guess = Eigen::Isometry3d::Identity();
      guess(0, 3) = std::numeric_limits<double>::quiet_NaN();
      REQUIRE_FALSE(reg.align(seq.scans[2], guess).status.ok());
    }
    CHECK(reg.set_target_to_source().code() == StatusCode::kEmptyCloud);
  }
  SECTION("a refusal leaves no target") {
    ppcr::Registration reg(o);
    REQUIRE(reg.set_target(seq.scans[0]).ok());
    REQUIRE(reg.set_target_to_source().code() == StatusCode::kEmptyCloud);
    CHECK(reg.align(seq.scans[1]).status.code() == StatusCode::kEmptyCloud);
  }
  SECTION("different voxel leaves") {
    o.source_voxel = 0.02;
    o.target_voxel = 0.03;
    ppcr::Registration reg(o);
    REQUIRE(reg.set_target(seq.scans[0]).ok());
    REQUIRE(reg.align(seq.scans[1]).status.ok());
    const ppcr::Status s = reg.set_target_to_source();
    CHECK(s.code() == StatusCode::kInvalidArgument);
    CHECK(s.message().find("source_voxel (0.02)") != std::string::npos);
    CHECK(s.message().find("target_voxel (0.03)") != std::string::npos);
  }
  SECTION("invalid options") {
    o.max_neighbours = 0;
    ppcr::Registration reg(o);
    CHECK(reg.set_target_to_source().code() == StatusCode::kInvalidArgument);
  }
}
