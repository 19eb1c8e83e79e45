// Tests of detail::KdTree (nanoflann's tree behind our interface, its points in leaf order):
// radius_knn against a brute-force scan of every point and against nanoflann's tree over the
// cloud as given.
#include <algorithm>
#include <catch2/catch.hpp>
#include <cstdint>
#include <cstring>
#include <nanoflann.hpp>
#include <sstream>
#include <string>
#include <vector>

#include "association/kdtree.hpp"
#include "association/radius_knn_result.hpp"
#include "core_test_util.hpp"

using core_test::Rng;
using ppcr::PointCloud;
using ppcr::detail::KdTree;

namespace {

struct Hit {
  double dist_sq;
  std::uint32_t index;
};

// nanoflann's tree over a cloud as given (no permutation), for the differential test below.
struct CloudAdaptor {
  const PointCloud* points = nullptr;
  std::size_t kdtree_get_point_count() const { return points->size(); }
  double kdtree_get_pt(std::uint32_t i, std::size_t axis) const { return (*points)[i][axis]; }
  template <class Box>
  bool kdtree_get_bbox(Box&) const {
    return false;
  }
};
using ReferenceTree = nanoflann::KDTreeSingleIndexAdaptor<
    nanoflann::L2_Simple_Adaptor<double, CloudAdaptor, double, std::uint32_t>, CloudAdaptor, 3,
    std::uint32_t>;
#if NANOFLANN_VERSION >= 0x150
nanoflann::SearchParameters exact_sorted_search() {
  return nanoflann::SearchParameters(0.0f, true);
}
#else
nanoflann::SearchParams exact_sorted_search() { return nanoflann::SearchParams(0, 0.0f, true); }
#endif

// Squared distance summed in x, y, z order (exact for integer coordinates).
double dist_sq(const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
  const double dx = a.x() - b.x(), dy = a.y() - b.y(), dz = a.z() - b.z();
  return dx * dx + dy * dy + dz * dz;
}

// Every point within the radius (inclusive), sorted by distance then index.
std::vector<Hit> brute_force(const PointCloud& cloud, const Eigen::Vector3d& q, double radius_sq) {
  std::vector<Hit> hits;
  for (std::size_t i = 0; i < cloud.size(); ++i) {
    const double d = dist_sq(cloud[i], q);
    if (d <= radius_sq) hits.push_back({d, static_cast<std::uint32_t>(i)});
  }
  std::sort(hits.begin(), hits.end(), [](const Hit& a, const Hit& b) {
    return a.dist_sq < b.dist_sq || (a.dist_sq == b.dist_sq && a.index < b.index);
  });
  return hits;
}

// Checks one query against brute force; returns "" or a description of the first mismatch
// (one Catch assertion per query keeps the suite fast). `exact` when squared distances are exact
// (integer coordinates), else a relative tolerance of a few ulps covers a different summation
// order.
std::string query_mismatch(const KdTree& tree, const PointCloud& cloud, const Eigen::Vector3d& q,
                           int k, double radius_sq, bool exact) {
  std::vector<std::uint32_t> idx(static_cast<std::size_t>(k) + 1, 0xFFFFFFFFu);
  std::vector<double> d(static_cast<std::size_t>(k) + 1, -1.0);
  const int n = tree.radius_knn(q, k, radius_sq, idx.data(), d.data());
  const std::vector<Hit> ref = brute_force(cloud, q, radius_sq);
  const int n_ref =
      static_cast<int>(std::min<std::size_t>(ref.size(), static_cast<std::size_t>(k)));
  std::ostringstream why;
  why << "query " << q.transpose() << " k " << k << " radius_sq " << radius_sq << " in range "
      << ref.size() << ": ";
  if (n != n_ref) {
    why << "returned " << n << " neighbours, brute force " << n_ref;
    return why.str();
  }
  if (idx[static_cast<std::size_t>(k)] != 0xFFFFFFFFu) return why.str() + "wrote past n";
  const double tol = exact ? 0.0 : 1e-13;
  std::vector<char> in_result(cloud.size(), 0);
  for (int m = 0; m < n; ++m) {
    const std::size_t um = static_cast<std::size_t>(m);
    if (idx[um] >= cloud.size()) return why.str() + "index out of range";
    if (in_result[idx[um]]) return why.str() + "index returned twice";
    in_result[idx[um]] = 1;
    // The reported distance is the true distance of the reported index, within the radius,
    // sorted, and equal to the brute-force m-th distance (ties at the k-th distance may pick
    // different indices: compare distances, not indices).
    if (std::abs(d[um] - dist_sq(cloud[idx[um]], q)) > tol * (1.0 + d[um])) {
      why << "slot " << m << ": distance " << d[um] << " is not that of index " << idx[um];
      return why.str();
    }
    // To the bit squared_distance(q, y): associate_cached (neighbour_cache.cpp) re-ranks a
    // query's candidates by the tree's distances and a cache hit's by that function.
    if (d[um] != ppcr::detail::squared_distance(q.data(), cloud[idx[um]].data())) {
      why << "slot " << m << ": distance " << d[um] << " differs in its last bits from "
          << "squared_distance(q, y)";
      return why.str();
    }
    if (d[um] > radius_sq * (1.0 + tol)) return why.str() + "outside the radius";
    if (m > 0 && d[um - 1] > d[um]) return why.str() + "not sorted";
    if (std::abs(d[um] - ref[um].dist_sq) > tol * (1.0 + d[um])) {
      why << "slot " << m << ": distance " << d[um] << ", brute force " << ref[um].dist_sq;
      return why.str();
    }
  }
  // Every point strictly closer than the k-th distance must be in the result (as a set).
  if (n > 0) {
    const double kth = d[static_cast<std::size_t>(n - 1)];
    for (const Hit& h : ref) {
      if (h.dist_sq < kth * (1.0 - 2.0 * tol) && !in_result[h.index]) {
        why << "point " << h.index << " at " << h.dist_sq << " missing";
        return why.str();
      }
    }
  }
  return "";
}

PointCloud clustered_cloud(Rng& rng, std::size_t n) {
  PointCloud centres = core_test::uniform_cloud(rng, 8, -5.0, 5.0);
  PointCloud out;
  for (std::size_t i = 0; i < n; ++i) {
    const Eigen::Vector3d& c = centres[i % centres.size()];
    out.push_back(c + Eigen::Vector3d(core_test::gaussian(rng, 0.05),
                                      core_test::gaussian(rng, 0.05),
                                      core_test::gaussian(rng, 0.05)));
  }
  return out;
}

PointCloud with_duplicates(Rng& rng, std::size_t n) {
  PointCloud base = core_test::uniform_cloud(rng, n / 4, -1.0, 1.0);
  PointCloud out;
  for (std::size_t i = 0; i < n; ++i) out.push_back(base[i % base.size()]);
  std::shuffle(out.begin(), out.end(), rng);
  return out;
}

// Integer grid: every squared distance to an integer or half-integer query is exact.
PointCloud integer_grid(int side) {
  PointCloud out;
  for (int x = 0; x < side; ++x) {
    for (int y = 0; y < side; ++y) {
      for (int z = 0; z < side; ++z) out.emplace_back(x, y, z);
    }
  }
  return out;
}

}  // namespace

