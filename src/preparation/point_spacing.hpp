// point_spacing.hpp - the typical distance between neighbouring points of a cloud: the scale
// against which an alignment's residual distances are judged (the verdict) and from which the
// automatic radius is derived.
#pragma once

#include <cstddef>
#include <vector>

#include "association/kdtree.hpp"
#include "common/buffer.hpp"
#include "ppcr/abi.hpp"
#include "ppcr/types.hpp"

namespace ppcr {
inline namespace PPCR_ABI_NAMESPACE {
namespace detail {

/// Neighbours a spacing query asks for: the point itself and up to 14 duplicates of it come first.
constexpr int kSpacingNeighbours = 16;

/// The upper median of values[0, count) (a value of the data; the median of an even count would
/// be a mean), or 0 when there is none. Partially sorts them in place (nth_element, O(n)).
double upper_median_in_place(double* values, std::size_t count);

/// The smallest non-zero of the first min(found, kSpacingNeighbours) squared distances of a k-NN
/// query sorted ascending, or -1 when they are all 0.
double nearest_nonzero_sq(const double* d2, int found);

/// The median, over every floor(n / max_samples)-th point of `points` (tree indexes them; all
/// points below 2 x max_samples), of the distance from a point to its nearest other point at a
/// non-zero distance (up to 14 duplicates of it skipped). 0 when no sampled point has such a
/// neighbour. Deterministic. nearest_sq, if not null nor empty, holds every point's
/// nearest_nonzero_sq() of a query for at least kSpacingNeighbours neighbours (compute_normals
/// writes it): the median is then read from it, with no query of its own, to the same value.
double median_spacing(const PointCloud& points, const KdTree& tree, std::size_t max_samples,
                      const Buffer<double>* nearest_sq, std::vector<double>* scratch);

}  // namespace detail
}  // namespace PPCR_ABI_NAMESPACE
}  // namespace ppcr
