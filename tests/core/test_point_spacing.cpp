// median_spacing against brute force: over every point, and over an even sample of them; read
// from the normal fits' neighbours, equal to its own queries.
#include <algorithm>
#include <catch2/catch.hpp>
#include <cmath>
#include <random>
#include <vector>

#include "association/kdtree.hpp"
#include "core_test_util.hpp"
#include "preparation/pca_normals.hpp"
#include "preparation/point_spacing.hpp"

using core_test::brute_force_spacing;
using ppcr::PointCloud;

TEST_CASE("median_spacing: brute force, all points and a sample, duplicates skipped",
          "[point_spacing]") {
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  PointCloud points;
  for (int i = 0; i < 3000; ++i) points.emplace_back(u(rng), u(rng), 0.1 * u(rng));
  for (int i = 0; i < 300; ++i) points.push_back(points[static_cast<std::size_t>(7 * i)]);
  ppcr::detail::KdTree tree;
  REQUIRE(tree.build(points).ok());
  std::vector<double> scratch;
  CHECK(ppcr::detail::median_spacing(points, tree, 4096, nullptr, &scratch) ==
        Approx(brute_force_spacing(points, 1)).epsilon(1e-12));
  // 3300 points, 1000 samples asked: every floor(3300 / 1000) = 3rd point.
  CHECK(ppcr::detail::median_spacing(points, tree, 1000, nullptr, &scratch) ==
        Approx(brute_force_spacing(points, 3)).epsilon(1e-12));
  // A cloud of one repeated point has no spacing.
  const PointCloud same(10, Eigen::Vector3d(1, 2, 3));
  REQUIRE(tree.build(same).ok());
  CHECK(ppcr::detail::median_spacing(same, tree, 4096, nullptr, &scratch) == 0.0);
}

TEST_CASE("median_spacing from the normal fits' neighbours equals its own queries, to the bit",
          "[point_spacing]") {
  // Clouds with runs of duplicates (up to 17 copies: past the 14 a query skips) and sizes on both
  // sides of the sampling (2 x 4096 points: about 7700 every point, 23600 every 5th), read with
  // fits of 16 and of 20 neighbours.
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (std::size_t n : {500u, 6500u, 20000u}) {
    PointCloud points;
    for (std::size_t i = 0; i < n; ++i) points.emplace_back(u(rng), u(rng), 0.05 * u(rng));
    for (std::size_t i = 0; i < n / 50; ++i) {
      const std::size_t copies = 1 + i % 17;
      for (std::size_t c = 0; c < copies; ++c) points.push_back(points[3 * i]);
    }
    ppcr::detail::KdTree tree;
    REQUIRE(tree.build(points).ok());
    std::vector<double> scratch;
    const double queried = ppcr::detail::median_spacing(points, tree, 4096, nullptr, &scratch);
    REQUIRE(queried > 0.0);
    // Fits of fewer neighbours keep none (nearest_sq left empty): the spacing is queried.
    for (int k : {8, ppcr::detail::kSpacingNeighbours, 20}) {
      INFO(points.size() << " points, fits of " << k);
      std::vector<Eigen::Vector3d> normals;
      ppcr::detail::Buffer<double> nearest_sq(3, 1.0);
      ppcr::detail::compute_normals(points, tree, k, core_test::parallel(2), &normals, nullptr,
                                    nullptr, &nearest_sq);
      CHECK(nearest_sq.size() == (k < ppcr::detail::kSpacingNeighbours ? 0 : points.size()));
      CHECK(ppcr::detail::median_spacing(points, tree, 4096, &nearest_sq, &scratch) == queried);
    }
  }
}