TEST_CASE("radius_knn equals brute force on random clouds", "[kdtree]") {
  Rng rng(31);
  struct Case {
    const char* name;
    PointCloud cloud;
  };
  std::vector<Case> cases;
  cases.push_back({"uniform", core_test::uniform_cloud(rng, 3000, -1.0, 1.0)});
  cases.push_back({"clustered", clustered_cloud(rng, 3000)});
  cases.push_back({"duplicates", with_duplicates(rng, 2000)});
  for (const Case& c : cases) {
    KdTree tree;
    REQUIRE(tree.build(c.cloud).ok());
    CHECK(tree.size() == c.cloud.size());
    for (int k : {1, 5, 20, 3500}) {
      for (double radius : {0.01, 0.1, 0.3, 1.0, 100.0}) {
        for (int qi = 0; qi < 40; ++qi) {
          // Half the queries at cloud points (distance 0 ties), half anywhere.
          const Eigen::Vector3d q = qi % 2 == 0
                                        ? c.cloud[rng() % c.cloud.size()]
                                        : Eigen::Vector3d(core_test::uniform(rng, -1.5, 1.5),
                                                          core_test::uniform(rng, -1.5, 1.5),
                                                          core_test::uniform(rng, -1.5, 1.5));
          INFO(c.name);
          CHECK(query_mismatch(tree, c.cloud, q, k, radius * radius, false) == "");
        }
      }
    }
  }
}

