// Tests of detail::associate_cached: along sequences of poses (small and large motions, points
// near the edge of the data, points with no neighbour), the table equals a brute-force
// radius-limited kNN of every transformed source point, it does not depend on the thread count,
// and the k-d tree is queried only where the candidate lists cannot prove the answer.
#include <algorithm>
#include <catch2/catch.hpp>
#include <cmath>
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include "association/association_table.hpp"
#include "association/kdtree.hpp"
#include "association/neighbour_cache.hpp"
#include "association/spatial_order.hpp"
#include "association_reference.hpp"
#include "common/parallel.hpp"
#include "core_test_util.hpp"
#include "ppcr/registration.hpp"

using core_test::Rng;
using core_test::table_mismatch;
using ppcr::PointCloud;
using ppcr::detail::AssociationTable;
using ppcr::detail::KdTree;
using ppcr::detail::NeighbourCache;

namespace {

// A 10 x 10 x 10 integer lattice in shuffled order (index order unlike the k-d tree's order:
// many exactly tied distances, exact in double), its tree, and a source at the centres of its
// inner cells (2.5 .. 6.5 on each axis, far from its edges).
struct Lattice {
  PointCloud target, source;
  KdTree tree;
  explicit Lattice(std::uint32_t seed) {
    Rng rng(seed);
    for (int x = 0; x < 10; ++x) {
      for (int y = 0; y < 10; ++y) {
        for (int z = 0; z < 10; ++z) target.emplace_back(x, y, z);
      }
    }
    std::shuffle(target.begin(), target.end(), rng);
    for (int x = 2; x < 7; ++x) {
      for (int y = 2; y < 7; ++y) {
        for (int z = 2; z < 7; ++z) source.emplace_back(x + 0.5, y + 0.5, z + 0.5);
      }
    }
    built = tree.build(target).ok();
  }
  /// associate_cached on this lattice at one thread.
  void associate(const Eigen::Isometry3d& T, double radius, NeighbourCache* cache,
                 AssociationTable* table) const {
    ppcr::detail::associate_cached(tree, target, source, T, radius, nullptr, cache, table);
  }
  bool built = false;
};

// A sequence of poses: a large jump, a slow drift (each step a fraction of the neighbour
// spacing), a jump back, and a repeated pose.
std::vector<Eigen::Isometry3d> pose_sequence(Rng& rng) {
  std::vector<Eigen::Isometry3d> poses;
  Eigen::Isometry3d T =
      core_test::make_pose(Eigen::Vector3d(0, 0, 1), 0.3, Eigen::Vector3d(0.1, 0.0, -0.05));
  poses.push_back(T);
  for (int i = 0; i < 12; ++i) {
    T = core_test::make_pose(core_test::random_unit_vector(rng), 0.004,
                             0.004 * core_test::random_unit_vector(rng)) *
        T;
    poses.push_back(T);
  }
  poses.push_back(poses.back());
  poses.push_back(
      core_test::make_pose(Eigen::Vector3d(1, 0, 0), -0.5, Eigen::Vector3d(-0.3, 0.2, 0.1)));
  poses.push_back(poses.front());
  return poses;
}

// A target uniform in [-1, 1]^3, a source uniform in [-w, w]^3, the target's tree and a
// pose_sequence, all drawn from one seed.
struct Scene {
  Scene(std::uint32_t seed, std::size_t target_points, std::size_t source_points, double w)
      : rng(seed),
        target(core_test::uniform_cloud(rng, target_points, -1.0, 1.0)),
        source(core_test::uniform_cloud(rng, source_points, -w, w)) {
    built = tree.build(target).ok();
    poses = pose_sequence(rng);
  }
  Rng rng;
  PointCloud target, source;
  KdTree tree;
  bool built = false;
  std::vector<Eigen::Isometry3d> poses;
};

// The scene's source in Z-order, as the registration passes it.
PointCloud z_ordered(const PointCloud& cloud) {
  PointCloud sorted = cloud;
  ppcr::detail::SpatialSortScratch sort_scratch;
  ppcr::detail::spatial_sort(&sorted, nullptr, &sort_scratch);
  return sorted;
}

// A translation by x along the x axis.
Eigen::Isometry3d at(double x) {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.translation() = Eigen::Vector3d(x, 0, 0);
  return T;
}

// The face-centre scene of the seeded-query tests: the lattice, k = 13, capacity 17, radius 2.5.
// At a face centre 4 + 8 target points lie at squared distances 0.5 and 1.5 and 8 tie at 2.5, so
// a query of 17 cuts the tie.
struct FaceCentres {
  static constexpr int k = 13, capacity = 17;
  static constexpr double radius = 2.5;
  Lattice lattice;
  explicit FaceCentres(std::uint32_t seed) : lattice(seed) { REQUIRE(lattice.built); }
  // Resizes a cache and a table for n source points.
  void resize(std::size_t n, NeighbourCache* cache, AssociationTable* table) const {
    cache->resize(n, capacity);
    table->resize(n, k);
  }
  // How many of the cache's lists for `source` at T differ (indices in order, count, bound) from
  // a direct, unbounded query of `capacity` within r_c, whose last distance must be the tie.
  int lists_differing_from_queries(const PointCloud& source, const NeighbourCache& cache,
                                   const Eigen::Isometry3d& T) const {
    const double candidate_radius = NeighbourCache::kRadiusMargin * radius;
    std::uint32_t idx[NeighbourCache::kMaxCapacity];
    double d2[NeighbourCache::kMaxCapacity];
    int differ = 0;
    for (std::size_t j = 0; j < source.size(); ++j) {
      const int found = lattice.tree.radius_knn(T * source[j], capacity,
                                                candidate_radius * candidate_radius, idx, d2);
      REQUIRE(found == capacity);
      REQUIRE(d2[capacity - 1] == 2.5);  // the tie is cut by the query
      const std::uint32_t* listed = &cache.index[j * static_cast<std::size_t>(capacity)];
      differ += cache.count[j] != found || cache.bound[j] != std::sqrt(d2[capacity - 1]) ||
                !std::equal(idx, idx + found, listed);
    }
    return differ;
  }
};

// Rows of two tables of the same shape whose counts or held entries differ. Row by row: a
// table's slots past a row's count are not part of the answer (and are never written: Buffer).
std::size_t rows_differing(const AssociationTable& a, const AssociationTable& b) {
  REQUIRE(a.count.size() == b.count.size());
  REQUIRE(a.k == b.k);
  const std::size_t k = static_cast<std::size_t>(a.k);
  std::size_t differing = 0;
  for (std::size_t j = 0; j < a.count.size(); ++j) {
    const std::size_t begin = j * k, end = begin + a.count[j];
    differing += a.count[j] != b.count[j] ||
                 !std::equal(a.index.data() + begin, a.index.data() + end, b.index.data() + begin);
  }
  return differing;
}

}  // namespace

