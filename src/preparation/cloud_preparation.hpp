// cloud_preparation.hpp - from a user's cloud to the points the solver works on: non-finite
// points dropped, voxel-filtered, and moved into the internal frame.
//
// Internal frame: each cloud is shifted by its per-axis median point o, so that coordinates are
// small even for georeferenced clouds and the left-perturbation twist acts about the middle of
// the target's data (a median, unlike a mean, is not dragged away by a few absurd points), and
// divided by one length u shared by both clouds (internal_unit()), so that the solver sees the
// same numbers whatever the clouds' units: a pair in millimetres and the same pair in
// kilometres differ inside only by rounding. With S_u the scaling by u, a pose T in that frame
// maps to T_target_source = Tr(o_target) * S_u * T * S_u^-1 * Tr(-o_source): the same rotation,
// the translation multiplied by u.
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
  // The kept points in the internal frame, (p - origin) / unit; the only copy: the user's frame
  // is origin + unit * c, to rounding (user_point()).
  PointCloud centered;
  Eigen::Vector3d origin = Eigen::Vector3d::Zero();
  double unit = 1.0;           // internal length unit, in cloud units
  double extent = 0.0;         // max |p - origin| per axis over the kept points, cloud units
  std::size_t dropped = 0;     // non-finite, or too far from the origin for a finite squared norm
  std::size_t duplicates = 0;  // copies of a kept point removed (spatial_order.hpp)
  double leaf = 0.0;           // the voxel leaf used, cloud units (0: not filtered)

  Eigen::Vector3d user_point(std::size_t i) const { return origin + unit * centered[i]; }
};

/// The internal length unit for a registration with this radius onto a target of this extent
/// (PreparedCloud::extent): the radius, or the target's extent when that is smaller (a radius of
/// 1e6 m on a 2 m cloud means "no radius", and must not shrink the clouds to 1e-6); at most
/// kMaxUnit, so that its square, which maps costs and areas back to cloud units, is finite (a
/// target of identical points with a radius of 1e300).
constexpr double kMaxUnit = 1e150;
double internal_unit(double radius, double target_extent);

/// Prepares `in` into *out (its buffers reused): drops non-finite points, filters (with the leaf
/// `voxel`; RegistrationOptions::kAutomaticVoxel: automatic_voxel_filter()), centres and
/// divides by `unit` (> 0), or by internal_unit(radius, extent) of this very cloud when `unit`
/// is 0 (the target). The points are prepared in one buffer, in place: their order is not kept
/// (the caller sorts them, spatial_order.hpp). name ("source" or "target") prefixes every message.
/// Fails with kEmptyCloud below 3 usable points, and with kInvalidArgument for a cloud so far from
/// the coordinate origin that a double cannot resolve a thousandth of its extent there or for a
/// unit a double cannot divide by (subnormal).
Status prepare_cloud(const PointCloud& in, double voxel, double radius, double unit,
                     const char* name, PreparedCloud* out);

}  // namespace detail
}  // namespace PPCR_ABI_NAMESPACE
}  // namespace ppcr
