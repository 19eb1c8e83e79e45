// voxel.hpp - voxel-grid downsampling (the preprocessing of the authors' tool, PCL's VoxelGrid).
#pragma once

#include "ppcr/abi.hpp"
#include "ppcr/status.hpp"
#include "ppcr/types.hpp"

namespace ppcr {
inline namespace PPCR_ABI_NAMESPACE {

/// Replaces the points of each occupied cubic voxel of side leaf_size (cloud units, > 0) by their
/// centroid. Voxels are aligned to the cloud's minimum corner; the output lists voxels in the order
/// their first point appears in the input, so it is deterministic. Non-finite input points are
/// skipped. Fails (kInvalidArgument) when leaf_size is not finite and positive, or so small that
/// the grid would exceed 2^21 cells along an axis (cell indices are floor((p - min) * (1 / leaf))).
Status voxel_downsample(const PointCloud& cloud, double leaf_size, PointCloud* out);

}  // namespace PPCR_ABI_NAMESPACE
}  // namespace ppcr
