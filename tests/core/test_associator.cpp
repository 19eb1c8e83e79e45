// Tests of detail::Associator, the association step behind one interface: with the neighbour
// cache and with the coarse level (both speed measures) its tables equal a brute-force
// radius-limited kNN of every associated point, and the plain path's, pose after pose.
#include <catch2/catch.hpp>
#include <cstdint>
#include <string>
#include <vector>

#include "association/associator.hpp"
#include "association/kdtree.hpp"
#include "association_reference.hpp"
#include "core_test_util.hpp"

using core_test::Rng;
using ppcr::PointCloud;
using ppcr::detail::Associator;
using ppcr::detail::KdTree;

namespace {

// A sequence of poses converging on the identity, as the outer loop produces.
Eigen::Isometry3d pose(int step) {
  const double f = 1.0 / (1 << step);
  return core_test::make_pose(Eigen::Vector3d(0.3, 1.0, 0.2), core_test::deg2rad(8.0) * f,
                              Eigen::Vector3d(0.05, -0.03, 0.02) * f);
}

struct Fixture {
  PointCloud target, source;
  KdTree tree;
  Fixture() {
    Rng rng(7);
    target = core_test::analytic_scene(rng, 6000);
    source = core_test::analytic_scene(rng, 3000);
    REQUIRE(tree.build(target).ok());
  }
};

// Prepares *a for the fixture's source over its target (with its boundary flags, if any): k = 5.
void prepare(Associator* a, const Fixture& f, double radius, int cache_extra, std::size_t stride,
             const std::uint8_t* flags = nullptr) {
  a->set_target(&f.tree, &f.target, flags);
  a->prepare(Associator::Settings{5, radius, cache_extra, stride, nullptr}, f.source, nullptr);
}

}  // namespace

TEST_CASE("Associator: cached and coarse paths give brute force's tables at every pose",
          "[associator]") {
  Fixture f;
  const double radius = 0.15;
  for (int cache_extra : {0, 4}) {
    for (std::size_t stride : {std::size_t{1}, std::size_t{3}}) {
      INFO("cache_extra " << cache_extra << ", stride " << stride);
      Associator a;
      prepare(&a, f, radius, cache_extra, stride);
      CHECK(a.has_coarse_level() == (stride > 1));
      for (int step = 0; step < 8; ++step) {
        const bool coarse = step < 4;  // the coarse phase, then every point
        const Eigen::Isometry3d T = pose(step);
        a.find(coarse, T);
        INFO("step " << step);
        CHECK(a.coarse() == (coarse && stride > 1));
        CHECK(a.points().size() ==
              (a.coarse() ? (f.source.size() + stride - 1) / stride : f.source.size()));
        CHECK(core_test::table_mismatch(a.table(), a.points(), f.target, T, radius * radius) == "");
      }
    }
  }
}

TEST_CASE("Associator: a coarse level that finds no pair is dropped for every point",
          "[associator]") {
  Fixture f;
  // Only every third source point is far from the target: the coarse level (stride 3, points
  // 0, 3, 6, ...) finds nothing, the others do.
  PointCloud source = f.source;
  for (std::size_t i = 0; i < source.size(); i += 3) source[i] += Eigen::Vector3d(100, 0, 0);
  Associator a;
  a.set_target(&f.tree, &f.target);
  a.prepare(Associator::Settings{5, 0.15, 4, 3, nullptr}, source, nullptr);
  a.find(true, Eigen::Isometry3d::Identity());
  CHECK_FALSE(a.coarse());
  CHECK_FALSE(a.has_coarse_level());
  CHECK(a.table().pairs > 0);
  CHECK(core_test::table_mismatch(a.table(), source, f.target, Eigen::Isometry3d::Identity(),
                                  0.15 * 0.15) == "");
}

