// measure_alignment's surface test on hand-placed points: along the nearest target point's
// normal, within the reach (never below close_distance), and the point test without normals.
#include <algorithm>
#include <catch2/catch.hpp>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "association/kdtree.hpp"
#include "core_test_util.hpp"
#include "model/normal_equations.hpp"
#include "preparation/pca_normals.hpp"
#include "quality/alignment_quality.hpp"

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
  ppcr::detail::Buffer<ppcr::detail::PlanePoint> planes;
  ppcr::detail::pack_plane_points(target, normals, 0.05, nullptr, &planes);
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

// The plain path: each point's nearest by an unseeded query, counted one by one.
namespace {
struct PlainSums {
  std::size_t matched = 0, near = 0, close = 0;
  double dist_sq = 0.0;
};
PlainSums plain_nearest(const ppcr::detail::KdTree& tree, const PointCloud& points,
                        const Eigen::Isometry3d& T, double radius_sq, double near_sq,
                        double close_sq,
                        const ppcr::detail::Buffer<ppcr::detail::PlanePoint>* planes) {
  PlainSums s;
  for (const Eigen::Vector3d& x : points) {
    const Eigen::Vector3d p = T * x;
    std::uint32_t index;
    double d_sq;
    if (tree.radius_knn(p, 1, radius_sq, &index, &d_sq) != 1) continue;
    ++s.matched;
    s.dist_sq += d_sq;
    if (d_sq > near_sq) continue;
    ++s.near;
    if (planes == nullptr) continue;
    const double along = (*planes)[index].n.dot(p - (*planes)[index].y);
    s.close += along * along <= close_sq && d_sq <= close_sq ? 1 : 0;
  }
  return s;
}
}  // namespace

TEST_CASE("measure_alignment's seeded queries give the unseeded queries' counts, ties included",
          "[alignment_quality]") {
  // Integer lattices: many nearest points at exactly equal distances, so a seeded query that
  // picked another of the tied points would change close_fraction (the tangent-plane test reads
  // the chosen point's normal, and the normals differ: a bumpy surface). And a moved copy.
  PointCloud target, source;
  for (int i = 0; i < 60; ++i) {
    for (int j = 0; j < 60; ++j) target.emplace_back(i, j, (i * 7 + j * 3) % 5 == 0 ? 1.0 : 0.0);
  }
  for (int i = -5; i < 70; ++i) {
    for (int j = -5; j < 70; j += 2) source.emplace_back(i + 0.5, j + 0.5, 0.5);
  }
  ppcr::detail::KdTree target_tree, source_tree;
  REQUIRE(target_tree.build(target).ok());
  REQUIRE(source_tree.build(source).ok());
  std::vector<Eigen::Vector3d> normals;
  ppcr::detail::compute_normals(target, target_tree, 8, nullptr, &normals);
  ppcr::detail::Buffer<ppcr::detail::PlanePoint> planes;
  ppcr::detail::pack_plane_points(target, normals, 0.05, nullptr, &planes);
  const double radius = 3.0, near = 2.0, close = 1.2;
  // The overlap's count of target points with a source point within the radius tries the
  // previous target point's find first, then queries: both must occur.
  std::size_t uncovered = 0;
  for (const Eigen::Isometry3d& T :
       {Eigen::Isometry3d(Eigen::Isometry3d::Identity()),
        core_test::make_pose(Eigen::Vector3d(1, 2, 3), core_test::deg2rad(10),
                             Eigen::Vector3d(0.3, -0.2, 0.1))}) {
    for (int threads : {1, 2}) {
      std::vector<double> scratch;
      const ppcr::detail::AlignmentQuality q = ppcr::detail::measure_alignment(
          target_tree, target, source, &source_tree, T, radius, near, {close, &planes, close},
          core_test::parallel(threads), &scratch);
      const PlainSums s = plain_nearest(target_tree, source, T, radius * radius, near * near,
                                        close * close, &planes);
      const PlainSums back = plain_nearest(source_tree, target, T.inverse(), radius * radius,
                                           near * near, close * close, nullptr);
      REQUIRE(s.matched > 1000);
      REQUIRE(s.matched < source.size());  // some source points lie beyond the radius
      REQUIRE(s.close > 0);
      REQUIRE(s.close < s.near);
      CHECK(q.fitness == static_cast<double>(s.matched) / static_cast<double>(source.size()));
      CHECK(q.inlier_rmse ==
            Approx(std::sqrt(s.dist_sq / static_cast<double>(s.matched))).epsilon(1e-12));
      CHECK(q.close_fraction == static_cast<double>(s.close) / static_cast<double>(s.near));
      CHECK(q.overlap == std::min(q.fitness, static_cast<double>(back.matched) /
                                                 static_cast<double>(target.size())));
      REQUIRE(back.matched > 1000);
      uncovered += target.size() - back.matched;
      // The clouds' roles swapped: the overlap is then the lower fraction of the backward count
      // (the source points with a target point within the radius).
      const ppcr::detail::AlignmentQuality swapped = ppcr::detail::measure_alignment(
          source_tree, source, target, &target_tree, T.inverse(), radius, near,
          {close, nullptr, close}, core_test::parallel(threads), &scratch);
      REQUIRE(q.fitness < static_cast<double>(back.matched) / static_cast<double>(target.size()));
      CHECK(swapped.overlap == static_cast<double>(s.matched) / static_cast<double>(source.size()));
    }
  }
  CHECK(uncovered > 0);
}
