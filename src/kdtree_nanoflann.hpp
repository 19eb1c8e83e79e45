// kdtree_nanoflann.hpp - nanoflann's side of the k-d tree (private): the dataset adaptor, the
// radius-bounded kNN result set (nanoflann 1.4 has none), the tree type and the few tree members
// the tests read, under the names of the nanoflann at hand. kdtree.cpp takes the leaf size and
// the result set from it and builds its own tree; tests/core/test_kdtree.cpp builds nanoflann's
// own tree and runs its search with it, the references the flat tree and search must equal.
// Built and tested with nanoflann 1.4.3 (Debian 12) and 1.7.1 (Debian 13).
#pragma once

#include <cmath>
#include <cstdint>
#include <limits>
#include <nanoflann.hpp>
#include <vector>

#include "ppcr/abi.hpp"
#include "ppcr/types.hpp"

static_assert(NANOFLANN_VERSION >= 0x140, "ppcr needs nanoflann 1.4 or newer (NANOFLANN_VERSION)");

namespace ppcr {
inline namespace PPCR_ABI_NAMESPACE {
namespace detail {

// nanoflann's dataset adaptor over a std::vector<Eigen::Vector3d>.
struct CloudAdaptor {
  const PointCloud* points = nullptr;
  std::size_t kdtree_get_point_count() const { return points->size(); }
  double kdtree_get_pt(std::uint32_t i, std::size_t dim) const { return (*points)[i][dim]; }
  template <class BBox>
  bool kdtree_get_bbox(BBox&) const {
    return false;  // let nanoflann compute it
  }
};

// nanoflann's leaf_max_size: a node of at most this many points is a leaf (nanoflann 1.4-1.7
// split a larger node so that each side keeps at least one point: leaves hold 1 to
// kLeafMaxSize). By timing (docs/PERFORMANCE.md; gains of a few %
// against the timing noise): leaves of 24 and 32 were faster than 16 with either leaf scan, within
// the noise of each other; with the one-step scan 8 was slower and 12 no faster; the two-step
// scan with 16 was not faster on lidar.
constexpr unsigned kLeafMaxSize = 24;

// The k nearest within a radius: nanoflann's KNN result set with an upper bound. nanoflann
// visits a candidate only if its squared distance is strictly below worstDist(); while fewer
// than k are held, worstDist() is the next double above radius_sq, so a point exactly at the
// radius is kept when the search reaches it (the radius is inclusive). The search's bound on a
// cell's distance is rounded, and can exceed the distance of a point exactly at the radius by an
// ulp and skip its cell: nanoflann's search and the flat one in kdtree.cpp both can. Once k are
// held worstDist() is the k-th best, as in KNN.
class RadiusKnnResultSet {
 public:
  using DistanceType = double;
  using IndexType = std::uint32_t;

  RadiusKnnResultSet(int capacity, double radius_sq, IndexType* indices, double* dist_sq)
      : indices_(indices),
        dist_sq_(dist_sq),
        capacity_(capacity),
        worst_(std::nextafter(radius_sq, std::numeric_limits<double>::infinity())) {}

  int size() const { return count_; }
  bool full() const { return count_ == capacity_; }
  double worstDist() const { return worst_; }

  // Insertion into the sorted prefix; returns true to keep searching.
  bool addPoint(double dist_sq, IndexType index) {
    if (dist_sq < worst_) insert(dist_sq, index);
    return true;
  }

  // nanoflann >= 1.6 sorts a result set after a search asked to sort: this one is kept sorted.
  void sort() {}

  // addPoint for a caller that has checked dist_sq < worstDist() (the flat search's leaf loop).
  void insert(double dist_sq, IndexType index) {
    int i = (count_ < capacity_) ? count_ : capacity_ - 1;
    while (i > 0 && dist_sq_[i - 1] > dist_sq) {
      dist_sq_[i] = dist_sq_[i - 1];
      indices_[i] = indices_[i - 1];
      --i;
    }
    dist_sq_[i] = dist_sq;
    indices_[i] = index;
    if (count_ < capacity_) ++count_;
    if (count_ == capacity_) worst_ = dist_sq_[capacity_ - 1];
  }

 private:
  IndexType* indices_;
  double* dist_sq_;
  int capacity_;
  int count_ = 0;
  double worst_;  // the bound below until full, then the k-th best
};

using Tree = nanoflann::KDTreeSingleIndexAdaptor<
    nanoflann::L2_Simple_Adaptor<double, CloudAdaptor, double, std::uint32_t>, CloudAdaptor, 3,
    std::uint32_t>;

// nanoflann 1.5 renamed the tree's members (root_node, vAcc, root_bbox gained a trailing
// underscore) and SearchParams (now SearchParameters, without the ignored `checks`): so read in
// 1.5.1's and 1.7.1's headers, against 1.4.3's.
#if NANOFLANN_VERSION >= 0x150
inline const auto* tree_root(const Tree& tree) { return tree.root_node_; }
inline const std::vector<std::uint32_t>& tree_leaf_order(const Tree& tree) { return tree.vAcc_; }
inline const auto& tree_bounding_box(const Tree& tree) { return tree.root_bbox_; }
/// An exact search (eps 0) whose result is sorted by distance.
inline nanoflann::SearchParameters exact_sorted_search() {
  return nanoflann::SearchParameters(0.0f, true);
}
#else
inline const auto* tree_root(const Tree& tree) { return tree.root_node; }
inline const std::vector<std::uint32_t>& tree_leaf_order(const Tree& tree) { return tree.vAcc; }
inline const auto& tree_bounding_box(const Tree& tree) { return tree.root_bbox; }
/// An exact search (eps 0) whose result is sorted by distance.
inline nanoflann::SearchParams exact_sorted_search() {
  return nanoflann::SearchParams(0, 0.0f, true);
}
#endif

}  // namespace detail
}  // namespace PPCR_ABI_NAMESPACE
}  // namespace ppcr
