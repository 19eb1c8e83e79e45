// Tests of detail::compute_normals (PCA normals of a cloud, the target's or the source's, for the
// plane error model) against the exact normals of analytic surfaces, and of its spreads and
// surface_noise against brute force.
#include <Eigen/Eigenvalues>
#include <algorithm>
#include <catch2/catch.hpp>
#include <cmath>
#include <cstdint>
#include <limits>
#include <utility>
#include <vector>

#include "association/kdtree.hpp"
#include "core_test_util.hpp"
#include "preparation/pca_normals.hpp"

using core_test::Rng;
using ppcr::PointCloud;

namespace {

std::vector<Eigen::Vector3d> normals_of(const PointCloud& cloud, int k, int threads) {
  ppcr::detail::KdTree tree;
  REQUIRE(tree.build(cloud).ok());
  std::vector<Eigen::Vector3d> normals;
  ppcr::detail::compute_normals(cloud, tree, k, core_test::parallel(threads), &normals);
  REQUIRE(normals.size() == cloud.size());
  return normals;
}

}  // namespace

TEST_CASE("normals of a plane are its normal, up to sign", "[target_normals]") {
  Rng rng(131);
  const Eigen::Vector3d n = core_test::random_unit_vector(rng);
  const Eigen::Vector3d u = n.unitOrthogonal(), v = n.cross(u);
  const Eigen::Vector3d origin(3.0, -2.0, 10.0);
  PointCloud plane;
  for (int i = 0; i < 3000; ++i) {
    plane.push_back(origin + core_test::uniform(rng, -1, 1) * u +
                    core_test::uniform(rng, -1, 1) * v);
  }
  for (int k : {5, 20, 64}) {
    const std::vector<Eigen::Vector3d> normals = normals_of(plane, k, 1);
    double worst = 0.0;
    for (const Eigen::Vector3d& m : normals) {
      CHECK(std::abs(m.norm() - 1.0) < 1e-12);
      worst = std::max(worst, 1.0 - std::abs(m.dot(n)));
    }
    INFO("k " << k << ": worst 1 - |cos| = " << worst);
    CHECK(worst < 1e-10);
  }
}

TEST_CASE("normals of a sphere are nearly radial", "[target_normals]") {
  Rng rng(132);
  const Eigen::Vector3d c(0.5, 0.2, -0.1);
  PointCloud sphere;
  for (int i = 0; i < 5000; ++i) sphere.push_back(c + core_test::random_unit_vector(rng));
  const std::vector<Eigen::Vector3d> normals = normals_of(sphere, 20, 1);
  double worst_deg = 0.0;
  for (std::size_t i = 0; i < sphere.size(); ++i) {
    const double cos_a = std::abs(normals[i].dot((sphere[i] - c).normalized()));
    worst_deg = std::max(worst_deg, std::acos(std::min(1.0, cos_a)) * 180.0 / core_test::kPi);
  }
  INFO("worst angle to the radial direction " << worst_deg << " deg");
  // Neighbourhoods of 20 points span ~0.13 rad: the PCA normal is within a few degrees.
  CHECK(worst_deg < 10.0);
}

TEST_CASE("fewer than 5 points: zero normals", "[target_normals]") {
  const PointCloud four = {Eigen::Vector3d(0, 0, 0), Eigen::Vector3d(1, 0, 0),
                           Eigen::Vector3d(0, 1, 0), Eigen::Vector3d(1, 1, 0)};
  for (const Eigen::Vector3d& m : normals_of(four, 20, 1)) CHECK(m == Eigen::Vector3d::Zero());
}

TEST_CASE("collinear or identical points: zero normals (no surface to fit)", "[target_normals]") {
  Rng rng(134);
  const Eigen::Vector3d dir = core_test::random_unit_vector(rng);
  PointCloud line, same(50, Eigen::Vector3d(1.0, -2.0, 0.5));
  for (int i = 0; i < 200; ++i) line.push_back(core_test::uniform(rng, -1, 1) * dir);
  for (const Eigen::Vector3d& m : normals_of(line, 20, 1)) CHECK(m == Eigen::Vector3d::Zero());
  for (const Eigen::Vector3d& m : normals_of(same, 20, 1)) CHECK(m == Eigen::Vector3d::Zero());
  // A thin but two-dimensional strip (1e-3 wide) still has its normal.
  PointCloud strip;
  for (int i = 0; i < 400; ++i) {
    strip.emplace_back(core_test::uniform(rng, -1, 1), core_test::uniform(rng, -1e-3, 1e-3), 0.0);
  }
  for (const Eigen::Vector3d& m : normals_of(strip, 20, 1)) CHECK(std::abs(m.z()) > 1.0 - 1e-9);
}

