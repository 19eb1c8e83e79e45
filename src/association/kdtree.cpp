// kdtree.cpp - the k-d tree: nanoflann's tree and its search, with our result set
// (radius_knn_result.hpp). The one source file of the core that includes nanoflann: nanoflann 1.4
// allocates with operator new and throws std::bad_alloc (and std::runtime_error for a search of a
// tree never built, which build() rules out), so this file alone is compiled with -fexceptions
// (CMakeLists.txt) and turns those into a Status here; nothing is thrown across its interface.
#include "association/kdtree.hpp"

#include <nanoflann.hpp>
#include <new>
#include <string>

#include "association/radius_knn_result.hpp"

static_assert(NANOFLANN_VERSION >= 0x140, "ppcr needs nanoflann 1.4 or newer");

namespace ppcr {
inline namespace PPCR_ABI_NAMESPACE {
namespace detail {
namespace {

// nanoflann's dataset adaptor over the tree's own copy of the points.
struct CloudAdaptor {
  const PointCloud* points = nullptr;
  std::size_t kdtree_get_point_count() const { return points->size(); }
  double kdtree_get_pt(std::uint32_t i, std::size_t axis) const { return (*points)[i][axis]; }
  template <class Box>
  bool kdtree_get_bbox(Box&) const {
    return false;  // nanoflann computes it
  }
};

// L2_Simple_Adaptor sums (q[a] - p[a])^2 over a = 0, 1, 2 from 0: bit for bit squared_distance()
// (kdtree.hpp), which the callers that re-rank cached candidates use.
using NanoflannTree = nanoflann::KDTreeSingleIndexAdaptor<
    nanoflann::L2_Simple_Adaptor<double, CloudAdaptor, double, std::uint32_t>, CloudAdaptor, 3,
    std::uint32_t>;

// nanoflann 1.5 renamed SearchParams to SearchParameters (without the ignored `checks`) and the
// tree's members (vAcc to vAcc_).
#if NANOFLANN_VERSION >= 0x150
inline nanoflann::SearchParameters exact_sorted_search() {
  return nanoflann::SearchParameters(0.0f, true);
}
inline std::vector<std::uint32_t>& leaf_order_of(NanoflannTree& t) { return t.vAcc_; }
#else
inline nanoflann::SearchParams exact_sorted_search() {
  return nanoflann::SearchParams(0, 0.0f, true);
}
inline std::vector<std::uint32_t>& leaf_order_of(NanoflannTree& t) { return t.vAcc; }
#endif

}  // namespace

// The tree's points are stored in its leaf order. nanoflann's tree holds, besides its nodes (split
// planes and ranges of positions), the leaf order: the position -> point index array it builds.
// Once built, the copy of the points is permuted into that order and the array set to the
// identity: the search visits the same positions in the same order and computes the same
// distances, but reads the points of a leaf contiguously instead of gathering them from the whole
// cloud (on a voxel-filtered cloud, whose order is the voxel grid's, the gathers cost 30 % of a
// registration on the bunny set: docs/PERFORMANCE.md). A result's positions are mapped back to
// the cloud's indices through `order`. tests/core/test_kdtree.cpp checks the results against
// brute force and against nanoflann's tree over the unpermuted cloud.
struct KdTree::Impl {
  PointCloud points;  // the indexed copy, in leaf order (nanoflann reads it through the adaptor)
  CloudAdaptor adaptor;
  std::unique_ptr<NanoflannTree> tree;
  std::vector<std::uint32_t> order;  // position in the leaf order -> index in the cloud
};

KdTree::KdTree() : impl_(new Impl) {}
KdTree::~KdTree() = default;
KdTree::KdTree(KdTree&&) noexcept = default;
KdTree& KdTree::operator=(KdTree&&) noexcept = default;

Status KdTree::build(const PointCloud& points) {
  if (points.size() > 0x7fffffffu) {
    return Status(StatusCode::kInvalidArgument,
                  "the cloud has " + std::to_string(points.size()) +
                      " points; the k-d tree indexes at most 2^31 - 1");
  }
  Impl& m = *impl_;
  m.tree.reset();
  m.points.clear();
  m.order.clear();
  if (points.empty()) return Status::Ok();
  try {
    m.points = points;
    m.adaptor.points = &m.points;
    m.tree.reset(
        new NanoflannTree(3, m.adaptor, nanoflann::KDTreeSingleIndexAdaptorParams(kLeafMaxSize)));
    std::vector<std::uint32_t>& positions = leaf_order_of(*m.tree);
    m.order = positions;
    for (std::size_t i = 0; i < positions.size(); ++i) {
      m.points[i] = points[m.order[i]];
      positions[i] = static_cast<std::uint32_t>(i);
    }
  } catch (const std::bad_alloc&) {
    m.tree.reset();
    PointCloud().swap(m.points);
    std::vector<std::uint32_t>().swap(m.order);
    return Status(StatusCode::kInvalidArgument, "out of memory building the k-d tree over " +
                                                    std::to_string(points.size()) + " points");
  }
  return Status::Ok();
}

int KdTree::radius_knn(const Eigen::Vector3d& query, int k, double radius_sq,
                       std::uint32_t* indices, double* dist_sq) const {
  const Impl& m = *impl_;
  if (!m.tree || k < 1) return 0;
  RadiusKnnResultSet result(k, radius_sq, indices, dist_sq);
  m.tree->findNeighbors(result, query.data(), exact_sorted_search());
  const int found = result.size();
  for (int i = 0; i < found; ++i) indices[i] = m.order[indices[i]];
  return found;
}

std::size_t KdTree::size() const { return impl_->points.size(); }

const std::vector<std::uint32_t>& KdTree::leaf_order() const { return impl_->order; }

}  // namespace detail
}  // namespace PPCR_ABI_NAMESPACE
}  // namespace ppcr