TEST_CASE("radius_knn: points exactly at the radius are included (integer grid)", "[kdtree]") {
  const PointCloud grid = integer_grid(9);  // 729 points
  KdTree tree;
  REQUIRE(tree.build(grid).ok());
  Rng rng(32);
  for (int qi = 0; qi < 200; ++qi) {
    // Integer and half-integer queries, some outside the grid.
    const Eigen::Vector3d q(0.5 * static_cast<double>(rng() % 24) - 2.0,
                            0.5 * static_cast<double>(rng() % 24) - 2.0,
                            0.5 * static_cast<double>(rng() % 24) - 2.0);
    // Squared radii that are exact squared distances of grid points (ties at the radius).
    for (double radius_sq : {0.0, 0.75, 1.0, 2.0, 2.25, 3.0, 4.0, 5.0, 6.75, 9.0}) {
      for (int k : {1, 5, 20, 64, 1000}) {
        CHECK(query_mismatch(tree, grid, q, k, radius_sq, true) == "");
      }
    }
  }
  SECTION("the whole shell at distance 1 of an interior point, plus the point itself") {
    std::uint32_t idx[16];
    double d[16];
    const int n = tree.radius_knn(Eigen::Vector3d(4, 4, 4), 16, 1.0, idx, d);
    REQUIRE(n == 7);
    CHECK(d[0] == 0.0);
    for (int m = 1; m < 7; ++m) CHECK(d[m] == 1.0);
    // Just below the radius: only the point itself.
    CHECK(tree.radius_knn(Eigen::Vector3d(4, 4, 4), 16, std::nextafter(1.0, 0.0), idx, d) == 1);
  }
}

TEST_CASE("radius_knn returns nothing when no point is in range", "[kdtree]") {
  Rng rng(33);
  const PointCloud cloud = core_test::uniform_cloud(rng, 1000, -1.0, 1.0);
  KdTree tree;
  REQUIRE(tree.build(cloud).ok());
  std::uint32_t idx[8];
  double d[8];
  CHECK(tree.radius_knn(Eigen::Vector3d(3.0, 0.0, 0.0), 8, 1.0, idx, d) == 0);
  CHECK(tree.radius_knn(Eigen::Vector3d(1e6, -1e6, 1e6), 8, 1e6, idx, d) == 0);
  // Far away but with a radius that reaches: brute force agrees.
  CHECK(query_mismatch(tree, cloud, Eigen::Vector3d(1e3, 0.0, 0.0), 8, 1e3 * 1e3 * 1.01, false) ==
        "");
  // Radius 0 away from every point.
  CHECK(tree.radius_knn(Eigen::Vector3d(0.123456, 0.5, -0.25), 8, 0.0, idx, d) == 0);
  // Radius 0 at a point: that point (inclusive).
  REQUIRE(tree.radius_knn(cloud[17], 8, 0.0, idx, d) == 1);
  CHECK(idx[0] == 17u);
  CHECK(d[0] == 0.0);
}

