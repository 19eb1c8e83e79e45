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

/// Filters the finite points `in` with the leaf that leaves about `points` of them (within 15 %),
/// into *out, and sets *leaf to it; a cloud of no more than `points` points is copied unfiltered,
/// *leaf = 0. The leaf is unit-free in effect (it scales with the cloud) and deterministic. On a
/// surface the number of occupied voxels falls as 1 / leaf^2: from the bounding box's diagonal /
/// sqrt(points), each step rescales the leaf by sqrt(voxels / points), at most 6 steps.
Status automatic_voxel_filter(const PointCloud& in, std::size_t points, PointCloud* out,
                              double* leaf);

}  // namespace detail
}  // namespace PPCR_ABI_NAMESPACE
}  // namespace ppcr
