// radius_knn_result.hpp - the nanoflann result set of the k-d tree's radius-limited kNN query
// (kdtree.cpp): the k nearest within a radius, kept sorted (worstDist, addPoint, sort).
#pragma once

#include <cmath>
#include <cstdint>
#include <limits>

#include "ppcr/abi.hpp"

namespace ppcr {
inline namespace PPCR_ABI_NAMESPACE {
namespace detail {

// The k nearest within a radius: a KNN result set with an upper bound. A search visits a
// candidate only if its squared distance is strictly below worstDist(); while fewer than k are
// held, worstDist() is the next double above radius_sq, so a point exactly at the radius is kept
// when the search reaches it (the radius is inclusive). The search's bound on a cell's distance
// is rounded, and can exceed the distance of a point exactly at the radius by an ulp and skip its
// cell. Once k are held worstDist()
// is the k-th best, as in KNN.
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

}  // namespace detail
}  // namespace PPCR_ABI_NAMESPACE
}  // namespace ppcr
