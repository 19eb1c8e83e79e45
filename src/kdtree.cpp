// kdtree.cpp - nanoflann adaptor and the radius-bounded kNN result set (nanoflann 1.4 has none).
#include "kdtree.hpp"

#include <cmath>
#include <limits>
#include <nanoflann.hpp>
#include <new>
#include <string>

namespace ppcr {
namespace detail {
namespace {

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

// The k nearest within a radius: nanoflann's KNN result set with an upper bound. nanoflann
// visits a candidate only if its squared distance is strictly below worstDist(); while fewer
// than k are held, worstDist() is the next double above radius_sq, so points exactly at the
// radius are kept (the radius is inclusive). Once k are held it is the k-th best, as in KNN.
class RadiusKnnResultSet {
 public:
  using DistanceType = double;
  using IndexType = std::uint32_t;

  RadiusKnnResultSet(int capacity, double radius_sq, IndexType* indices, double* dist_sq)
      : indices_(indices),
        dist_sq_(dist_sq),
        capacity_(capacity),
        bound_(std::nextafter(radius_sq, std::numeric_limits<double>::infinity())) {}

  int size() const { return count_; }
  bool full() const { return count_ == capacity_; }
  double worstDist() const { return full() ? dist_sq_[capacity_ - 1] : bound_; }

  // Insertion into the sorted prefix; returns true to keep searching.
  bool addPoint(double dist_sq, IndexType index) {
    if (!(dist_sq < worstDist())) return true;
    int i = (count_ < capacity_) ? count_ : capacity_ - 1;
    while (i > 0 && dist_sq_[i - 1] > dist_sq) {
      dist_sq_[i] = dist_sq_[i - 1];
      indices_[i] = indices_[i - 1];
      --i;
    }
    dist_sq_[i] = dist_sq;
    indices_[i] = index;
    if (count_ < capacity_) ++count_;
    return true;
  }

 private:
  IndexType* indices_;
  double* dist_sq_;
  int capacity_;
  int count_ = 0;
  double bound_;
};

using Tree = nanoflann::KDTreeSingleIndexAdaptor<
    nanoflann::L2_Simple_Adaptor<double, CloudAdaptor, double, std::uint32_t>, CloudAdaptor, 3,
    std::uint32_t>;

}  // namespace

struct KdTree::Impl {
  CloudAdaptor adaptor;
  std::unique_ptr<Tree> tree;
};

KdTree::KdTree() : impl_(new Impl) {}
KdTree::~KdTree() = default;
KdTree::KdTree(KdTree&&) noexcept = default;
KdTree& KdTree::operator=(KdTree&&) noexcept = default;

Status KdTree::build(const PointCloud& points) {
  if (points.size() >= std::numeric_limits<std::uint32_t>::max()) {
    return Status(StatusCode::kInvalidArgument,
                  "the cloud has " + std::to_string(points.size()) +
                      " points; the k-d tree indexes at most 2^32 - 1");
  }
  impl_->adaptor.points = &points;
  try {
    impl_->tree.reset(new Tree(3, impl_->adaptor, nanoflann::KDTreeSingleIndexAdaptorParams(16)));
  } catch (const std::bad_alloc&) {
    impl_->tree.reset();
    return Status(StatusCode::kInvalidArgument, "out of memory building the k-d tree over " +
                                                    std::to_string(points.size()) + " points");
  }
  return Status::Ok();
}

int KdTree::radius_knn(const Eigen::Vector3d& query, int k, double radius_sq,
                       std::uint32_t* indices, double* dist_sq) const {
  if (!impl_->tree || impl_->adaptor.points->empty() || k < 1) return 0;
  RadiusKnnResultSet result(k, radius_sq, indices, dist_sq);
  impl_->tree->findNeighbors(result, query.data(), nanoflann::SearchParams(0, 0.0f, true));
  return result.size();
}

std::size_t KdTree::size() const {
  return impl_->adaptor.points ? impl_->adaptor.points->size() : 0;
}

}  // namespace detail
}  // namespace ppcr