TEST_CASE("normals and spreads are identical with 1 and 2 threads", "[target_normals]") {
  Rng rng(133);
  const PointCloud scene = core_test::analytic_scene(rng, 6000);
  CHECK(normals_of(scene, 20, 1) == normals_of(scene, 20, 2));
  ppcr::detail::KdTree tree;
  REQUIRE(tree.build(scene).ok());
  std::vector<Eigen::Vector3d> normals;
  ppcr::detail::Buffer<double> spread[2];
  for (int threads : {1, 2}) {
    ppcr::detail::compute_normals(scene, tree, 20, core_test::parallel(threads), &normals,
                                  &spread[threads - 1]);
  }
  CHECK(spread[0] == spread[1]);
}

TEST_CASE(
    "spread and reach: the RMS distance of each fit's points from their plane and the farthest "
    "one's distance, brute force",
    "[target_normals]") {
  // A plane with Gaussian noise of std 0.01 along its normal: the spread of every point against an
  // independent reference (brute-force k nearest, Eigen's iterative eigensolver), and the surface
  // noise (their upper median) near the noise's std.
  Rng rng(135);
  const Eigen::Vector3d n = core_test::random_unit_vector(rng);
  const Eigen::Vector3d u = n.unitOrthogonal(), v = n.cross(u);
  PointCloud plane;
  for (int i = 0; i < 2000; ++i) {
    plane.push_back(core_test::uniform(rng, -1, 1) * u + core_test::uniform(rng, -1, 1) * v +
                    core_test::gaussian(rng, 0.01) * n);
  }
  const int k = 20;
  ppcr::detail::KdTree tree;
  REQUIRE(tree.build(plane).ok());
  std::vector<Eigen::Vector3d> normals;
  ppcr::detail::Buffer<double> spread, reach;
  ppcr::detail::compute_normals(plane, tree, k, core_test::parallel(2), &normals, &spread, &reach);
  REQUIRE(spread.size() == plane.size());
  REQUIRE(reach.size() == plane.size());
  for (std::size_t i = 0; i < plane.size(); ++i) {
    const std::vector<std::pair<double, std::size_t>> by_distance =
        core_test::brute_force_nearest(plane, i, k);
    Eigen::MatrixXd X(k, 3);
    for (int m = 0; m < k; ++m) X.row(m) = plane[by_distance[m].second].transpose();
    const Eigen::MatrixXd centred = X.rowwise() - X.colwise().mean();
    const Eigen::Matrix3d C = centred.transpose() * centred / k;
    const double lambda_min = Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(C).eigenvalues()[0];
    CHECK(spread[i] == Approx(std::sqrt(lambda_min)).epsilon(1e-6));
    CHECK(reach[i] == std::sqrt(by_distance[static_cast<std::size_t>(k - 1)].first));
  }
  const double noise_level = ppcr::detail::upper_median(&spread);
  // The smallest eigenvalue of 20 points' scatter underestimates the noise's variance (the fitted
  // plane follows the sample): about (k - 3) / k of it.
  INFO("surface noise " << noise_level);
  CHECK(noise_level > 0.007);
  CHECK(noise_level < 0.011);
}

TEST_CASE("upper_median: the upper median of the values >= 0 (spreads of points with a normal)",
          "[target_normals]") {
  auto upper_median = [](const std::vector<double>& values) {  // in place on a copy
    ppcr::detail::Buffer<double> copy(values.begin(), values.end());
    return ppcr::detail::upper_median(&copy);
  };
  CHECK(upper_median({}) == 0.0);
  CHECK(upper_median({-1.0, -1.0}) == 0.0);
  CHECK(upper_median({0.3, -1.0, 0.1, 0.2}) == 0.2);
  CHECK(upper_median({0.4, 0.1, -1.0, 0.3, 0.2}) == 0.3);
  // Points without a normal report -1 and are left out.
  const PointCloud four = {Eigen::Vector3d(0, 0, 0), Eigen::Vector3d(1, 0, 0),
                           Eigen::Vector3d(0, 1, 0), Eigen::Vector3d(1, 1, 0)};
  ppcr::detail::KdTree tree;
  REQUIRE(tree.build(four).ok());
  std::vector<Eigen::Vector3d> normals;
  ppcr::detail::Buffer<double> spread;
  ppcr::detail::compute_normals(four, tree, 20, nullptr, &normals, &spread);
  CHECK(spread == ppcr::detail::Buffer<double>(4, -1.0));
}

