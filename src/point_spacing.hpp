// point_spacing.hpp - the typical distance between neighbouring points of a cloud: the scale
// against which an alignment's residual distances are judged (the verdict) and from which the
// automatic radius is derived.
#pragma once

#include <cstddef>
#include <vector>

#include "kdtree.hpp"
#include "ppcr/abi.hpp"
#include "ppcr/types.hpp"

namespace ppcr {
inline namespace PPCR_ABI_NAMESPACE {
namespace detail {

/// The median, over every floor(n / max_samples)-th point of `points` (tree indexes them; all
/// points below 2 x max_samples), of the distance from a point to its nearest other point at a
/// non-zero distance (up to 14 duplicates of it skipped). 0 when no sampled point has such a
/// neighbour. Deterministic.
double median_spacing(const PointCloud& points, const KdTree& tree, std::size_t max_samples,
                      std::vector<double>* scratch);

}  // namespace detail
}  // namespace PPCR_ABI_NAMESPACE
}  // namespace ppcr
