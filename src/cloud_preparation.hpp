// cloud_preparation.hpp - from a user's cloud to the points the solver works on: non-finite
// points dropped, voxel-filtered, and shifted into the internal frame.
//
// Internal frame: each cloud is shifted by its per-axis median point o, so that coordinates are
// small even for georeferenced clouds and the left-perturbation twist acts about the middle of
// the target's data (a median, unlike a mean, is not dragged away by a few absurd points). A pose
// T in that frame maps to T_target_source = Tr(o_target) * T * Tr(-o_source).
#pragma once

#include <Eigen/Core>
#include <cstddef>
#include <vector>

#include "ppcr/abi.hpp"
#include "ppcr/status.hpp"
#include "ppcr/types.hpp"

namespace ppcr {
inline namespace PPCR_ABI_NAMESPACE {
namespace detail {

struct PreparedCloud {
  PointCloud points;    // kept points, in the user's frame
  PointCloud centered;  // the same points minus origin
  Eigen::Vector3d origin = Eigen::Vector3d::Zero();
  std::size_t dropped = 0;      // non-finite, or too far from the origin for a finite squared norm
  std::vector<double> scratch;  // for the median, kept so that a same-size cloud allocates nothing
};

/// Prepares `in` into *out (its buffers reused). name ("source" or "target") prefixes every
/// message. Fails with kEmptyCloud below 3 usable points and with kInvalidArgument for a cloud so
/// far from the coordinate origin that a double cannot resolve a thousandth of its extent there.
Status prepare_cloud(const PointCloud& in, double voxel, const char* name, PreparedCloud* out);

}  // namespace detail
}  // namespace PPCR_ABI_NAMESPACE
}  // namespace ppcr