TEST_CASE("associate_cached equals brute force along a sequence of poses", "[association]") {
  // The source wider than the target: points near and beyond its edge have short or empty lists.
  // In Z-order, as the registration passes it: consecutive points are neighbours, so a point
  // can seed its query from the previous point's list.
  const Scene scene(51, 3000, 1200, 1.3);
  REQUIRE(scene.built);
  const PointCloud& target = scene.target;
  const PointCloud source = z_ordered(scene.source);
  const KdTree& tree = scene.tree;
  const std::vector<Eigen::Isometry3d>& poses = scene.poses;
  std::size_t later_neighbour_seeded = 0;  // neighbour-seeded queries after each first call
  for (int k : {1, 6, 15}) {
    for (int extra : {1, 8}) {
      for (double radius : {0.08, 0.2}) {
        NeighbourCache cache;
        cache.resize(source.size(), k + extra);
        AssociationTable table;
        table.resize(source.size(), k);
        std::size_t drift_resorted = 0;
        for (std::size_t i = 0; i < poses.size(); ++i) {
          ppcr::detail::associate_cached(tree, target, source, poses[i], radius, nullptr, &cache,
                                         &table);
          INFO("k " << k << " extra " << extra << " radius " << radius << " pose " << i);
          REQUIRE(table_mismatch(table, source, target, poses[i], radius * radius) == "");
          if (i == 0) CHECK(cache.last_queries == source.size());  // an empty cache queries all
          if (i >= 1 && i <= 12) drift_resorted += cache.last_resorted;
          if (i >= 1) later_neighbour_seeded += cache.last_neighbour_seeded;
        }
        // Some of the drift's moving rows were refreshed by the set certificate: the brute-force
        // check above covered that path.
        CHECK(drift_resorted > source.size());
      }
    }
  }
  // Points without a list of their own long enough, seeded by the previous point's (the jumps
  // of the sequence): the brute-force check covered them too.
  CHECK(later_neighbour_seeded > 0u);
}

