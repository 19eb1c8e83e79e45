// Tests of spatial_order.hpp: the Z-order sort against a reference Morton code computed bit by bit,
// the permutation applied to both clouds alike, ties and degenerate clouds.
#include <algorithm>
#include <catch2/catch.hpp>
#include <cstdint>
#include <limits>
#include <vector>

#include "association/spatial_order.hpp"
#include "common/parallel.hpp"
#include "core_test_util.hpp"

using ppcr::PointCloud;
using ppcr::detail::spatial_sort;
using ppcr::detail::SpatialSortScratch;

namespace {

// The Morton code the header specifies, bit by bit: cell q = floor((p - lo) / extent * 2^21)
// (clamped to 2^21 - 1) per axis, bit i of x, y, z to bits 3i, 3i + 1, 3i + 2.
std::uint64_t reference_code(const Eigen::Vector3d& p, const Eigen::Vector3d& lo, double extent) {
  std::uint64_t code = 0;
  for (int axis = 0; axis < 3; ++axis) {
    const double cells = static_cast<double>(1 << 21);
    const double q = std::min(std::floor((p[axis] - lo[axis]) / extent * cells), cells - 1.0);
    const std::uint64_t cell = static_cast<std::uint64_t>(q);
    for (int bit = 0; bit < 21; ++bit) {
      code |= ((cell >> bit) & 1u) << (3 * bit + axis);
    }
  }
  return code;
}

// A cloud whose point i is (i, 0, 0): carried along as b, it tells where each point went.
PointCloud index_cloud(std::size_t n) {
  PointCloud c(n, Eigen::Vector3d::Zero());
  for (std::size_t i = 0; i < n; ++i) c[i].x() = static_cast<double>(i);
  return c;
}

// Checks that spatial_sort(original) is a permutation ordered by reference_code, ties by x, y, z,
// then index, that moves a second cloud alike, on `threads` threads (the parallel sort splits the
// keys at their median: every key must still land in its place).
void check_sorted(const PointCloud& original, int threads) {
  PointCloud a = original;
  PointCloud b = index_cloud(a.size());
  SpatialSortScratch scratch;
  const ppcr::detail::Parallel parallel(threads);
  spatial_sort(&a, &b, &scratch, &parallel);
  Eigen::Vector3d lo = original[0], hi = original[0];
  for (const Eigen::Vector3d& p : original) {
    lo = lo.cwiseMin(p);
    hi = hi.cwiseMax(p);
  }
  const double extent = (hi - lo).maxCoeff();
  REQUIRE(a.size() == original.size());
  std::vector<bool> seen(a.size(), false);
  for (std::size_t i = 0; i < a.size(); ++i) {
    const std::size_t from = static_cast<std::size_t>(b[i].x());
    REQUIRE(from < a.size());
    CHECK_FALSE(seen[from]);  // a permutation
    seen[from] = true;
    CHECK(a[i] == original[from]);  // a and b moved alike
    if (i > 0) {
      const std::size_t prev = static_cast<std::size_t>(b[i - 1].x());
      const std::uint64_t c0 = reference_code(original[prev], lo, extent);
      const std::uint64_t c1 = reference_code(original[from], lo, extent);
      const Eigen::Vector3d& p0 = original[prev];
      const Eigen::Vector3d& p1 = original[from];
      const bool coordinates_before =
          p0.x() < p1.x() ||
          (p0.x() == p1.x() &&
           (p0.y() < p1.y() ||
            (p0.y() == p1.y() && (p0.z() < p1.z() || (p0.z() == p1.z() && prev < from)))));
      CHECK((c0 < c1 || (c0 == c1 && coordinates_before)));
    }
  }
}

}  // namespace

TEST_CASE("spatial_sort orders by the Morton code, ties by coordinates, and moves b alike",
          "[spatial_order]") {
  core_test::Rng rng(91);
  PointCloud a = core_test::uniform_cloud(rng, 3000, -2.0, 5.0);
  // Ties: copies of earlier points (equal codes), distinct points in one cell (1e-9 apart: a
  // cell is ~3e-6 wide here), and a flat axis (z of a quarter set to 0).
  for (std::size_t i = 0; i < 200; ++i) a[2000 + i] = a[i];
  for (std::size_t i = 0; i < 100; ++i) {
    a[2400 + i] = a[2200 + i] - Eigen::Vector3d(1e-9 * (i % 3), 1e-9 * (i % 2), 1e-9);
  }
  for (std::size_t i = 0; i < a.size(); i += 4) a[i].z() = 0.0;
  check_sorted(a, 1);
  check_sorted(a, 2);
  // Extents of ~7e-305 and ~7e300 (2^21 / extent would overflow for the first: below ~1.2e-302).
  for (double scale : {1e-305, 1e300}) {
    PointCloud scaled = a;
    for (Eigen::Vector3d& p : scaled) p *= scale;
    INFO("scale " << scale);
    check_sorted(scaled, 1);
    check_sorted(scaled, 2);
  }
}

TEST_CASE("spatial_sort leaves a cloud whose extent overflows as it is", "[spatial_order]") {
  const double big = std::numeric_limits<double>::max();
  PointCloud a = {Eigen::Vector3d(big, 0, 0), Eigen::Vector3d(0, 1, 0),
                  Eigen::Vector3d(-big, 0, 0)};
  const PointCloud original = a;
  SpatialSortScratch scratch;
  spatial_sort(&a, nullptr, &scratch);
  CHECK(a == original);
}

