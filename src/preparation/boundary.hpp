// boundary.hpp - the points on a sampled surface's boundary, from their plane fits' neighbours.
//
// A point y lies on the boundary when its neighbours, seen from y in its tangent plane (the
// plane fit's, pca_normals.hpp), leave a wide sector around y empty: the sample ends on that
// side (a scan's edge, an occlusion's shadow, a partial view's cut). A source point whose nearest
// target point lies there may lie beyond what the target saw, and its pairs then pull it toward
// the target's interior, away from the truth; the association leaves such rows out once the
// coarse phase has brought the clouds together (associator.hpp; the rule of Turk and Levoy's
// zippering, which drops pairs with a mesh's boundary vertices). Measured: docs/BENCHMARK.md;
// what it leaves open: docs/RELIABILITY.md, "Partial overlap".
#pragma once

#include <Eigen/Core>
#include <cstdint>

#include "ppcr/abi.hpp"
#include "ppcr/types.hpp"

namespace ppcr {
inline namespace PPCR_ABI_NAMESPACE {
namespace detail {

/// The circle around y in sectors of 22.5 degrees, and how many consecutive empty ones make y a
/// boundary point: an empty angle of at least 135 degrees (6 sectors), sure beyond 157.5 (any
/// wider empty angle holds 6 whole sectors). An evenly sampled interior leaves gaps of 45-90
/// degrees, an edge about 180. A scanner's ring whose fit reaches the next ring on one side only
/// leaves about 180 too: such points count as boundary points (docs/BENCHMARK.md, "Rows beyond the
/// target's boundary").
inline constexpr int kSectors = 16;
inline constexpr int kBoundarySectors = 6;

/// The sector, 0 to 15 counter-clockwise from the a axis, of the direction (a, b) != 0: sector s
/// holds the angles in [22.5 s, 22.5 (s + 1)) degrees (an angle on an edge to the sector it
/// starts, to the rounding of the constants below; exactly so on the axes). No trigonometry and no
/// branch: with theta the direction's angle and r its length, b cos(phi) - a sin(phi) =
/// r sin(theta - phi). For theta in [0, 180) that is >= 0 for the phi = 22.5 k (k = 1..7) with
/// phi <= theta, whose count is the sector; for theta in [180, 360) it is > 0 for those with
/// phi > theta - 180, and the sector is 15 less their count.
inline int direction_sector(double a, double b) {
  // cos and sin of 22.5 k degrees, k = 1..7.
  static constexpr double kCos[7] = {
      0.92387953251128674,  0.70710678118654757,  0.38268343236508984, 0.0,
      -0.38268343236508984, -0.70710678118654757, -0.92387953251128674};
  static constexpr double kSin[7] = {
      0.38268343236508978, 0.70710678118654746, 0.92387953251128674, 1.0,
      0.92387953251128674, 0.70710678118654746, 0.38268343236508978};
  const bool upper = b > 0.0 || (b == 0.0 && a > 0.0);  // theta in [0, 180)
  int count = 0;
  for (int k = 0; k < 7; ++k) {
    const double s = b * kCos[k] - a * kSin[k];
    count += upper ? s >= 0.0 : s > 0.0;
  }
  return upper ? count : 15 - count;
}

/// Whether y lies on the boundary: the directions from y to points[idx[0..n)], projected on the
/// plane through y with unit normal `normal`, leave kBoundarySectors consecutive sectors empty
/// (direction_sector() in the basis normal.unitOrthogonal(), normal x that). Neighbours that
/// project onto y give no direction; with one direction 15 sectors are empty; with none, or a zero
/// normal (no plane fit), false.
bool on_boundary(const PointCloud& points, const Eigen::Vector3d& y, const Eigen::Vector3d& normal,
                 const std::uint32_t* idx, int n);

}  // namespace detail
}  // namespace PPCR_ABI_NAMESPACE
}  // namespace ppcr