TEST_CASE("associate_cached: the set certificate holds inside rho and lets go outside it",
          "[association]") {
  // Two target points 1 apart on the x axis and one source point moved along it, so that rho is
  // known in closed form (neighbour_cache.hpp): a move just inside it keeps the set (re-sorted),
  // a move just past it changes the set (re-ranked); a rho twice too large would keep a stale row.
  const PointCloud target = {Eigen::Vector3d(0, 0, 0), Eigen::Vector3d(1, 0, 0)};
  const PointCloud source = {Eigen::Vector3d(0, 0, 0)};
  KdTree tree;
  REQUIRE(tree.build(target).ok());
  struct Case {
    const char* name;
    int k;
    double radius, start, inside, outside;
    std::uint16_t count_after;  // the row's size once the point moved past rho
  };
  // k = 1 within a large radius: separation, rho = (0.6 - 0.4) / 2 = 0.1; past it the other
  // point is the nearest. k = 2 within 0.6, one neighbour (the other, 0.7 away, is a candidate
  // within 1.25 x 0.6): entry, rho = min(0.6 - 0.3, 0.7 - 0.6) = 0.1; past it both are in range.
  for (const Case& c : {Case{"separation", 1, 10.0, 0.4, 0.099, 0.11, 1},
                        Case{"entry", 2, 0.6, 0.3, 0.099, 0.11, 2}}) {
    INFO(c.name);
    NeighbourCache cache;
    cache.resize(1, c.k + 1);
    AssociationTable table;
    table.resize(1, c.k);
    const double r_sq = c.radius * c.radius;
    ppcr::detail::associate_cached(tree, target, source, at(c.start), c.radius, nullptr, &cache,
                                   &table);
    REQUIRE(table_mismatch(table, source, target, at(c.start), r_sq) == "");
    REQUIRE(table.count[0] == 1);
    CHECK(table.index[0] == 0u);
    ppcr::detail::associate_cached(tree, target, source, at(c.start + c.inside), c.radius, nullptr,
                                   &cache, &table);
    CHECK(cache.last_resorted == 1u);
    CHECK(table_mismatch(table, source, target, at(c.start + c.inside), r_sq) == "");
    ppcr::detail::associate_cached(tree, target, source, at(c.start + c.outside), c.radius, nullptr,
                                   &cache, &table);
    CHECK(cache.last_resorted == 0u);
    CHECK(table_mismatch(table, source, target, at(c.start + c.outside), r_sq) == "");
    CHECK(table.count[0] == c.count_after);
    if (c.k == 1) CHECK(table.index[0] == 1u);
  }
}

TEST_CASE("lists and certificates older than the kept poses are queried again, same table",
          "[association]") {
  // The cache keeps the poses of its last kPoses calls, from which it recomputes where a point
  // was queried and re-ranked. At one pose every call after the first re-sorts every row (the set
  // certificate) without re-ranking it, so at call kPoses the first call's pose is gone: every
  // point is queried again, and the table is still the fresh association's.
  const Scene scene(53, 2000, 300, 0.8);
  REQUIRE(scene.built);
  const PointCloud &target = scene.target, &source = scene.source;
  const KdTree& tree = scene.tree;
  NeighbourCache cache;
  cache.resize(source.size(), 12);
  AssociationTable table;
  table.resize(source.size(), 8);
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.translation() = Eigen::Vector3d(0.01, -0.02, 0.03);
  for (std::uint32_t call = 0; call < NeighbourCache::kPoses; ++call) {
    ppcr::detail::associate_cached(tree, target, source, T, 0.3, nullptr, &cache, &table);
    REQUIRE(cache.last_queries == (call == 0 ? source.size() : 0u));
  }
  ppcr::detail::associate_cached(tree, target, source, T, 0.3, nullptr, &cache, &table);
  CHECK(cache.last_queries == source.size());
  CHECK(table_mismatch(table, source, target, T, 0.3 * 0.3) == "");
  // And the lists it made then serve again.
  ppcr::detail::associate_cached(tree, target, source, T, 0.3, nullptr, &cache, &table);
  CHECK(cache.last_queries == 0u);
  CHECK(table_mismatch(table, source, target, T, 0.3 * 0.3) == "");
}

TEST_CASE("associate_cached queries only where the lists cannot prove the answer",
          "[association]") {
  const Scene scene(52, 4000, 1000, 0.8);  // the source in the interior
  REQUIRE(scene.built);
  const PointCloud &target = scene.target, &source = scene.source;
  const KdTree& tree = scene.tree;
  NeighbourCache cache;
  cache.resize(source.size(), 18);
  AssociationTable table;
  table.resize(source.size(), 10);
  const Eigen::Isometry3d T0 = Eigen::Isometry3d::Identity();
  ppcr::detail::associate_cached(tree, target, source, T0, 0.3, nullptr, &cache, &table);
  CHECK(cache.last_queries == source.size());
  // The same pose again: every list proves itself (delta = 0, and the 10th neighbour is closer
  // than the 18th unless they tie, which random points do not).
  ppcr::detail::associate_cached(tree, target, source, T0, 0.3, nullptr, &cache, &table);
  CHECK(cache.last_queries == 0u);
  // A motion far below the neighbour spacing (~0.06 here): few queries, same answer.
  Eigen::Isometry3d T1 = Eigen::Isometry3d::Identity();
  T1.translation() = Eigen::Vector3d(1e-4, 0.0, 0.0);
  ppcr::detail::associate_cached(tree, target, source, T1, 0.3, nullptr, &cache, &table);
  CHECK(cache.last_queries < source.size() / 10);
  CHECK(table_mismatch(table, source, target, T1, 0.3 * 0.3) == "");
  // A motion larger than the whole candidate radius: every point is re-queried.
  Eigen::Isometry3d T2 = Eigen::Isometry3d::Identity();
  T2.translation() = Eigen::Vector3d(0.5, 0.0, 0.0);
  ppcr::detail::associate_cached(tree, target, source, T2, 0.3, nullptr, &cache, &table);
  CHECK(cache.last_queries == source.size());
  CHECK(table_mismatch(table, source, target, T2, 0.3 * 0.3) == "");
  // invalidate() forgets the lists.
  cache.invalidate();
  ppcr::detail::associate_cached(tree, target, source, T2, 0.3, nullptr, &cache, &table);
  CHECK(cache.last_queries == source.size());
}