TEST_CASE("radius_knn on a single-point tree", "[kdtree]") {
  const PointCloud one = {Eigen::Vector3d(1.0, 2.0, 3.0)};
  KdTree tree;
  REQUIRE(tree.build(one).ok());
  std::uint32_t idx[4];
  double d[4];
  REQUIRE(tree.radius_knn(Eigen::Vector3d(1.0, 2.0, 5.0), 4, 4.0, idx, d) == 1);
  CHECK(idx[0] == 0u);
  CHECK(d[0] == 4.0);
  CHECK(tree.radius_knn(Eigen::Vector3d(1.0, 2.0, 5.0), 4, 3.99, idx, d) == 0);
  CHECK(tree.radius_knn(Eigen::Vector3d(1.0, 2.0, 3.0), 1, 0.0, idx, d) == 1);
}

TEST_CASE("radius_knn when all points are identical", "[kdtree]") {
  const PointCloud same(500, Eigen::Vector3d(0.25, -0.5, 2.0));
  KdTree tree;
  REQUIRE(tree.build(same).ok());
  for (int k : {1, 10, 499, 500, 600}) {
    std::vector<std::uint32_t> idx(static_cast<std::size_t>(k));
    std::vector<double> d(static_cast<std::size_t>(k));
    const int n = tree.radius_knn(Eigen::Vector3d(0.25, -0.5, 2.5), k, 0.25, idx.data(), d.data());
    CHECK(n == std::min(k, 500));
    for (int m = 0; m < n; ++m) CHECK(d[static_cast<std::size_t>(m)] == 0.25);
    std::sort(idx.begin(), idx.begin() + n);
    CHECK(std::adjacent_find(idx.begin(), idx.begin() + n) == idx.begin() + n);
    CHECK(tree.radius_knn(Eigen::Vector3d(0.25, -0.5, 2.5), k, 0.2, idx.data(), d.data()) == 0);
  }
}

TEST_CASE("radius_knn on an empty tree and with k < 1 returns 0", "[kdtree]") {
  const PointCloud empty;
  KdTree tree;
  tree.build(empty);
  std::uint32_t idx[2];
  double d[2];
  CHECK(tree.radius_knn(Eigen::Vector3d::Zero(), 2, 1.0, idx, d) == 0);
  KdTree unbuilt;
  CHECK(unbuilt.size() == 0u);
  CHECK(unbuilt.radius_knn(Eigen::Vector3d::Zero(), 2, 1.0, idx, d) == 0);
  const PointCloud one = {Eigen::Vector3d::Zero()};
  KdTree t1;
  REQUIRE(t1.build(one).ok());
  CHECK(t1.radius_knn(Eigen::Vector3d::Zero(), 0, 1.0, idx, d) == 0);
}

// The leaf order is a permutation of the cloud's indices, and the search on trees of varied shape
// (ties along the split axes: grids, duplicates, a flat and a straight cloud; clustered ones;
// sizes around a leaf's) agrees with brute force.
TEST_CASE("leaf order and search on clouds of varied shape", "[kdtree]") {
  Rng rng(78);
  std::vector<PointCloud> clouds;
  clouds.push_back(core_test::uniform_cloud(rng, 5000, -1.0, 1.0));
  clouds.push_back(clustered_cloud(rng, 4000));
  clouds.push_back(with_duplicates(rng, 3000));
  clouds.push_back(integer_grid(12));
  PointCloud flat = core_test::uniform_cloud(rng, 3000, -2.0, 2.0);
  for (Eigen::Vector3d& p : flat) p.z() = 0.0;
  clouds.push_back(flat);
  PointCloud line;
  for (int i = 0; i < 500; ++i) line.emplace_back(0.25 * (i % 37), 1.0, -3.0);
  clouds.push_back(line);
  for (std::size_t n : {std::size_t{1}, std::size_t{ppcr::detail::kLeafMaxSize},
                        std::size_t{ppcr::detail::kLeafMaxSize + 1}, std::size_t{100}}) {
    clouds.push_back(core_test::uniform_cloud(rng, n, 0.0, 1.0));
  }
  for (std::size_t c = 0; c < clouds.size(); ++c) {
    const PointCloud& cloud = clouds[c];
    INFO("cloud " << c << " (" << cloud.size() << " points)");
    KdTree tree;
    REQUIRE(tree.build(cloud).ok());
    std::vector<std::uint32_t> order(tree.leaf_order().begin(), tree.leaf_order().end());
    std::sort(order.begin(), order.end());
    REQUIRE(order.size() == cloud.size());
    for (std::size_t i = 0; i < order.size(); ++i) REQUIRE(order[i] == i);
    for (int qi = 0; qi < 100; ++qi) {
      Eigen::Vector3d q = cloud[rng() % cloud.size()];
      if (qi % 2 == 1) q += Eigen::Vector3d(0.3, -0.2, 0.1);
      CHECK(query_mismatch(tree, cloud, q, 64, 0.25, false) == "");
    }
  }
}

