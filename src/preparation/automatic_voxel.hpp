// automatic_voxel.hpp - the voxel leaf chosen from the cloud itself (RegistrationOptions::
// kAutomaticVoxel): the leaf that leaves about a given number of points.
#pragma once

#include <cstddef>

#include "ppcr/abi.hpp"
#include "ppcr/status.hpp"
#include "ppcr/types.hpp"

namespace ppcr {
inline namespace PPCR_ABI_NAMESPACE {
namespace detail {

/// Filters the finite points `in` with the leaf that leaves about `points` of them into *out, and
/// sets *leaf to it; a cloud of no more than `points` points (or of equal points) is copied
/// unfiltered, *leaf = 0. The leaf scales with the cloud (unit-free) and is deterministic. On a
/// surface the number of occupied voxels falls as 1 / leaf^2: the first leaf is sqrt(area /
/// points), the area from the middle 98 % of the points along each axis (far outliers do not set
/// it); then each step rescales the leaf by sqrt(voxels / points) until the count is bracketed,
/// and halves the bracket in log(leaf). It stops within 15 % of `points` (the usual case, in 1-3
/// steps) or after 12 steps, keeping the closest count.
Status automatic_voxel_filter(const PointCloud& in, std::size_t points, PointCloud* out,
                              double* leaf);

}  // namespace detail
}  // namespace PPCR_ABI_NAMESPACE
}  // namespace ppcr