TEST_CASE("seeded queries: normals and spreads equal to the bit fits of unbounded queries",
          "[target_normals]") {
  // compute_normals bounds each query by its previous point's neighbours (pca_normals.hpp);
  // the reference fits every point from an unbounded query. A lattice makes exact ties at the
  // k-th distance common (the tie order must survive the seed), the scene has curved surfaces
  // and gaps, and k = 64 reaches past a leaf's points.
  Rng rng(136);
  PointCloud lattice;
  for (int x = 0; x < 16; ++x) {
    for (int y = 0; y < 16; ++y) {
      for (int z = 0; z < 3; ++z) lattice.emplace_back(x, y, 0.5 * z * z);  // exact: ties are exact
    }
  }
  const PointCloud scene = core_test::analytic_scene(rng, 4000);
  for (const PointCloud* cloud : std::vector<const PointCloud*>{&lattice, &scene}) {
    ppcr::detail::KdTree tree;
    REQUIRE(tree.build(*cloud).ok());
    for (int k : {5, 20, 64}) {
      for (int threads : {1, 2}) {
        std::vector<Eigen::Vector3d> normals;
        ppcr::detail::Buffer<double> spread;
        ppcr::detail::compute_normals(*cloud, tree, k, core_test::parallel(threads), &normals,
                                      &spread);
        std::size_t mismatches = 0, with_normal = 0;
        std::uint32_t idx[64];
        double d2[64];
        for (std::size_t i = 0; i < cloud->size(); ++i) {
          const int n =
              tree.radius_knn((*cloud)[i], k, std::numeric_limits<double>::max(), idx, d2);
          const ppcr::detail::NormalFit fit = ppcr::detail::fit_normal(*cloud, idx, n);
          mismatches += !(normals[i] == fit.normal && spread[i] == fit.spread);
          with_normal += fit.spread >= 0.0;
        }
        INFO("cloud of " << cloud->size() << ", k " << k << ", threads " << threads);
        CHECK(mismatches == 0);
        CHECK(with_normal > cloud->size() / 2);
      }
      // The claim itself, query by query: bounded by the previous point's (in leaf order) k
      // neighbours, a query finds the unbounded query's k neighbours in the same order, ties
      // included, with no repeat. The bound is compute_normals' (seed_bound_sq), the query the raw
      // radius_knn: the fits above would pass with a too tight bound, which seeded_radius_knn's
      // repeat mends. That repeat is checked apart: a seed of 0 (too tight for k >= 2 distinct
      // points) must be repeated and give the unbounded list.
      const auto& order = tree.leaf_order();
      const double unbounded = std::numeric_limits<double>::max();
      std::uint32_t prev[64], idx[64], ref[64];
      double d2[64];
      std::size_t seeded = 0, differ = 0, ties = 0, not_mended = 0;
      int prev_found = 0;
      for (std::uint32_t i : order) {
        const Eigen::Vector3d& q = (*cloud)[i];
        const int n = tree.radius_knn(q, k, unbounded, ref, d2);
        for (int m = 1; m < n; ++m) ties += d2[m] == d2[m - 1];
        if (prev_found == k) {
          const double bound_sq = ppcr::detail::seed_bound_sq(q, *cloud, prev, k);
          const int found = tree.radius_knn(q, k, bound_sq, idx, d2);
          ++seeded;
          differ += !(found == n && std::equal(idx, idx + n, ref));
          const ppcr::detail::SeededKnn mended =
              ppcr::detail::seeded_radius_knn(tree, q, k, 0.0, unbounded, idx, d2);
          not_mended += !(mended.outcome == ppcr::detail::SeedOutcome::kRepeated &&
                          mended.found == n && std::equal(idx, idx + n, ref));
        }
        std::copy(ref, ref + n, prev);
        prev_found = n;
      }
      INFO("cloud of " << cloud->size() << ", k " << k);
      CHECK(seeded > cloud->size() / 2);
      CHECK(differ == 0);
      CHECK(not_mended == 0);
      if (cloud == &lattice) CHECK(ties > 0);  // exact ties reached the seeded queries
    }
  }
}