TEST_CASE("Associator: once every point is associated, the coarse level is gone for the run",
          "[associator]") {
  // The caller may ask for the coarse level again (the registration asks while the EM scale
  // settles, and it can settle again after a full iteration): the rows were spread over every
  // point, and the table stays every point's. Also when every point came first.
  Fixture f;
  const double radius = 0.15;
  for (int cache_extra : {0, 4}) {
    INFO("cache_extra " << cache_extra);
    Associator a;
    prepare(&a, f, radius, cache_extra, 3);
    a.find(true, pose(0));
    REQUIRE(a.coarse());
    a.find(false, pose(1));
    CHECK_FALSE(a.has_coarse_level());
    for (int step = 2; step < 5; ++step) {
      INFO("step " << step);
      a.find(true, pose(step));
      CHECK_FALSE(a.coarse());
      CHECK(a.points().size() == f.source.size());
      CHECK(core_test::table_mismatch(a.table(), a.points(), f.target, pose(step),
                                      radius * radius) == "");
    }
    // Every point first, the coarse level prepared but never used: the table grows to every
    // point (it held the coarse level's rows only, and the association of every point ran past
    // them), brute force's over the whole source.
    Associator b;
    prepare(&b, f, radius, cache_extra, 2);
    REQUIRE(b.has_coarse_level());
    for (int step = 0; step < 3; ++step) {
      INFO("every point first, step " << step);
      b.find(false, pose(step));
      CHECK_FALSE(b.coarse());
      CHECK(b.points().size() == f.source.size());
      CHECK(b.table().count.size() == f.source.size());
      CHECK(core_test::table_mismatch(b.table(), f.source, f.target, pose(step), radius * radius) ==
            "");
    }
  }
}

TEST_CASE("Associator: a start beyond every target point falls back to the solved pose",
          "[associator]") {
  Fixture f;
  const double radius = 0.15;
  const Eigen::Isometry3d T = pose(5);  // the last solved pose: pairs
  Eigen::Isometry3d away = T;
  away.translation() += Eigen::Vector3d(0, 0, 50);  // an extrapolation far past the target
  for (int cache_extra : {0, 4}) {
    INFO("cache_extra " << cache_extra);
    Associator a;
    prepare(&a, f, radius, cache_extra, 1);
    Eigen::Isometry3d T_start = away;
    CHECK(a.find_from(false, T, &T_start));
    CHECK(T_start.matrix() == T.matrix());
    CHECK(a.table().pairs > 0);
    CHECK(core_test::table_mismatch(a.table(), a.points(), f.target, T, radius * radius) == "");
    // A start with pairs is kept.
    Eigen::Isometry3d near = pose(6);
    CHECK_FALSE(a.find_from(false, T, &near));
    CHECK(near.matrix() == pose(6).matrix());
    CHECK(core_test::table_mismatch(a.table(), a.points(), f.target, near, radius * radius) == "");
    // No fallback from the solved pose itself: no pair there is no pair.
    Eigen::Isometry3d at = away;
    CHECK_FALSE(a.find_from(false, away, &at));
    CHECK(a.table().pairs == 0);
  }
}

TEST_CASE("Associator: rows whose nearest target point is flagged are left out, slots kept",
          "[associator]") {
  // Flags on every fifth target point (the registration's are the target's boundary points,
  // boundary.hpp; the associator only reads them). While asked, a row is left out when its
  // nearest target point (brute force's) is flagged; its slots stay those of brute force (the
  // cache's state), pairs and matched count the rows used. When more than half of the matched
  // rows would go, none does.
  Fixture f;
  const double radius = 0.15;
  std::vector<std::uint8_t> every_fifth(f.target.size()), all(f.target.size(), 1);
  for (std::size_t i = 0; i < f.target.size(); i += 5) every_fifth[i] = 1;
  for (int cache_extra : {0, 4}) {
    for (std::size_t stride : {std::size_t{1}, std::size_t{3}}) {
      INFO("cache_extra " << cache_extra << ", stride " << stride);
      Associator a;
      prepare(&a, f, radius, cache_extra, stride, every_fifth.data());
      for (int step = 0; step < 8; ++step) {
        const bool coarse = step < 4;
        const bool leave_out = step % 3 != 0;  // asked, then not, then asked again
        const Eigen::Isometry3d T = pose(step);
        a.find(coarse, T, leave_out);
        INFO("step " << step);
        const ppcr::detail::AssociationTable& t = a.table();
        // The slots, every row counted: brute force's.
        ppcr::detail::AssociationTable whole = t;
        whole.any_left_out = false;
        whole.recount();
        CHECK(core_test::table_mismatch(whole, a.points(), f.target, T, radius * radius) == "");
        CHECK(t.any_left_out == leave_out);
        std::size_t pairs = 0, matched = 0, left = 0;
        for (std::size_t j = 0; j < t.count.size(); ++j) {
          if (t.count[j] == 0) continue;
          // Brute force's nearest: the closest target point to the moved source point.
          const Eigen::Vector3d p = T * a.points()[j];
          std::size_t nearest = 0;
          for (std::size_t i = 1; i < f.target.size(); ++i) {
            if ((f.target[i] - p).squaredNorm() < (f.target[nearest] - p).squaredNorm()) {
              nearest = i;
            }
          }
          const bool out = leave_out && every_fifth[nearest] != 0;
          CHECK(t.used(j) == !out);
          left += out;
          if (!out) {
            pairs += t.count[j];
            ++matched;
          }
        }
        CHECK(t.pairs == pairs);
        CHECK(t.matched == matched);
        CHECK(t.left_out_rows == left);
        CHECK(t.all_pairs() == whole.pairs);
        if (leave_out) CHECK(left > 0);
      }
      // Every target point flagged: more than half would go, so none does.
      a.set_target(&f.tree, &f.target, all.data());
      a.find(false, pose(8), true);
      CHECK_FALSE(a.table().any_left_out);
      CHECK(a.table().matched > 0);
      CHECK(core_test::table_mismatch(a.table(), a.points(), f.target, pose(8), radius * radius) ==
            "");
    }
  }
}

