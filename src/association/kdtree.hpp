// kdtree.hpp - a k-d tree over a cloud (the target; the source too for its normals), the
// radius-limited k-nearest-neighbour query, and that query seeded by points already known.
//
// nanoflann's tree and search (kdtree.cpp, the one file that includes nanoflann) behind an
// interface that throws nothing. Distances are SQUARED, as nanoflann's L2 metric: every distance
// here is squared and says so.
#pragma once

#include <cstdint>
#include <memory>
#include <vector>

#include "ppcr/abi.hpp"
#include "ppcr/status.hpp"
#include "ppcr/types.hpp"

namespace ppcr {
inline namespace PPCR_ABI_NAMESPACE {
namespace detail {

// A node of at most this many points is a leaf (nanoflann's leaf_max_size). By timing
// (docs/PERFORMANCE.md), leaves of 24 and 32 were faster than 16 and 8.
constexpr unsigned kLeafMaxSize = 24;

/// |a - b|^2 as nanoflann's L2_Simple_Adaptor computes it (the terms summed in axis order), so that
/// a query's distances and a cached candidate's re-ranked here (neighbour_cache.cpp) are alike.
/// Our targets are compiled with -ffp-contract=off (CMakeLists.txt), so both round as written.
/// Tests with == on the build at hand: tests/core/test_kdtree.cpp and test_neighbour_cache.cpp.
inline double squared_distance(const double* a, double bx, double by, double bz) {
  const double dx = a[0] - bx, dy = a[1] - by, dz = a[2] - bz;
  return dx * dx + dy * dy + dz * dz;
}
inline double squared_distance(const double* a, const double* b) {
  return squared_distance(a, b[0], b[1], b[2]);
}

class KdTree {
 public:
  KdTree();
  ~KdTree();
  KdTree(KdTree&&) noexcept;
  KdTree& operator=(KdTree&&) noexcept;

  /// Indexes a copy of points (24 B per point, plus 8 B of indices and nanoflann's nodes). At most
  /// 2^31 - 1 points; out of memory is a status, not an exception.
  Status build(const PointCloud& points);

  /// Up to k indices of the points nearest to query with squared distance <= radius_sq
  /// (inclusive, but a point exactly at the radius can be missed when the rounded distance to
  /// its cell exceeds radius_sq: radius_knn_result.hpp), sorted by increasing distance; writes
  /// indices[0..n), dist_sq[0..n) and returns n. Allocation-free. Thread-safe (const).
  int radius_knn(const Eigen::Vector3d& query, int k, double radius_sq, std::uint32_t* indices,
                 double* dist_sq) const;

  std::size_t size() const;

  /// The indexed points' indices in the tree's leaf order (spatially coherent: queries made in
  /// this order reuse the same nodes and leaves).
  const std::vector<std::uint32_t>& leaf_order() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

/// Seeded queries. Points already known near the query (its list from an earlier query, or the
/// previous query point's neighbours) bound its k-th nearest: k distinct indexed points lie within
/// max_sq, the largest of their squared distances to the query (by squared_distance(), the
/// search's own expression), so its k-th nearest does too. A search bounded by that finds the same
/// k neighbours in the same order, ties included: it visits the cells in the same order, skips only
/// cells beyond the bound (which hold none of the k) and, once it holds k points, prunes by its
/// k-th as an unbounded search does (neighbour_cache.hpp, "Seeded queries"). The gain: it prunes
/// from its first leaf on, not only once it holds k points.
///
/// The bound of a seeded query: max_sq widened by 1e-9 of itself. The margin covers the rounding
/// between the two distance computations: a point's distance is computed as its seed's was, but
/// the search skips a cell by its own rounded distance to the query (built up axis by axis), which
/// can exceed the distance of a point inside it (radius_knn_result.hpp) and so skip a point at
/// exactly the bound. Should rounding beyond the margin skip one, the bounded query finds fewer
/// than k and seeded_radius_knn repeats it.
inline double seed_bound_sq(double max_sq) { return max_sq * (1.0 + 1e-9); }

/// seed_bound_sq() of the largest squared distance from query to points[seeds[0..n)] (n distinct
/// indexed points; points is the cloud the tree was built over).
inline double seed_bound_sq(const Eigen::Vector3d& query, const PointCloud& points,
                            const std::uint32_t* seeds, int n) {
  double max_sq = 0.0;
  for (int m = 0; m < n; ++m) {
    const double d = squared_distance(query.data(), points[seeds[m]].data());
    max_sq = d > max_sq ? d : max_sq;
  }
  return seed_bound_sq(max_sq);
}

/// How a seeded_radius_knn() query went.
enum class SeedOutcome : std::uint8_t {
  kUnseeded,  // !(seed_sq < radius_sq) (>=, or NaN): bounded by radius_sq alone (radius_knn)
  kSeeded,    // bounded by seed_sq, and that found k (found >= k)
  kRepeated,  // bounded by seed_sq, found fewer than k, and repeated with radius_sq alone
};

/// The result of a seeded_radius_knn() query.
struct SeededKnn {
  int found = 0;  // neighbours written, as radius_knn returns
  SeedOutcome outcome = SeedOutcome::kUnseeded;
};

/// tree.radius_knn(query, k, radius_sq, indices, dist_sq), seeded: the query is bounded by
/// min(seed_sq, radius_sq) and, when the seed bounded it (seed_sq < radius_sq) and it found fewer
/// than k, repeated with radius_sq alone. With seed_sq the seed_bound_sq() of k points, the result
/// is radius_knn's with radius_sq (above); a seed_sq >= radius_sq (+infinity: no seed) makes it
/// radius_knn itself. Allocation-free. Thread-safe (const).
inline SeededKnn seeded_radius_knn(const KdTree& tree, const Eigen::Vector3d& query, int k,
                                   double seed_sq, double radius_sq, std::uint32_t* indices,
                                   double* dist_sq) {
  if (!(seed_sq < radius_sq)) {
    return {tree.radius_knn(query, k, radius_sq, indices, dist_sq), SeedOutcome::kUnseeded};
  }
  const int found = tree.radius_knn(query, k, seed_sq, indices, dist_sq);
  if (found >= k) return {found, SeedOutcome::kSeeded};
  return {tree.radius_knn(query, k, radius_sq, indices, dist_sq), SeedOutcome::kRepeated};
}

}  // namespace detail
}  // namespace PPCR_ABI_NAMESPACE
}  // namespace ppcr
