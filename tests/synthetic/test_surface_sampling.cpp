// sample_surface(): points on the scene's surfaces, outside the solids, deterministic.
#include <catch2/catch.hpp>
#include <string>

#include "ppcr/synthetic.hpp"
#include "scene_reference.hpp"
#include "synthetic/scene.hpp"

using ppcr::PointCloud;
using ppcr::synthetic::SceneKind;
using ppcr::synthetic::SurfaceSampleOptions;

TEST_CASE("surface samples lie on the scene's surfaces, outside the solids",
          "[synthetic][sampling]") {
  for (const SceneKind kind : {SceneKind::kRoom, SceneKind::kStreet}) {
    SurfaceSampleOptions options;
    options.scene = kind;
    options.seed = 3;
    options.count = 20000;
    PointCloud points;
    REQUIRE(ppcr::synthetic::sample_surface(options, &points).ok());
    REQUIRE(points.size() == options.count);
    const auto scene = ppcr::synthetic::internal::make_scene(kind, 3);
    const synth_test::SceneDistance distance(scene);
    std::size_t inside = 0;
    double worst = 0.0;
    for (const Eigen::Vector3d& p : points) {
      worst = std::max(worst, distance(p));
      // Strictly inside (beyond rounding: a point on its own solid's face may test inside).
      for (const auto& b : scene.boxes) {
        inside += synth_test::inside(p, b) && synth_test::surface_distance(p, b) > 1e-9;
      }
      for (const auto& s : scene.spheres) {
        inside += synth_test::inside(p, s) && synth_test::surface_distance(p, s) > 1e-9;
      }
      for (const auto& c : scene.cylinders) {
        inside += synth_test::inside(p, c) && synth_test::surface_distance(p, c) > 1e-9;
      }
    }
    CHECK(worst < 1e-9);
    CHECK(inside == 0);
    // Spread over the scene: the samples' bounds cover most of the scene's bounds.
    Eigen::AlignedBox3d covered;
    for (const Eigen::Vector3d& p : points) covered.extend(p);
    CHECK(covered.volume() > 0.8 * scene.bounds.volume());
  }
}

TEST_CASE("surface sampling is deterministic and checks its options", "[synthetic][sampling]") {
  SurfaceSampleOptions options;
  options.count = 1000;
  PointCloud a;
  PointCloud b;
  REQUIRE(ppcr::synthetic::sample_surface(options, &a).ok());
  REQUIRE(ppcr::synthetic::sample_surface(options, &b).ok());
  CHECK(a == b);
  options.seed = 2;
  REQUIRE(ppcr::synthetic::sample_surface(options, &b).ok());
  CHECK(a != b);

  options.count = 0;
  const ppcr::Status status = ppcr::synthetic::sample_surface(options, &b);
  CHECK(status.code() == ppcr::StatusCode::kInvalidArgument);
  CHECK(status.message().find("count = 0") != std::string::npos);
  CHECK(b.size() == 1000);
  options.count = 10;
  CHECK(ppcr::synthetic::sample_surface(options, nullptr).code() ==
        ppcr::StatusCode::kInvalidArgument);
}