TEST_CASE("spatial_sort puts neighbours near each other in memory", "[spatial_order]") {
  // A 32^3 lattice, shuffled: after the sort, consecutive points are mostly lattice neighbours
  // (the Z-curve's jumps are rare), before it almost never.
  core_test::Rng rng(92);
  PointCloud a;
  for (int x = 0; x < 32; ++x)
    for (int y = 0; y < 32; ++y)
      for (int z = 0; z < 32; ++z) a.emplace_back(x, y, z);
  for (std::size_t i = a.size() - 1; i > 0; --i) {
    std::swap(a[i],
              a[static_cast<std::size_t>(core_test::uniform(rng, 0.0, 1.0) * (i + 1)) % (i + 1)]);
  }
  auto adjacent_fraction = [](const PointCloud& c) {
    std::size_t adjacent = 0;
    for (std::size_t i = 1; i < c.size(); ++i) adjacent += (c[i] - c[i - 1]).norm() < 1.5;
    return static_cast<double>(adjacent) / static_cast<double>(c.size() - 1);
  };
  CHECK(adjacent_fraction(a) < 0.01);
  SpatialSortScratch scratch;
  spatial_sort(&a, nullptr, &scratch);
  CHECK(adjacent_fraction(a) > 0.7);
}

TEST_CASE("spatial_sort keeps the order of identical points and of tiny clouds",
          "[spatial_order]") {
  SpatialSortScratch scratch;
  PointCloud same(5, Eigen::Vector3d(1.0, 2.0, 3.0));  // extent 0: one cell
  PointCloud b = index_cloud(5);
  spatial_sort(&same, &b, &scratch);
  for (std::size_t i = 0; i < 5; ++i) CHECK(b[i].x() == static_cast<double>(i));
  PointCloud one(1, Eigen::Vector3d(4.0, 5.0, 6.0));
  spatial_sort(&one, nullptr, &scratch);
  CHECK(one[0] == Eigen::Vector3d(4.0, 5.0, 6.0));
  PointCloud none;
  spatial_sort(&none, nullptr, &scratch);
  CHECK(none.empty());
}

TEST_CASE("drop_duplicates: after spatial_sort, one of each set of equal points, brute force",
          "[spatial_order]") {
  core_test::Rng rng(93);
  PointCloud a = core_test::uniform_cloud(rng, 2000, -1.0, 1.0);
  // Runs of copies (up to 40 of one point, as a scanner's invalid returns at its origin), points
  // 1e-12 from another (distinct, one cell) and a -0 / +0 pair (equal).
  for (std::size_t i = 0; i < 300; ++i) a[1000 + i] = a[i % 7];
  for (std::size_t i = 0; i < 50; ++i) a[1500 + i] = a[i] + Eigen::Vector3d(1e-12, 0, 0);
  a[1600] = Eigen::Vector3d(0.0, 0.5, 0.5);
  a[1601] = Eigen::Vector3d(-0.0, 0.5, 0.5);
  // Copies with a distinct point of their cell between them, in index order (ties by index
  // alone would leave them apart).
  for (std::size_t i = 0; i < 30; ++i) {
    a[1700 + 3 * i] = a[100 + i];
    a[1701 + 3 * i] = a[100 + i] + Eigen::Vector3d(0, 1e-12, 0);
    a[1702 + 3 * i] = a[100 + i];
  }
  // Brute force: the distinct points (== as the function compares).
  std::vector<Eigen::Vector3d> distinct;
  for (const Eigen::Vector3d& p : a) {
    if (std::none_of(distinct.begin(), distinct.end(),
                     [&p](const Eigen::Vector3d& q) { return q == p; })) {
      distinct.push_back(p);
    }
  }
  for (std::size_t shuffle = 0; shuffle < 2; ++shuffle) {
    PointCloud b = a;
    if (shuffle == 1) std::reverse(b.begin(), b.end());
    SpatialSortScratch scratch;
    spatial_sort(&b, nullptr, &scratch);
    const std::size_t removed = ppcr::detail::drop_duplicates(&b);
    CHECK(removed == a.size() - distinct.size());
    REQUIRE(b.size() == distinct.size());
    for (const Eigen::Vector3d& p : distinct) {
      CHECK(std::count(b.begin(), b.end(), p) == 1);
    }
    // The input's order does not change the result (the -0 / +0 pair aside, kept as either).
    if (shuffle == 0) continue;
    PointCloud c = a;
    spatial_sort(&c, nullptr, &scratch);
    ppcr::detail::drop_duplicates(&c);
    for (std::size_t i = 0; i < c.size(); ++i) CHECK(c[i] == b[i]);
  }
  // A cloud of identical points (spatial_sort leaves it as it is): one point.
  PointCloud same(5, Eigen::Vector3d(1.0, 2.0, 3.0));
  CHECK(ppcr::detail::drop_duplicates(&same) == 4);
  CHECK(same.size() == 1);
  PointCloud none;
  CHECK(ppcr::detail::drop_duplicates(&none) == 0);
}