TEST_CASE("associate_cached: a fast mover is queried for k + 1 candidates, then for capacity",
          "[association]") {
  // neighbour_cache.hpp, "Fast movers": a point re-queried after moving more than
  // kFastMove x B_j since its last query gets a list of k + 1; once it moves slowly, a point
  // whose list fails is queried for capacity again.
  Rng rng(58);
  const PointCloud target = core_test::uniform_cloud(rng, 4000, -1.0, 1.0);
  const PointCloud source = core_test::uniform_cloud(rng, 1000, -0.6, 0.6);
  KdTree tree;
  REQUIRE(tree.build(target).ok());
  const int k = 10, capacity = 16;
  const double radius = 0.3;  // r_c = 0.375: ~110 target points per ball, ~50 near the edge
  NeighbourCache cache;
  cache.resize(source.size(), capacity);
  AssociationTable table;
  table.resize(source.size(), k);
  // Counts the points whose list holds `count` candidates, its bound the last one's distance.
  auto lists_of = [&](int count) {
    std::size_t n = 0;
    for (std::size_t j = 0; j < source.size(); ++j) {
      n += cache.count[j] == count && cache.bound[j] < NeighbourCache::kRadiusMargin * radius;
    }
    return n;
  };
  // Moves along x: a jump of 0.3 > kFastMove x r_c >= kFastMove x B_j, then 0.002 (below
  // kFastMove x B_j for every point, see the check at the jump; some lists of k + 1 still
  // certify it, others do not), then 1e-4.
  REQUIRE(0.3 > NeighbourCache::kFastMove * NeighbourCache::kRadiusMargin * radius);
  const std::vector<double> xs = {0.0, 0.3, 0.302, 0.3021};
  for (std::size_t i = 0; i < xs.size(); ++i) {
    ppcr::detail::associate_cached(tree, target, source, at(xs[i]), radius, nullptr, &cache,
                                   &table);
    INFO("pose " << i << " x " << xs[i]);
    REQUIRE(table_mismatch(table, source, target, at(xs[i]), radius * radius) == "");
    if (i == 0) {  // a first query is for capacity
      CHECK(cache.last_queries == source.size());
      CHECK(lists_of(capacity) == source.size());
    } else if (i == 1) {  // every point moved fast: lists of k + 1
      CHECK(cache.last_queries == source.size());
      CHECK(lists_of(k + 1) == source.size());
      double nearest_bound = 1e300;  // the nearest 11th neighbour: the next move is slow
      for (double b : cache.bound) nearest_bound = std::min(nearest_bound, b);
      CHECK(0.002 < NeighbourCache::kFastMove * nearest_bound);
    } else if (i == 2) {  // slow: a re-queried point gets capacity again, the others keep k + 1
      std::size_t queried_full = 0, kept = 0;
      for (std::size_t j = 0; j < source.size(); ++j) {
        if (cache.path[j] == NeighbourCache::kQueried) {
          queried_full += cache.count[j] == capacity;
        } else {
          kept += cache.count[j] == k + 1;
        }
      }
      CHECK(cache.last_queries > 0);  // both kinds occur
      CHECK(cache.last_queries < source.size());
      CHECK(queried_full == cache.last_queries);
      CHECK(kept == source.size() - cache.last_queries);
      // A list of k + 1 is too short to seed a query of capacity.
      CHECK(cache.last_seeded == 0u);
    } else {  // moved 1e-4: the lists answer almost every row
      CHECK(cache.last_queries < source.size() / 10);
    }
  }
}

