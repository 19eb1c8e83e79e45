// types.hpp - the point cloud type shared by the core and ppcr_io.
#pragma once

#include <Eigen/Core>
#include <vector>

#include "ppcr/abi.hpp"

namespace ppcr {
inline namespace PPCR_ABI_NAMESPACE {

/// A point cloud: coordinates in double precision, in the cloud's own frame and units.
/// (Eigen::Vector3d has no alignment requirement, so a plain std::vector is safe.)
using PointCloud = std::vector<Eigen::Vector3d>;

}  // namespace PPCR_ABI_NAMESPACE
}  // namespace ppcr
