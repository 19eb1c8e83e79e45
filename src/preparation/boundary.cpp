// boundary.cpp - see boundary.hpp.
#include "preparation/boundary.hpp"

#include <Eigen/Geometry>
#include <cstdint>

namespace ppcr {
inline namespace PPCR_ABI_NAMESPACE {
namespace detail {

namespace {

// Whether the sectors not in `occupied` hold a run of kBoundarySectors, around the circle: the
// empty set written twice, and a bit left at each start of such a run.
bool has_gap(std::uint32_t occupied) {
  constexpr std::uint32_t kAll = (1u << kSectors) - 1;
  const std::uint32_t empty = ~occupied & kAll;
  const std::uint32_t twice = empty | (empty << kSectors);
  std::uint32_t run = twice;
  for (int s = 1; s < kBoundarySectors; ++s) run &= twice >> s;
  return (run & kAll) != 0;
}

}  // namespace

bool on_boundary(const PointCloud& points, const Eigen::Vector3d& y, const Eigen::Vector3d& normal,
                 const std::uint32_t* idx, int n) {
  if (normal.squaredNorm() == 0.0) return false;
  const Eigen::Vector3d u = normal.unitOrthogonal();
  const Eigen::Vector3d v = normal.cross(u);
  std::uint32_t occupied = 0;  // bit s: a direction in sector s
  for (int i = 0; i < n; ++i) {
    const Eigen::Vector3d e = points[idx[i]] - y;
    const double a = e.dot(u), b = e.dot(v);
    if (a == 0.0 && b == 0.0) continue;  // on y, or along its normal: no direction
    occupied |= 1u << direction_sector(a, b);
    // Sectors only fill: once no gap is left, none opens. Most points are interior, and their
    // nearest few neighbours already surround them (checked every 4th, the test costs a few
    // bit operations).
    if ((i & 3) == 3 && !has_gap(occupied)) return false;
  }
  return occupied != 0 && has_gap(occupied);
}

}  // namespace detail
}  // namespace PPCR_ABI_NAMESPACE
}  // namespace ppcr