TEST_CASE("associate_cached: exact ties at the k-th distance resolve alike for fast movers",
          "[association]") {
  // An integer lattice in shuffled order, and source points moved onto lattice points: each
  // has 1 + 6 + 12 target points at squared distances 0, 1 and 2 (exact in double), so the
  // 8th to 19th nearest tie. The tree keeps tied points in its visiting order; a fast mover's
  // query of k + 1 sees the tie and is repeated for capacity, so its row is the one a fresh
  // cache (a query of capacity) gives, index for index.
  const Lattice lattice(59);
  REQUIRE(lattice.built);
  const int k = 10, capacity = 16;
  const double radius = 2.5;
  NeighbourCache warm;
  warm.resize(lattice.source.size(), capacity);
  AssociationTable t_warm, t_fresh;
  t_warm.resize(lattice.source.size(), k);
  t_fresh.resize(lattice.source.size(), k);
  // At cell centres first (B_j = sqrt(2.75) ~ 1.66: the 16th of 8 + 24 points at sqrt(0.75)
  // and sqrt(2.75)), then onto lattice points, a move of sqrt(0.75) ~ 0.87 > kFastMove x B_j:
  // every point is a fast mover.
  const Eigen::Vector3d onto_lattice(0.5, -0.5, -0.5);
  REQUIRE(onto_lattice.norm() > NeighbourCache::kFastMove * std::sqrt(2.75));
  for (const Eigen::Vector3d& shift : {Eigen::Vector3d(0, 0, 0), onto_lattice}) {
    Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
    T.translation() = shift;
    lattice.associate(T, radius, &warm, &t_warm);
    NeighbourCache fresh;
    fresh.resize(lattice.source.size(), capacity);
    lattice.associate(T, radius, &fresh, &t_fresh);
    INFO("shift " << shift.transpose());
    REQUIRE(table_mismatch(t_warm, lattice.source, lattice.target, T, radius * radius) == "");
    CHECK(warm.last_queries == lattice.source.size());
    // After the shift every point tied at its k-th, so every query was repeated for capacity
    // (without a seed); its first query, of k + 1, was seeded by the list of capacity.
    CHECK(warm.last_seeded == (shift == Eigen::Vector3d::Zero() ? 0u : lattice.source.size()));
    CHECK(warm.last_seed_repeats == 0u);
    if (shift != Eigen::Vector3d::Zero()) {
      CHECK(std::all_of(warm.count.begin(), warm.count.end(),
                        [&](std::uint16_t c) { return c == capacity; }));
    }
    CHECK(t_warm.count == t_fresh.count);
    CHECK(rows_differing(t_warm, t_fresh) == 0);
  }
}

TEST_CASE(
    "associate_cached: a seeded query keeps the unbounded query's candidates, ties included, "
    "also seeded by the previous point's list",
    "[association]") {
  // From cell centres (capacity 17: 8 points at sqrt(0.75), then 9 of 24 at sqrt(2.75), so B_j =
  // sqrt(2.75) ~ 1.66), every point moves 0.5 onto a face centre: not a fast mover (0.5 <
  // kFastMove x B_j), and its list fails (only 12 target points lie within sqrt(1.5), so its
  // 13th is farther, and sqrt(1.5) + 0.5 > B_j), so it is re-queried for capacity, bounded by its
  // list's distances. At the face centre 4 + 8 points lie at squared distances 0.5 and 1.5 and 8
  // tie at 2.5: the query of 17 keeps 5 of the 8 in the tree's visiting order, and the row's 13th
  // is one of them. The seeded query must keep the same 5 as an unbounded one, so the list
  // (indices, count, bound) and the row equal a direct query's and a fresh cache's.
  const FaceCentres scene(61);
  const Lattice& lattice = scene.lattice;
  const double radius = FaceCentres::radius;
  NeighbourCache warm, fresh;
  AssociationTable t_warm, t_fresh;
  scene.resize(lattice.source.size(), &warm, &t_warm);
  scene.resize(lattice.source.size(), &fresh, &t_fresh);
  lattice.associate(at(0.0), radius, &warm, &t_warm);
  REQUIRE(0.5 <= NeighbourCache::kFastMove * std::sqrt(2.75));
  lattice.associate(at(0.5), radius, &warm, &t_warm);
  lattice.associate(at(0.5), radius, &fresh, &t_fresh);
  REQUIRE(warm.last_queries == lattice.source.size());
  REQUIRE(warm.last_seeded == lattice.source.size());  // every query took the seeded path
  CHECK(warm.last_seed_repeats == 0u);                 // and kept its seed
  CHECK(fresh.last_seeded == 0u);                      // a fresh cache has no lists to seed
  // ... but its points seed from the previous point's list: all but the first of each block.
  CHECK(fresh.last_neighbour_seeded > lattice.source.size() / 2);
  CHECK(fresh.last_neighbour_seed_repeats == 0u);
  CHECK(warm.last_neighbour_seeded == 0u);  // every warm point had a list of its own
  REQUIRE(table_mismatch(t_warm, lattice.source, lattice.target, at(0.5), radius * radius) == "");
  CHECK(rows_differing(t_warm, t_fresh) == 0);
  CHECK(scene.lists_differing_from_queries(lattice.source, warm, at(0.5)) == 0);
  // The fresh cache's lists, seeded by their neighbours' (the same 5 of 8 tied points).
  CHECK(scene.lists_differing_from_queries(lattice.source, fresh, at(0.5)) == 0);
}

