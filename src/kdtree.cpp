// kdtree.cpp - the k-d tree: built by nanoflann (kdtree_nanoflann.hpp), searched on a flat copy.
#include "kdtree.hpp"

#include <algorithm>
#include <new>
#include <string>
#include <utility>
#include <vector>

#include "kdtree_nanoflann.hpp"

namespace ppcr {
inline namespace PPCR_ABI_NAMESPACE {
namespace detail {
namespace {

// nanoflann's tree, flattened for the search: nodes in depth-first order (a split node's first
// child follows it; `second` indexes the other), and the points copied in the tree's leaf order,
// x, y and z apart, so that a leaf scans contiguous coordinates (its distances are vectorisable)
// instead of gathering through nanoflann's index array. The search below is nanoflann's searchLevel
// (same bounds, same visiting order, hence the same result) on this layout.
struct FlatNode {
  // Split node: the first child's upper and the second child's lower extent along `axis`
  // (nanoflann's divlow, divhigh).
  double low, high;
  std::uint32_t second;  // split node: the second child; leaf: its first point (leaf order)
  std::uint32_t axis;    // split node: 0..2; leaf: kLeaf | one past its last point
};
constexpr std::uint32_t kLeaf = 0x80000000u;
// Points a leaf's distances are computed for at once (on the stack). A leaf holds at most
// kLeafMaxSize points (kdtree_nanoflann.hpp), so it is one chunk; the loop over chunks is for
// safety only (a larger leaf would be scanned in several, not overflow the arrays), and no test
// reaches a second chunk.
constexpr std::uint32_t kChunk = 32;
static_assert(kLeafMaxSize <= kChunk, "a leaf of nanoflann's tree is scanned in one chunk");

}  // namespace

struct KdTree::Impl {
  Buffer<FlatNode> nodes;
  // Point i of the n in the leaf order at (xyz[i], xyz[n + i], xyz[2 n + i]).
  Buffer<double> xyz;
  Buffer<std::uint32_t> index;                             // its index in the cloud
  double box_low[3] = {0, 0, 0}, box_high[3] = {0, 0, 0};  // the cloud's bounding box

  // Nodes of nanoflann's (sub)tree at node: flatten's count, so that `nodes` is sized once.
  template <class Node>
  static std::size_t count_nodes(const Node* node) {
    if (node->child1 == nullptr && node->child2 == nullptr) return 1;
    return 1 + count_nodes(node->child1) + count_nodes(node->child2);
  }

  template <class Node>
  std::uint32_t flatten(const Node* node) {
    const std::uint32_t me = static_cast<std::uint32_t>(nodes.size());
    nodes.push_back(FlatNode{0.0, 0.0, 0, 0});
    if (node->child1 == nullptr && node->child2 == nullptr) {
      nodes[me].second = static_cast<std::uint32_t>(node->node_type.lr.left);
      nodes[me].axis = kLeaf | static_cast<std::uint32_t>(node->node_type.lr.right);
      return me;
    }
    nodes[me].low = node->node_type.sub.divlow;
    nodes[me].high = node->node_type.sub.divhigh;
    nodes[me].axis = static_cast<std::uint32_t>(node->node_type.sub.divfeat);
    flatten(node->child1);
    const std::uint32_t second = flatten(node->child2);
    nodes[me].second = second;
    return me;
  }

  // nanoflann's searchLevel: min_dist_sq is the squared distance from the query to the node's
  // cell as far as the splits above tell (per-axis terms in axis_dist_sq), and a subtree is
  // visited only if that is within the result set's current bound.
  void search(const FlatNode* node, const double* q, double min_dist_sq, double* axis_dist_sq,
              RadiusKnnResultSet& result) const {
    if (node->axis & kLeaf) {
      // nanoflann's leaf loop compares each point with the bound at the leaf's start, and
      // addPoint re-checks it against the current one. Here the first check is done for the
      // whole leaf at once, in two branch-free steps: the distances of the leaf's points
      // (squared_distance on the coordinate arrays; vectorisable, GCC -O3: two lanes with
      // SSE2), then the list of the points nearer than the bound at the chunk's start, in leaf
      // order. Then each of those, checked against the current bound, is inserted. The bound
      // only shrinks: the same points in the same order as nanoflann's loop.
      const std::uint32_t end = node->axis & ~kLeaf;
      const std::size_t n = index.size();
      const double* x = xyz.data();
      const double* y = x + n;
      const double* z = y + n;
      for (std::uint32_t begin = node->second; begin < end; begin += kChunk) {
        const std::uint32_t count = std::min(kChunk, end - begin);
        double d[kChunk];
        for (std::uint32_t i = 0; i < count; ++i) {
          d[i] = squared_distance(q, x[begin + i], y[begin + i], z[begin + i]);
        }
        double worst = result.worstDist();
        std::uint32_t below[kChunk];
        std::uint32_t below_count = 0;
        for (std::uint32_t i = 0; i < count; ++i) {
          below[below_count] = i;
          below_count += d[i] < worst;
        }
        for (std::uint32_t c = 0; c < below_count; ++c) {
          const std::uint32_t i = below[c];
          if (d[i] < worst) {
            result.insert(d[i], index[begin + i]);
            worst = result.worstDist();
          }
        }
      }
      return;
    }
    const std::uint32_t axis = node->axis;
    const double v = q[axis];
    const FlatNode* first = node + 1;
    const FlatNode* other = &nodes[node->second];
    double cut_sq;  // squared distance to the other child's extent along the axis
    if ((v - node->low) + (v - node->high) < 0.0) {
      cut_sq = (v - node->high) * (v - node->high);
    } else {
      std::swap(first, other);
      cut_sq = (v - node->low) * (v - node->low);
    }
    search(first, q, min_dist_sq, axis_dist_sq, result);
    const double saved = axis_dist_sq[axis];
    // As nanoflann: (min + cut) - saved, in that order (another order rounds differently and
    // can prune a cell whose nearest point lies exactly at the radius).
    min_dist_sq = min_dist_sq + cut_sq - saved;
    axis_dist_sq[axis] = cut_sq;
    if (min_dist_sq <= result.worstDist()) search(other, q, min_dist_sq, axis_dist_sq, result);
    axis_dist_sq[axis] = saved;
  }
};

KdTree::KdTree() : impl_(new Impl) {}
KdTree::~KdTree() = default;
KdTree::KdTree(KdTree&&) noexcept = default;
KdTree& KdTree::operator=(KdTree&&) noexcept = default;

Status KdTree::build(const PointCloud& points) {
  // Leaf ends carry the kLeaf bit, so point counts (and node indices, < 2 x points) stay below it.
  if (points.size() >= kLeaf) {
    return Status(StatusCode::kInvalidArgument,
                  "the cloud has " + std::to_string(points.size()) +
                      " points; the k-d tree indexes at most 2^31 - 1");
  }
  Impl& m = *impl_;
  m = Impl();
  if (points.empty()) return Status::Ok();
  try {
    // nanoflann builds the tree (leaves of at most kLeafMaxSize points); its nodes are then
    // copied into the flat layout and its own structure is freed.
    const CloudAdaptor adaptor{&points};
    const Tree tree(3, adaptor, nanoflann::KDTreeSingleIndexAdaptorParams(kLeafMaxSize));
    const auto& box = tree_bounding_box(tree);
    for (int a = 0; a < 3; ++a) {
      m.box_low[a] = box[static_cast<std::size_t>(a)].low;
      m.box_high[a] = box[static_cast<std::size_t>(a)].high;
    }
    const std::vector<std::uint32_t>& leaf_order = tree_leaf_order(tree);
    m.index.assign(leaf_order.begin(), leaf_order.end());
    const std::size_t n = m.index.size();
    m.xyz.resize(3 * n);
    for (std::size_t i = 0; i < n; ++i) {
      for (int a = 0; a < 3; ++a)
        m.xyz[static_cast<std::size_t>(a) * n + i] = points[m.index[i]][a];
    }
    m.nodes.reserve(Impl::count_nodes(tree_root(tree)));  // one allocation, no growth
    m.flatten(tree_root(tree));
  } catch (const std::bad_alloc&) {
    m = Impl();
    return Status(StatusCode::kInvalidArgument, "out of memory building the k-d tree over " +
                                                    std::to_string(points.size()) + " points");
  }
  return Status::Ok();
}

int KdTree::radius_knn(const Eigen::Vector3d& query, int k, double radius_sq,
                       std::uint32_t* indices, double* dist_sq) const {
  const Impl& m = *impl_;
  if (m.nodes.empty() || k < 1) return 0;
  RadiusKnnResultSet result(k, radius_sq, indices, dist_sq);
  // nanoflann's computeInitialDistances: the query's squared distance to the bounding box.
  double axis_dist_sq[3];
  double min_dist_sq = 0.0;
  for (int a = 0; a < 3; ++a) {
    const double below = query[a] - m.box_low[a], above = query[a] - m.box_high[a];
    axis_dist_sq[a] = below < 0.0 ? below * below : (above > 0.0 ? above * above : 0.0);
    min_dist_sq += axis_dist_sq[a];
  }
  m.search(m.nodes.data(), query.data(), min_dist_sq, axis_dist_sq, result);
  return result.size();
}

std::size_t KdTree::size() const { return impl_->index.size(); }

const Buffer<std::uint32_t>& KdTree::leaf_order() const { return impl_->index; }

}  // namespace detail
}  // namespace PPCR_ABI_NAMESPACE
}  // namespace ppcr
