// point_spacing.cpp - see point_spacing.hpp.
#include "preparation/point_spacing.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>

namespace ppcr {
inline namespace PPCR_ABI_NAMESPACE {
namespace detail {

double upper_median_in_place(double* values, std::size_t count) {
  if (count == 0) return 0.0;
  double* middle = values + count / 2;
  std::nth_element(values, middle, values + count);
  return *middle;
}

double nearest_nonzero_sq(const double* d2, int found) {
  for (int m = 0; m < std::min(found, kSpacingNeighbours); ++m) {
    if (d2[m] > 0.0) return d2[m];
  }
  return -1.0;
}

double median_spacing(const PointCloud& points, const KdTree& tree, std::size_t max_samples,
                      const Buffer<double>* nearest_sq, std::vector<double>* scratch) {
  scratch->clear();
  if (points.size() < 2 || max_samples == 0) return 0.0;
  const std::size_t stride = std::max<std::size_t>(1, points.size() / max_samples);
  std::uint32_t idx[kSpacingNeighbours];
  double d2[kSpacingNeighbours];
  for (std::size_t i = 0; i < points.size(); i += stride) {
    double nearest = 0.0;
    if (nearest_sq != nullptr && !nearest_sq->empty()) {
      nearest = (*nearest_sq)[i];
    } else {
      const int found = tree.radius_knn(points[i], kSpacingNeighbours,
                                        std::numeric_limits<double>::max(), idx, d2);
      nearest = nearest_nonzero_sq(d2, found);
    }
    if (nearest > 0.0) scratch->push_back(nearest);
  }
  return std::sqrt(upper_median_in_place(scratch->data(), scratch->size()));
}

}  // namespace detail
}  // namespace PPCR_ABI_NAMESPACE
}  // namespace ppcr