TEST_CASE(
    "associate_cached: a query seeded by the previous point's list at its own k-th distance "
    "keeps the unbounded query's tied candidates",
    "[association]") {
  // Every source point twice in a row: the second copy's seed, the largest distance in the first
  // copy's list, is exactly its own capacity-th distance, where 8 points tie (face centres of the
  // integer lattice, 4 + 8 points at squared distances 0.5 and 1.5, 8 at 2.5). A seed below the
  // k-th distance would find fewer than `capacity` and be repeated (counted); on this lattice's
  // exact distances the 1e-9 slack itself is not exercised.
  const FaceCentres scene(63);
  const Lattice& lattice = scene.lattice;
  const double radius = FaceCentres::radius;
  PointCloud twice;
  for (const Eigen::Vector3d& s : lattice.source) {
    twice.push_back(s);
    twice.push_back(s);
  }
  NeighbourCache cache;
  AssociationTable table;
  scene.resize(twice.size(), &cache, &table);
  ppcr::detail::associate_cached(lattice.tree, lattice.target, twice, at(0.5), radius, nullptr,
                                 &cache, &table);
  REQUIRE(cache.last_queries == twice.size());
  CHECK(cache.last_neighbour_seeded >= twice.size() / 2);  // at least every second copy
  CHECK(cache.last_neighbour_seed_repeats == 0u);
  REQUIRE(table_mismatch(table, twice, lattice.target, at(0.5), radius * radius) == "");
  CHECK(scene.lists_differing_from_queries(twice, cache, at(0.5)) == 0);
}

TEST_CASE("associate_cached: rows re-ranked from the lists equal freshly queried rows, bit for bit",
          "[association]") {
  // A warm cache answers most rows from its lists (distances computed in neighbour_cache.cpp);
  // a fresh cache queries every row (distances from the k-d tree, kdtree.cpp). Same indices in
  // the same order: the distances, by the same expression, rank ties alike.
  const Scene scene(57, 5000, 3000, 1.1);
  REQUIRE(scene.built);
  const PointCloud &target = scene.target, &source = scene.source;
  const KdTree& tree = scene.tree;
  const std::vector<Eigen::Isometry3d>& poses = scene.poses;
  NeighbourCache warm;
  warm.resize(source.size(), 14);
  AssociationTable t_warm, t_fresh;
  t_warm.resize(source.size(), 10);
  t_fresh.resize(source.size(), 10);
  std::size_t answered_from_lists = 0;
  for (std::size_t i = 0; i < poses.size(); ++i) {
    ppcr::detail::associate_cached(tree, target, source, poses[i], 0.15, nullptr, &warm, &t_warm);
    NeighbourCache fresh;
    fresh.resize(source.size(), 14);
    ppcr::detail::associate_cached(tree, target, source, poses[i], 0.15, nullptr, &fresh, &t_fresh);
    REQUIRE(fresh.last_queries == source.size());
    answered_from_lists += source.size() - warm.last_queries;
    INFO("pose " << i);
    CHECK(t_warm.count == t_fresh.count);
    CHECK(rows_differing(t_warm, t_fresh) == 0);
  }
  CHECK(answered_from_lists > 5 * source.size());  // the lists' paths were exercised
}

