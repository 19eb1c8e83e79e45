// nanoflann_reference.hpp - nanoflann's own k-d tree over a cloud, the reference that
// test_kdtree.cpp checks ppcr's tree (src/kdtree.cpp) against: the dataset adaptor, the tree type
// (leaves of kLeafMaxSize points, as ppcr's) and the few tree members the test reads, under the
// names of the nanoflann at hand. Its search runs with ppcr's result set (radius_knn_result.hpp).
// Tested with nanoflann 1.4.3 (Debian 12) and 1.7.1 (Debian 13); the library does not use
// nanoflann.
#pragma once

#include <cstdint>
#include <nanoflann.hpp>
#include <vector>

#include "kdtree.hpp"
#include "ppcr/abi.hpp"
#include "ppcr/types.hpp"
#include "radius_knn_result.hpp"

static_assert(NANOFLANN_VERSION >= 0x140, "the reference needs nanoflann 1.4 or newer");

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