// The differential test of the leaf-order layout (kdtree.cpp): nanoflann's own tree over the
// cloud as given, searched with the same result set, is the reference: the same indices, the same
// squared distances bit for bit, in the same order. Grid clouds with duplicates, queries on and
// off the points, and radii set to a point's exact squared distance put many points exactly at
// the radius, where the rounding of the search's cell bound decides (an addition in another order
// than nanoflann's dropped or kept whole groups of such points).
TEST_CASE("radius_knn returns exactly nanoflann's own search (ties at the radius)", "[kdtree]") {
  Rng rng(77);
  std::size_t queries = 0, at_radius = 0;
  for (int c = 0; c < 24; ++c) {
    const std::size_t n = 200 + rng() % 2800;
    PointCloud cloud;
    for (std::size_t i = 0; i < n; ++i) {
      if (i > 0 && i % 3 != 0) {
        cloud.push_back(cloud[rng() % i]);  // duplicates
      } else {
        cloud.emplace_back(0.1 * static_cast<double>(rng() % 10),
                           0.1 * static_cast<double>(rng() % 10),
                           0.1 * static_cast<double>(rng() % 10));
      }
    }
    KdTree tree;
    REQUIRE(tree.build(cloud).ok());
    const CloudAdaptor adaptor{&cloud};
    const ReferenceTree reference(
        3, adaptor, nanoflann::KDTreeSingleIndexAdaptorParams(ppcr::detail::kLeafMaxSize));
    for (int qi = 0; qi < 200; ++qi) {
      Eigen::Vector3d q = cloud[rng() % n];
      if (qi % 2 == 1) q[static_cast<int>(rng() % 3)] += 0.05 * static_cast<double>(rng() % 5);
      const double radius_sq = dist_sq(q, cloud[rng() % n]);
      const int k = qi % 4 == 0 ? 5000 : 1 + static_cast<int>(rng() % 40);
      std::vector<std::uint32_t> got_index(static_cast<std::size_t>(k)),
          ref_index(static_cast<std::size_t>(k));
      std::vector<double> got_d(static_cast<std::size_t>(k)), ref_d(static_cast<std::size_t>(k));
      const int got = tree.radius_knn(q, k, radius_sq, got_index.data(), got_d.data());
      ppcr::detail::RadiusKnnResultSet result(k, radius_sq, ref_index.data(), ref_d.data());
      reference.findNeighbors(result, q.data(), exact_sorted_search());
      const int expected = result.size();
      ++queries;
      for (int m = 0; m < expected; ++m)
        at_radius += ref_d[static_cast<std::size_t>(m)] == radius_sq;
      INFO("cloud " << c << ", query " << qi << ", k " << k);
      REQUIRE(got == expected);
      CHECK(std::equal(got_index.begin(), got_index.begin() + got, ref_index.begin()));
      CHECK(std::memcmp(got_d.data(), ref_d.data(),
                        static_cast<std::size_t>(got) * sizeof(double)) == 0);
    }
  }
  // The cases must exercise points exactly at the radius.
  CHECK(queries == 24 * 200);
  CHECK(at_radius > queries);
}
