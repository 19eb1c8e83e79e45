// point_spacing.cpp - see point_spacing.hpp.
#include "point_spacing.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>

namespace ppcr {
inline namespace PPCR_ABI_NAMESPACE {
namespace detail {

double median_spacing(const PointCloud& points, const KdTree& tree, std::size_t max_samples,
                      std::vector<double>* scratch) {
  scratch->clear();
  if (points.size() < 2 || max_samples == 0) return 0.0;
  const std::size_t stride = std::max<std::size_t>(1, points.size() / max_samples);
  // The point itself and up to 14 duplicates of it come first.
  constexpr int kNeighbours = 16;
  std::uint32_t idx[kNeighbours];
  double d2[kNeighbours];
  for (std::size_t i = 0; i < points.size(); i += stride) {
    const int found =
        tree.radius_knn(points[i], kNeighbours, std::numeric_limits<double>::max(), idx, d2);
    for (int m = 0; m < found; ++m) {
      if (d2[m] > 0.0) {
        scratch->push_back(d2[m]);
        break;
      }
    }
  }
  if (scratch->empty()) return 0.0;
  // Upper median (a value of the data).
  const auto middle = scratch->begin() + static_cast<std::ptrdiff_t>(scratch->size() / 2);
  std::nth_element(scratch->begin(), middle, scratch->end());
  return std::sqrt(*middle);
}

}  // namespace detail
}  // namespace PPCR_ABI_NAMESPACE
}  // namespace ppcr