TEST_CASE("Associator: without a target's flags no row is left out and none has room for it",
          "[associator]") {
  // The rule reads the target's boundary flags: a target without them (reject_boundary off)
  // leaves every row in, asked or not, and the table holds no per-row flags (1 B per source point
  // otherwise); with flags, prepare() makes room for every row, so finding allocates nothing.
  Fixture f;
  const double radius = 0.15;
  Associator a;
  prepare(&a, f, radius, 4, 2);
  for (int step = 0; step < 3; ++step) {
    a.find(step == 0, pose(step), true);
    CHECK_FALSE(a.table().any_left_out);
    CHECK(a.table().left_out.capacity() == 0u);
    CHECK(a.table().left_out_rows == 0u);
    CHECK(core_test::table_mismatch(a.table(), a.points(), f.target, pose(step), radius * radius) ==
          "");
  }
  std::vector<std::uint8_t> every_fifth(f.target.size());
  for (std::size_t i = 0; i < f.target.size(); i += 5) every_fifth[i] = 1;
  prepare(&a, f, radius, 4, 2, every_fifth.data());
  CHECK(a.table().left_out.capacity() >= f.source.size());
  a.find(false, pose(1), true);
  CHECK(a.table().any_left_out);
  CHECK(a.table().left_out.size() == f.source.size());
}

TEST_CASE("Associator: a row's flag does not depend on how ties at its nearest are ordered",
          "[associator]") {
  // Exact ties: a unit lattice in the plane z = 0 as the target and the cells' centres as the
  // source, so that each source point has 4 nearest target points at the same distance (0.5 in
  // squares, exact in doubles). The k-d tree's query lists tied points in its visit order; the
  // table lists them by index on every path (the cache's and the query's), so a row is left out
  // when the lowest-indexed of its tied nearest points is flagged (brute force's rule here), with
  // the cache on and off.
  PointCloud target, source;
  const int n = 24;
  for (int y = 0; y < n; ++y) {
    for (int x = 0; x < n; ++x) target.emplace_back(x, y, 0.0);
  }
  for (int y = 0; y + 1 < n; ++y) {
    for (int x = 0; x + 1 < n; ++x) source.emplace_back(x + 0.5, y + 0.5, 0.0);
  }
  KdTree tree;
  REQUIRE(tree.build(target).ok());
  // Flags on points with x + 2 y divisible by 3: of each cell's four corners one or two are
  // flagged, and which one is lowest-indexed decides.
  std::vector<std::uint8_t> flags(target.size());
  for (std::size_t i = 0; i < target.size(); ++i) flags[i] = (i % n + 2 * (i / n)) % 3 == 0;
  const Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  std::vector<std::uint8_t> expected(source.size());
  std::size_t expected_left = 0;
  for (std::size_t j = 0; j < source.size(); ++j) {
    double best = 1e300;
    std::size_t nearest = 0;
    for (std::size_t i = 0; i < target.size(); ++i) {
      const double d = (target[i] - source[j]).squaredNorm();
      if (d < best) {  // the first (lowest index) of equals
        best = d;
        nearest = i;
      }
    }
    expected[j] = flags[nearest];
    expected_left += flags[nearest];
  }
  REQUIRE(expected_left > 0);
  REQUIRE(2 * expected_left <= source.size());
  for (int cache_extra : {0, 4}) {
    INFO("cache_extra " << cache_extra);
    Associator a;
    a.set_target(&tree, &target, flags.data());
    a.prepare(Associator::Settings{6, 1.2, cache_extra, 1, nullptr}, source, nullptr);
    a.find(false, T, true);
    const ppcr::detail::AssociationTable& t = a.table();
    REQUIRE(t.any_left_out);
    std::size_t mismatches = 0;
    for (std::size_t j = 0; j < source.size(); ++j) mismatches += t.left_out[j] != expected[j];
    CHECK(mismatches == 0);
    CHECK(t.left_out_rows == expected_left);
  }
}
