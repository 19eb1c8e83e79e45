// measure_alignment's surface test on hand-placed points: along the nearest target point's
// normal, within the reach (never below close_distance), and the point test without normals.
#include <catch2/catch.hpp>
#include <vector>

#include "alignment_quality.hpp"
#include "core_test_util.hpp"
#include "kdtree.hpp"
#include "normal_equations.hpp"
#include "target_normals.hpp"

using ppcr::PointCloud;

TEST_CASE(
    "close_fraction: on the tangent plane, within the reach, never stricter than the point "
    "test",
    "[alignment_quality]") {
  // A 30 x 30 grid on z = 0, 1 cm apart, with its PCA normals (+-z).
  PointCloud target;
  for (int i = 0; i < 30; ++i) {
    for (int j = 0; j < 30; ++j) target.emplace_back(0.01 * i, 0.01 * j, 0.0);
  }
  ppcr::detail::KdTree tree;
  REQUIRE(tree.build(target).ok());
  std::vector<Eigen::Vector3d> normals;
  ppcr::detail::compute_normals(target, tree, 20, nullptr, &normals);
  std::vector<ppcr::detail::PlanePoint> planes;
  ppcr::detail::pack_plane_points(target, normals, 0.05, &planes);
  const PointCloud source = {
      {0.15, 0.15, 0.005},  // 5 mm above the plane, 5 mm from the grid point below it
      {0.32, 0.15, 0.0},    // on the plane's extension, 3 cm beyond its edge
      {0.15, 0.15, 0.03},   // 3 cm above the plane
  };
  const double radius = 0.1, near = 0.08, close = 0.02;
  std::vector<double> scratch;
  auto share = [&](const ppcr::detail::SurfaceTest& t) {
    return ppcr::detail::measure_alignment(tree, target, source, nullptr,
                                           Eigen::Isometry3d::Identity(), radius, near, t, nullptr,
                                           &scratch)
        .close_fraction;
  };
  // Every point is within near_distance; only the first is within 2 cm of its nearest point.
  CHECK(share({close, nullptr, 0.0}) == Approx(1.0 / 3.0));
  // Along the normal: the second is on the plane, but 3 cm from the nearest sample, beyond a
  // 2.24 cm reach (a 20-neighbour fit on this grid) and within a 5 cm one.
  CHECK(share({close, &planes, 0.0224}) == Approx(1.0 / 3.0));
  CHECK(share({close, &planes, 0.05}) == Approx(2.0 / 3.0));
  // A reach below close_distance does not exclude the first point (5 mm from its nearest).
  CHECK(share({close, &planes, 0.001}) == Approx(1.0 / 3.0));
  // Far above the plane: never on the surface, whatever the reach.
  CHECK(share({close, &planes, 1.0}) == Approx(2.0 / 3.0));
}