TEST_CASE(
    "spread_lists: after a coarse level's lists are spread over every point, the tables are those "
    "of brute force and of a fresh cache, with fewer queries",
    "[association]") {
  // The registration's coarse phase (RegistrationOptions::coarse_stride): every stride-th point
  // of a Z-ordered source drifts in the first rows of a cache and table sized for every point;
  // then every point, the coarse points' lists spread to their rows. Their rows must be
  // answered from their lists (fewer queries) and every table must be what brute force and a
  // fresh cache give: indices and order (the distances follow from the indices).
  const Scene scene(58, 5000, 3000, 1.1);
  REQUIRE(scene.built);
  const PointCloud& target = scene.target;
  const PointCloud source = z_ordered(scene.source);
  const KdTree& tree = scene.tree;
  const std::vector<Eigen::Isometry3d>& poses = scene.poses;
  const double radius = 0.15;
  const int k = 10, capacity = 14;
  constexpr std::size_t kSwitch = 7;  // the first pose of the full level: in the slow drift
  ppcr::detail::Parallel two(2);
  // The rows spread on one thread and on two (spread_lists moves rows in parallel rounds).
  for (const auto& [stride, parallel] :
       {std::pair<std::size_t, const ppcr::detail::Parallel*>{2, nullptr},
        {3, nullptr},
        {2, &two},
        {3, &two}}) {
    INFO("stride " << stride << ", threads " << (parallel != nullptr ? 2 : 1));
    PointCloud coarse;
    for (std::size_t i = 0; i < source.size(); i += stride) coarse.push_back(source[i]);
    NeighbourCache cache;
    AssociationTable table, fresh_table;
    cache.resize(source.size(), capacity);  // as the registration: sized for every point first
    table.resize(source.size(), k);
    const std::uint32_t* index_data = table.index.data();
    cache.resize(coarse.size(), capacity);
    table.resize(coarse.size(), k);
    fresh_table.resize(source.size(), k);
    for (std::size_t i = 0; i < kSwitch; ++i) {
      ppcr::detail::associate_cached(tree, target, coarse, poses[i], radius, nullptr, &cache,
                                     &table);
      REQUIRE(table_mismatch(table, coarse, target, poses[i], radius * radius) == "");
    }
    // The rows as they were, to check where spread_lists puts them.
    const NeighbourCache before = cache;
    const AssociationTable table_before = table;
    const std::uint32_t* cache_data = cache.index.data();
    ppcr::detail::spread_lists(stride, source.size(), &cache, &table, parallel);
    CHECK(table.index.data() == index_data);  // grown within their capacity
    CHECK(cache.index.data() == cache_data);
    REQUIRE(cache.count.size() == source.size());
    REQUIRE(table.count.size() == source.size());
    std::size_t misplaced = 0, listed_others = 0;
    for (std::size_t j = 0; j < source.size(); ++j) {
      if (j % stride != 0) {
        listed_others += cache.bound[j] >= 0.0 || cache.set_radius_sq[j] >= 0.0;
        continue;
      }
      const std::size_t i = j / stride;
      const auto row = [](const auto& v, std::size_t r, std::size_t width) {
        return std::vector<typename std::decay_t<decltype(v)>::value_type>(
            v.begin() + static_cast<std::ptrdiff_t>(r * width),
            v.begin() + static_cast<std::ptrdiff_t>((r + 1) * width));
      };
      misplaced += cache.count[j] != before.count[i] || cache.bound[j] != before.bound[i] ||
                   cache.query_call[j] != before.query_call[i] ||
                   cache.ranked_call[j] != before.ranked_call[i] ||
                   cache.set_radius_sq[j] != before.set_radius_sq[i] ||
                   row(cache.index, j, capacity) != row(before.index, i, capacity) ||
                   table.count[j] != table_before.count[i] ||
                   row(table.index, j, k) != row(table_before.index, i, k);
    }
    CHECK(misplaced == 0);
    CHECK(listed_others == 0);
    for (std::size_t i = kSwitch; i < poses.size(); ++i) {
      INFO("pose " << i);
      ppcr::detail::associate_cached(tree, target, source, poses[i], radius, nullptr, &cache,
                                     &table);
      if (i == kSwitch) {
        // Every point without a list is queried; most of the coarse points are answered from
        // theirs.
        CHECK(cache.last_queries >= source.size() - coarse.size());
        CHECK(cache.last_queries < source.size() - coarse.size() / 2);
      }
      REQUIRE(table_mismatch(table, source, target, poses[i], radius * radius) == "");
      NeighbourCache fresh;
      fresh.resize(source.size(), capacity);
      ppcr::detail::associate_cached(tree, target, source, poses[i], radius, nullptr, &fresh,
                                     &fresh_table);
      REQUIRE(table.count == fresh_table.count);
      CHECK(rows_differing(table, fresh_table) == 0);
    }
  }
}

TEST_CASE("spread_lists: row i lands at row i * stride, on 1 and 2 threads, the others list-less",
          "[association]") {
  // Rows that name their source row, so that a row taken from the wrong place, or overwritten
  // before it was read, shows. 6000 rows: the rounds then span several blocks each, so that two
  // threads move rows at once. Point counts that are not a multiple of the stride.
  ppcr::detail::Parallel two(2);
  const int k = 3, capacity = 5;
  const std::size_t cap = static_cast<std::size_t>(capacity), kk = static_cast<std::size_t>(k);
  for (std::size_t coarse : {0u, 1u, 2u, 7u, 6000u}) {
    for (std::size_t stride : {2u, 3u, 64u}) {
      const std::size_t points = coarse == 0 ? 0 : (coarse - 1) * stride + 1 + stride / 2;
      for (const ppcr::detail::Parallel* parallel :
           {static_cast<ppcr::detail::Parallel*>(nullptr), &two}) {
        INFO("coarse " << coarse << ", stride " << stride << ", threads "
                       << (parallel != nullptr ? 2 : 1));
        NeighbourCache cache;
        AssociationTable table;
        cache.resize(points, capacity);  // as the associator: every point first
        table.resize(points, k);
        cache.resize(coarse, capacity);
        table.resize(coarse, k);
        cache.table = &table;  // as associate_cached leaves it
        for (std::size_t i = 0; i < coarse; ++i) {
          for (std::size_t c = 0; c < cap; ++c) {
            cache.index[i * cap + c] = static_cast<std::uint32_t>(i * 100 + c);
          }
          cache.count[i] = static_cast<std::uint16_t>(i % cap + 1);
          cache.query_call[i] = static_cast<std::uint32_t>(i);
          cache.bound[i] = static_cast<double>(i) + 0.5;
          cache.ranked_call[i] = static_cast<std::uint32_t>(i + 1);
          cache.set_radius_sq[i] = static_cast<double>(i) + 0.25;
          for (std::size_t m = 0; m < kk; ++m) {
            table.index[i * kk + m] = static_cast<std::uint32_t>(i * 10 + m);
          }
          table.count[i] = static_cast<std::uint16_t>(i % kk);
        }
        ppcr::detail::spread_lists(stride, points, &cache, &table, parallel);
        REQUIRE(cache.count.size() == points);
        REQUIRE(table.count.size() == points);
        std::size_t wrong = 0, listed_others = 0;
        for (std::size_t j = 0; j < points; ++j) {
          if (j % stride != 0) {
            listed_others += cache.bound[j] >= 0.0 || cache.set_radius_sq[j] >= 0.0;
            continue;
          }
          const std::size_t i = j / stride;
          REQUIRE(i < coarse);
          bool ok =
              cache.count[j] == i % cap + 1 && cache.query_call[j] == i &&
              cache.bound[j] == static_cast<double>(i) + 0.5 && cache.ranked_call[j] == i + 1 &&
              cache.set_radius_sq[j] == static_cast<double>(i) + 0.25 && table.count[j] == i % kk;
          for (std::size_t c = 0; c < cap; ++c) ok = ok && cache.index[j * cap + c] == i * 100 + c;
          for (std::size_t m = 0; m < kk; ++m) ok = ok && table.index[j * kk + m] == i * 10 + m;
          wrong += !ok;
        }
        CHECK(wrong == 0);
        CHECK(listed_others == 0);
      }
    }
  }
}

