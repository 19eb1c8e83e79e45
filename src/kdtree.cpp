// kdtree.cpp - the k-d tree: nanoflann's tree, built and searched on a flat layout of our own.
#include "kdtree.hpp"

#include <algorithm>
#include <array>
#include <new>
#include <string>
#include <utility>
#include <vector>

#include "parallel.hpp"
#include "radius_knn_result.hpp"

namespace ppcr {
inline namespace PPCR_ABI_NAMESPACE {
namespace detail {
namespace {

// nanoflann's tree in a flat layout: nodes in depth-first order (a split node's first child
// follows it; `second` indexes the other), and the points copied in the tree's leaf order, x, y
// and z apart, so that a leaf scans contiguous coordinates (its distances are vectorisable)
// instead of gathering through an index array. TreeBuilder builds it as nanoflann 1.4 builds its
// own (the same splits, hence the same tree: tests/core/test_kdtree.cpp), its subtrees on the
// threads of `parallel` (ParallelBuild); the search below is nanoflann's searchLevel (same bounds,
// same visiting order, hence the same result) on this layout.
struct FlatNode {
  // Split node: the first child's upper and the second child's lower extent along `axis`
  // (nanoflann's divlow, divhigh).
  double low, high;
  std::uint32_t second;  // split node: the second child; leaf: its first point (leaf order)
  std::uint32_t axis;    // split node: 0..2; leaf: kLeaf | one past its last point
};
constexpr std::uint32_t kLeaf = 0x80000000u;
// Points a leaf's distances are computed for at once (on the stack). A leaf holds at most
// kLeafMaxSize points (kdtree.hpp), so it is one chunk; the loop over chunks is for
// safety only (a larger leaf would be scanned in several, not overflow the arrays), and no test
// reaches a second chunk.
constexpr std::uint32_t kChunk = 32;
static_assert(kLeafMaxSize <= kChunk, "a leaf of nanoflann's tree is scanned in one chunk");

// One axis of a bounding box.
struct Interval {
  double low, high;
};
using Box = std::array<Interval, 3>;

// nanoflann 1.4's build (KDTreeBaseClass::divideTree, middleSplit_, planeSplit), on the flat
// layout: the tree over points[index[left..right)), reordering that range of the index array in
// place. Two ranges that do not overlap can be built at once.
class TreeBuilder {
 public:
  TreeBuilder(const PointCloud& points, std::uint32_t* index) : points_(points), index_(index) {}

  struct Split {
    std::size_t size;  // points in the first child
    std::uint32_t axis;
    double cut;  // along axis: the first child's upper bound, the second's lower
    // The children's cells: `cell` cut at `cut` along `axis`.
    void cells(const Box& cell, Box* first, Box* second) const {
      *first = *second = cell;
      (*first)[axis].high = cut;
      (*second)[axis].low = cut;
    }
  };

  // divideTree: appends the subtree over [left, right) to *nodes, depth first, `second` counted
  // from the vector's start; *box (the cell, on entry) becomes the points' bounding box.
  void build(std::size_t left, std::size_t right, Box* box, Buffer<FlatNode>* nodes) const {
    const std::size_t me = nodes->size();
    nodes->push_back(FlatNode{0.0, 0.0, 0, 0});
    if (right - left <= kLeafMaxSize) {
      (*nodes)[me].second = static_cast<std::uint32_t>(left);
      (*nodes)[me].axis = kLeaf | static_cast<std::uint32_t>(right);
      bounding_box(left, right, box);
      return;
    }
    const Split s = split(left, right - left, *box);
    Box first, second;
    s.cells(*box, &first, &second);
    build(left, left + s.size, &first, nodes);
    const std::size_t other = nodes->size();
    build(left + s.size, right, &second, nodes);
    join(s.axis, first, second, static_cast<std::uint32_t>(other), &(*nodes)[me], box);
  }

  // middleSplit_: among the axes whose cell side is within 1e-5 of the longest, the one along
  // which the points spread most (the first of equals); cut at the cell's middle, clamped to the
  // points' range; the points partitioned at the cut (planeSplit), the first child taking those
  // below it, then as many equal to it as balance the two. (nanoflann scans the chosen axis'
  // range again; the scan of the loop gives the same values.)
  Split split(std::size_t left, std::size_t count, const Box& box) const {
    const double eps = 0.00001;
    double max_span = box[0].high - box[0].low;
    for (std::uint32_t a = 1; a < 3; ++a) max_span = std::max(max_span, box[a].high - box[a].low);
    double max_spread = -1.0;
    std::uint32_t axis = 0;
    double lo = 0.0, hi = 0.0;  // the points' range along axis
    for (std::uint32_t a = 0; a < 3; ++a) {
      if (!(box[a].high - box[a].low > (1 - eps) * max_span)) continue;
      double a_lo, a_hi;
      min_max(left, count, a, &a_lo, &a_hi);
      if (a_hi - a_lo > max_spread) {
        axis = a;
        max_spread = a_hi - a_lo;
        lo = a_lo;
        hi = a_hi;
      }
    }
    // A cell of no extent (every point equal) has no candidate axis: axis 0, scanned here.
    if (max_spread < 0.0) min_max(left, count, axis, &lo, &hi);
    const double middle = (box[axis].low + box[axis].high) / 2;
    const double cut = middle < lo ? lo : (middle > hi ? hi : middle);
    std::size_t below, not_above;
    plane_split(left, count, axis, cut, &below, &not_above);
    const std::size_t half = count / 2;
    return Split{below > half ? below : (not_above < half ? not_above : half), axis, cut};
  }

  // A split node's bounds along its axis (the children's boxes, now their points' bounding
  // boxes: nanoflann's divlow, divhigh), and its box, the union of theirs.
  static void join(std::uint32_t axis, const Box& first, const Box& second, std::uint32_t other,
                   FlatNode* node, Box* box) {
    *node = FlatNode{first[axis].high, second[axis].low, other, axis};
    for (std::size_t a = 0; a < 3; ++a) {
      (*box)[a].low = std::min(first[a].low, second[a].low);
      (*box)[a].high = std::max(first[a].high, second[a].high);
    }
  }

  // The bounding box of points[index[left..right)) (a leaf's; nanoflann's computeBoundingBox
  // over the whole cloud).
  void bounding_box(std::size_t left, std::size_t right, Box* box) const {
    for (std::uint32_t a = 0; a < 3; ++a) (*box)[a].low = (*box)[a].high = coordinate(left, a);
    for (std::size_t k = left + 1; k < right; ++k) {
      for (std::uint32_t a = 0; a < 3; ++a) {
        const double v = coordinate(k, a);
        if ((*box)[a].low > v) (*box)[a].low = v;
        if ((*box)[a].high < v) (*box)[a].high = v;
      }
    }
  }

 private:
  double coordinate(std::size_t k, std::uint32_t axis) const { return points_[index_[k]][axis]; }

  // computeMinMax.
  void min_max(std::size_t left, std::size_t count, std::uint32_t axis, double* lo,
               double* hi) const {
    *lo = *hi = coordinate(left, axis);
    for (std::size_t k = 1; k < count; ++k) {
      const double v = coordinate(left + k, axis);
      if (v < *lo) *lo = v;
      if (v > *hi) *hi = v;
    }
  }

  // planeSplit: reorders index[left..left + count) into the points below cut, [0, *below), equal
  // to it, [*below, *not_above), and above it, swapping from both ends as nanoflann does (the
  // order within each part is its).
  void plane_split(std::size_t left, std::size_t count, std::uint32_t axis, double cut,
                   std::size_t* below, std::size_t* not_above) const {
    std::uint32_t* ind = index_ + left;
    auto at = [&](std::size_t k) { return points_[ind[k]][axis]; };
    std::size_t l = 0, r = count - 1;
    for (;;) {
      while (l <= r && at(l) < cut) ++l;
      while (r != 0 && l <= r && at(r) >= cut) --r;
      if (l > r || r == 0) break;
      std::swap(ind[l], ind[r]);
      ++l;
      --r;
    }
    *below = l;
    r = count - 1;
    for (;;) {
      while (l <= r && at(l) <= cut) ++l;
      while (r != 0 && l <= r && at(r) > cut) --r;
      if (l > r || r == 0) break;
      std::swap(ind[l], ind[r]);
      ++l;
      --r;
    }
    *not_above = l;
  }

  const PointCloud& points_;
  std::uint32_t* index_;
};

// The tree built on several threads: the nodes holding more points than a grain are split on the
// calling thread, then the subtrees below them are built at once (OpenMP hands them out as
// threads free up: middle splits leave them unequal), then every node is laid out depth first.
// The same splits as TreeBuilder::build alone: each partitions its own range of the index array.
class ParallelBuild {
 public:
  ParallelBuild(const TreeBuilder& builder, std::size_t grain) : builder_(builder), grain_(grain) {}

  // The tree over [0, n) into *nodes; *box, the cell on entry, becomes the bounding box.
  void run(std::size_t n, Box* box, const Parallel* parallel, Buffer<FlatNode>* nodes) {
    plan(0, n, *box);
    parallel_for(parallel, static_cast<std::ptrdiff_t>(subtrees_.size()), [&](std::ptrdiff_t i) {
      Top& t = tops_[static_cast<std::size_t>(subtrees_[static_cast<std::size_t>(i)])];
      builder_.build(t.left, t.right, &t.box, &t.nodes);
    });
    std::size_t count = tops_.size() - subtrees_.size();
    for (int t : subtrees_) count += tops_[static_cast<std::size_t>(t)].nodes.size();
    nodes->clear();
    nodes->reserve(count);
    emit(0, nodes);
    *box = tops_[0].box;
  }

 private:
  // A node above the subtrees (a split: first, second >= 0), or one of them.
  struct Top {
    std::size_t left, right;
    Box box;  // its cell, then its points' bounding box
    int first = -1, second = -1;
    std::uint32_t axis = 0;
    Buffer<FlatNode> nodes;  // a subtree's, `second` counted from its own start
  };

  // The splits of the nodes above the grain, in the order TreeBuilder::build makes them.
  int plan(std::size_t left, std::size_t right, const Box& cell) {
    const int me = static_cast<int>(tops_.size());
    tops_.push_back(Top{left, right, cell, -1, -1, 0, {}});
    if (right - left <= grain_ || right - left <= kLeafMaxSize) {
      subtrees_.push_back(me);
      return me;
    }
    const TreeBuilder::Split s = builder_.split(left, right - left, cell);
    Box first, second;
    s.cells(cell, &first, &second);
    const int f = plan(left, left + s.size, first);
    const int g = plan(left + s.size, right, second);
    Top& t = tops_[static_cast<std::size_t>(me)];
    t.first = f;
    t.second = g;
    t.axis = s.axis;
    return me;
  }

  // Lays out top t's nodes depth first (a subtree's shifted to where they land) and joins the
  // splits' boxes bottom-up.
  void emit(int t, Buffer<FlatNode>* nodes) {
    Top& top = tops_[static_cast<std::size_t>(t)];
    if (top.first < 0) {
      const std::uint32_t offset = static_cast<std::uint32_t>(nodes->size());
      for (FlatNode node : top.nodes) {
        if (!(node.axis & kLeaf)) node.second += offset;
        nodes->push_back(node);
      }
      Buffer<FlatNode>().swap(top.nodes);
      return;
    }
    const std::size_t me = nodes->size();
    nodes->push_back(FlatNode{0.0, 0.0, 0, 0});
    emit(top.first, nodes);
    const std::uint32_t other = static_cast<std::uint32_t>(nodes->size());
    emit(top.second, nodes);
    const Top& first = tops_[static_cast<std::size_t>(top.first)];
    const Top& second = tops_[static_cast<std::size_t>(top.second)];
    TreeBuilder::join(top.axis, first.box, second.box, other, &(*nodes)[me], &top.box);
  }

  const TreeBuilder& builder_;
  std::size_t grain_;
  std::vector<Top> tops_;
  std::vector<int> subtrees_;
};

}  // namespace

struct KdTree::Impl {
  Buffer<FlatNode> nodes;
  // Point i of the n in the leaf order at (xyz[i], xyz[n + i], xyz[2 n + i]).
  Buffer<double> xyz;
  Buffer<std::uint32_t> index;                             // its index in the cloud
  double box_low[3] = {0, 0, 0}, box_high[3] = {0, 0, 0};  // the cloud's bounding box

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

Status KdTree::build(const PointCloud& points, const Parallel* parallel) {
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
    const std::size_t n = points.size();
    m.index.resize(n);
    for (std::size_t i = 0; i < n; ++i) m.index[i] = static_cast<std::uint32_t>(i);
    const TreeBuilder builder(points, m.index.data());
    Box box;
    builder.bounding_box(0, n, &box);  // the index is still the identity
    if (parallel == nullptr || parallel->threads() < 2 || n <= kLeafMaxSize) {
      builder.build(0, n, &box, &m.nodes);
      m.nodes.shrink_to_fit();  // grown by doubling
    } else {
      // Subtrees of about a sixteenth of the points for two threads, handed out as threads free.
      const std::size_t grain = n / (8 * static_cast<std::size_t>(parallel->threads()));
      ParallelBuild(builder, grain).run(n, &box, parallel, &m.nodes);
    }
    for (std::size_t a = 0; a < 3; ++a) {
      m.box_low[a] = box[a].low;
      m.box_high[a] = box[a].high;
    }
    m.xyz.resize(3 * n);
    parallel_for(parallel, static_cast<std::ptrdiff_t>(n), [&](std::ptrdiff_t j) {
      const std::size_t i = static_cast<std::size_t>(j);
      for (std::size_t a = 0; a < 3; ++a) m.xyz[a * n + i] = points[m.index[i]][a];
    });
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
