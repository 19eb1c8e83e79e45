// Tests of detail::associate against a brute-force radius-limited kNN of every transformed source
// point, and its independence of the thread count.
#include <algorithm>
#include <catch2/catch.hpp>
#include <string>
#include <vector>

#include "association/association_table.hpp"
#include "association/kdtree.hpp"
#include "association_reference.hpp"
#include "core_test_util.hpp"

using core_test::Rng;
using core_test::table_mismatch;
using ppcr::PointCloud;
using ppcr::detail::AssociationTable;
using ppcr::detail::KdTree;

namespace {

// The first count[j] slots of two tables are identical (the rest is unspecified).
bool same_tables(const AssociationTable& a, const AssociationTable& b) {
  if (a.k != b.k || a.count != b.count || a.pairs != b.pairs || a.matched != b.matched) {
    return false;
  }
  const std::size_t k = static_cast<std::size_t>(a.k);
  for (std::size_t j = 0; j < a.count.size(); ++j) {
    for (std::size_t m = 0; m < a.count[j]; ++m) {
      if (a.index[j * k + m] != b.index[j * k + m]) return false;
    }
  }
  return true;
}

}  // namespace

TEST_CASE("associate matches brute force with a transform applied", "[association]") {
  Rng rng(41);
  const PointCloud target = core_test::uniform_cloud(rng, 3000, -1.0, 1.0);
  const PointCloud source_true = core_test::uniform_cloud(rng, 1500, -1.2, 1.2);
  const Eigen::Isometry3d T = core_test::make_pose(
      Eigen::Vector3d(0.2, -0.3, 1.0), core_test::deg2rad(20.0), Eigen::Vector3d(0.05, -0.1, 0.02));
  // Source in its own frame: T maps it back onto source_true.
  const PointCloud source = core_test::transformed(source_true, T.inverse());
  KdTree tree;
  REQUIRE(tree.build(target).ok());
  for (int k : {1, 7, 20}) {
    for (double radius : {0.05, 0.15, 0.4}) {
      for (int threads : {1, 2}) {
        AssociationTable table;
        table.resize(source.size(), k);
        ppcr::detail::associate(tree, source, T, radius * radius, core_test::parallel(threads),
                                &table);
        INFO("k " << k << " radius " << radius << " threads " << threads);
        CHECK(table_mismatch(table, source, target, T, radius * radius) == "");
        CHECK(table.pairs > 0);
        CHECK(table.matched <= source.size());
        CHECK(table.pairs <= table.matched * static_cast<std::size_t>(k));
      }
    }
  }
}

TEST_CASE("associate: the table can be reused across poses", "[association]") {
  Rng rng(42);
  const PointCloud target = core_test::uniform_cloud(rng, 2000, -1.0, 1.0);
  const PointCloud source = core_test::uniform_cloud(rng, 800, -1.0, 1.0);
  KdTree tree;
  REQUIRE(tree.build(target).ok());
  AssociationTable reused;
  reused.resize(source.size(), 10);
  for (int i = 0; i < 5; ++i) {
    const Eigen::Isometry3d T =
        core_test::make_pose(core_test::random_unit_vector(rng), core_test::uniform(rng, 0.0, 0.5),
                             0.3 * core_test::random_unit_vector(rng));
    ppcr::detail::associate(tree, source, T, 0.04, nullptr, &reused);
    AssociationTable fresh;
    fresh.resize(source.size(), 10);
    ppcr::detail::associate(tree, source, T, 0.04, nullptr, &fresh);
    CHECK(same_tables(reused, fresh));
    CHECK(table_mismatch(reused, source, target, T, 0.04) == "");
  }
}

TEST_CASE("associate: no target point in range gives zero pairs and zero matched",
          "[association]") {
  Rng rng(43);
  const PointCloud target = core_test::uniform_cloud(rng, 500, -1.0, 1.0);
  const PointCloud source = core_test::uniform_cloud(rng, 300, -1.0, 1.0);
  KdTree tree;
  REQUIRE(tree.build(target).ok());
  AssociationTable table;
  table.resize(source.size(), 5);
  Eigen::Isometry3d far = Eigen::Isometry3d::Identity();
  far.translation() = Eigen::Vector3d(10.0, 0.0, 0.0);
  ppcr::detail::associate(tree, source, far, 1.0, core_test::parallel(2), &table);
  CHECK(table.pairs == 0u);
  CHECK(table.matched == 0u);
  CHECK(
      std::all_of(table.count.begin(), table.count.end(), [](std::uint16_t c) { return c == 0; }));
}

TEST_CASE("associate: bit-identical tables with 1 and 2 threads", "[association]") {
  Rng rng(44);
  const PointCloud target = core_test::uniform_cloud(rng, 20000, -1.0, 1.0);
  const PointCloud source = core_test::uniform_cloud(rng, 15000, -1.1, 1.1);
  KdTree tree;
  REQUIRE(tree.build(target).ok());
  const Eigen::Isometry3d T =
      core_test::make_pose(Eigen::Vector3d(1, 1, 0), 0.2, Eigen::Vector3d(0.01, 0.02, 0.03));
  for (int k : {1, 10}) {
    AssociationTable one, two;
    one.resize(source.size(), k);
    two.resize(source.size(), k);
    ppcr::detail::associate(tree, source, T, 0.01, nullptr, &one);
    ppcr::detail::associate(tree, source, T, 0.01, core_test::parallel(2), &two);
    CHECK(one.pairs > 0u);
    CHECK(same_tables(one, two));
  }
}

TEST_CASE("associate: a source point on a target point gets it first at distance 0",
          "[association]") {
  Rng rng(45);
  const PointCloud target = core_test::uniform_cloud(rng, 1000, -1.0, 1.0);
  // Source = target in a frame rotated by T^-1: moving it by T puts it on the target (to
  // rounding).
  const Eigen::Isometry3d T =
      core_test::make_pose(Eigen::Vector3d(0, 0, 1), 0.7, Eigen::Vector3d(0.5, 0, 0));
  const PointCloud source = core_test::transformed(target, T.inverse());
  KdTree tree;
  REQUIRE(tree.build(target).ok());
  AssociationTable table;
  table.resize(source.size(), 3);
  ppcr::detail::associate(tree, source, T, 0.01, nullptr, &table);
  for (std::size_t j = 0; j < source.size(); ++j) {
    REQUIRE(table.count[j] >= 1);
    CHECK(table.index[j * 3] == j);
  }
  CHECK(table_mismatch(table, source, target, T, 0.01) == "");  // the rest of each row
  CHECK(table.matched == source.size());
}