TEST_CASE("associate_cached: same tables and query counts with 1 and 2 threads", "[association]") {
  const Scene scene(53, 20000, 15000, 1.1);
  REQUIRE(scene.built);
  const PointCloud &target = scene.target, &source = scene.source;
  const KdTree& tree = scene.tree;
  const std::vector<Eigen::Isometry3d>& poses = scene.poses;
  NeighbourCache c1, c2;
  c1.resize(source.size(), 18);
  c2.resize(source.size(), 18);
  AssociationTable t1, t2;
  t1.resize(source.size(), 10);
  t2.resize(source.size(), 10);
  for (const Eigen::Isometry3d& T : poses) {
    ppcr::detail::associate_cached(tree, target, source, T, 0.1, nullptr, &c1, &t1);
    ppcr::detail::associate_cached(tree, target, source, T, 0.1, core_test::parallel(2), &c2, &t2);
    CHECK(c1.last_queries == c2.last_queries);
    CHECK(t1.count == t2.count);
    CHECK(rows_differing(t1, t2) == 0);
    CHECK(t1.pairs == t2.pairs);
    CHECK(t1.matched == t2.matched);
  }
}

TEST_CASE("registration with and without the neighbour cache gives the same pose",
          "[association][registration]") {
  Rng rng(54);
  const PointCloud target = core_test::analytic_scene(rng, 6000);
  const Eigen::Isometry3d T_true =
      core_test::make_pose(Eigen::Vector3d(0.3, -0.5, 1.0), core_test::deg2rad(10.0),
                           Eigen::Vector3d(0.04, -0.03, 0.02));
  const PointCloud source =
      core_test::transformed(core_test::analytic_scene(rng, 2500), T_true.inverse());
  for (ppcr::ErrorModel model : {ppcr::ErrorModel::kPlane, ppcr::ErrorModel::kPoint}) {
    ppcr::RegistrationOptions o;
    o.radius = 0.2;
    o.error_model = model;
    o.expert.neighbour_cache = 0;
    const ppcr::RegistrationResult plain = ppcr::align(source, target, o);
    REQUIRE(plain.status.ok());
    for (int extra : {4, 8}) {  // the default, and the default before the set certificate
      INFO("neighbour_cache " << extra);
      o.expert.neighbour_cache = extra;
      const ppcr::RegistrationResult cached = ppcr::align(source, target, o);
      REQUIRE(cached.status.ok());
      CHECK(plain.iterations == cached.iterations);
      CHECK(plain.correspondences == cached.correspondences);
      CHECK(
          (plain.T_target_source.matrix() - cached.T_target_source.matrix()).cwiseAbs().maxCoeff() <
          1e-12);
      CHECK((cached.T_target_source.linear() - T_true.linear()).norm() < 1e-2);
    }
  }
  // A coarse level (the plane model's default stride 2 here: 2500 points) spreads its lists over
  // every point at the switch: the same pose as without the cache, with that stride.
  ppcr::RegistrationOptions o;
  o.radius = 0.2;
  o.expert.coarse_stride = 2;
  o.expert.neighbour_cache = 0;
  const ppcr::RegistrationResult plain = ppcr::align(source, target, o);
  o.expert.neighbour_cache = 4;
  const ppcr::RegistrationResult cached = ppcr::align(source, target, o);
  REQUIRE(plain.status.ok());
  REQUIRE(cached.status.ok());
  CHECK(plain.iterations == cached.iterations);
  CHECK(plain.T_target_source.matrix() == cached.T_target_source.matrix());
}
