// cloud_preparation.cpp - see cloud_preparation.hpp.
#include "preparation/cloud_preparation.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

#include "common/format.hpp"
#include "ppcr/options.hpp"
#include "ppcr/voxel.hpp"
#include "preparation/automatic_voxel.hpp"

namespace ppcr {
inline namespace PPCR_ABI_NAMESPACE {
namespace detail {
namespace {

Status too_few(const char* name, std::size_t kept, std::size_t input, std::size_t dropped,
               double voxel) {
  return Status(StatusCode::kEmptyCloud,
                std::string(name) + " has " + std::to_string(kept) + " usable point(s) (of " +
                    std::to_string(input) + ", " + std::to_string(dropped) +
                    " non-finite or too far from the others for a finite squared distance" +
                    (voxel > 0.0 ? ", after a voxel filter of " + num(voxel) : std::string()) +
                    "); at least 3 are needed");
}

// Per-axis median of the cloud, O(n) (nth_element), reordering it: no copy of a coordinate. The
// Z-order sort then sets the order (spatial_order.hpp); only equal points keep this one among
// themselves, and all but one of them are dropped.
Eigen::Vector3d median_origin(PointCloud* cloud) {
  Eigen::Vector3d origin;
  const auto mid = cloud->begin() + static_cast<std::ptrdiff_t>(cloud->size() / 2);
  for (int axis = 0; axis < 3; ++axis) {
    std::nth_element(
        cloud->begin(), mid, cloud->end(),
        [axis](const Eigen::Vector3d& a, const Eigen::Vector3d& b) { return a[axis] < b[axis]; });
    origin[axis] = (*mid)[axis];
  }
  return origin;
}

// Replaces each point c of out->centered by map(c) and keeps those whose squared norm is then
// finite (no squared distance to the others is), in order, counting the dropped ones.
template <class Map>
void keep_finite(PreparedCloud* out, Map map) {
  PointCloud& points = out->centered;
  std::size_t kept = 0;
  for (std::size_t i = 0; i < points.size(); ++i) {
    const Eigen::Vector3d c = map(points[i]);
    if (!std::isfinite(c.squaredNorm())) continue;
    points[kept++] = c;
  }
  out->dropped += points.size() - kept;
  points.resize(kept);
}

// Shifts the points by their median.
void center(PreparedCloud* out) {
  out->origin = median_origin(&out->centered);
  const Eigen::Vector3d origin = out->origin;
  keep_finite(out, [origin](const Eigen::Vector3d& p) { return Eigen::Vector3d(p - origin); });
}

double max_abs(const PointCloud& centered) {
  double extent = 0.0;
  for (const Eigen::Vector3d& c : centered) extent = std::max(extent, c.cwiseAbs().maxCoeff());
  return extent;
}

// A 2 m scene 1e14 m from the coordinate origin has steps of 2 cm: refused. A cloud whose points
// all round to one value is accepted (a cloud of identical points).
Status check_resolution(const char* name, const PreparedCloud& cloud) {
  const double distance = cloud.origin.cwiseAbs().maxCoeff();
  const double resolution = distance * std::numeric_limits<double>::epsilon();
  if (cloud.extent > 0.0 && resolution > 1e-3 * cloud.extent) {
    return Status(StatusCode::kInvalidArgument,
                  std::string(name) + " lies ~" + num(distance) +
                      " from the coordinate origin, where doubles resolve only " + num(resolution) +
                      ", more than a thousandth of its extent " + num(cloud.extent) +
                      ": shift both clouds nearer the origin");
  }
  return Status::Ok();
}

// Divides the centred points by out->unit (a source far outside the target's scale can then
// overflow).
void divide_by_unit(PreparedCloud* out) {
  const double unit = out->unit;
  keep_finite(out, [unit](const Eigen::Vector3d& c) { return Eigen::Vector3d(c / unit); });
}

}  // namespace

double internal_unit(double radius, double target_extent) {
  return std::min(kMaxUnit, target_extent > 0.0 ? std::min(radius, target_extent) : radius);
}

Status prepare_cloud(const PointCloud& in, double voxel, double radius, double unit,
                     const char* name, PreparedCloud* out) {
  PointCloud& points = out->centered;  // the user's frame until center()
  points.clear();
  points.reserve(in.size());
  for (const Eigen::Vector3d& p : in) {
    if (p.allFinite()) points.push_back(p);
  }
  out->dropped = in.size() - points.size();
  out->leaf = voxel > 0.0 ? voxel : 0.0;
  if (voxel != 0.0 && !points.empty()) {
    PointCloud filtered;
    Status s = voxel == RegistrationOptions::kAutomaticVoxel
                   ? automatic_voxel_filter(points, RegistrationOptions::kAutomaticVoxelPoints,
                                            &filtered, &out->leaf)
                   : voxel_downsample(points, voxel, &filtered);
    if (!s.ok())
      return Status(s.code(), std::string(name) + "_voxel " + num(voxel) + ": " + s.message());
    points = std::move(filtered);
  }
  if (points.size() < 3) return too_few(name, points.size(), in.size(), out->dropped, out->leaf);
  center(out);
  out->extent = max_abs(out->centered);
  Status s = check_resolution(name, *out);
  if (!s.ok()) return s;
  out->unit = unit > 0.0 ? unit : internal_unit(radius, out->extent);
  if (!(out->unit >= std::numeric_limits<double>::min())) {
    return Status(StatusCode::kInvalidArgument,
                  "radius " + num(radius) + ": lengths this small (the " + name +
                      "'s internal unit " + num(out->unit) +
                      ") are subnormal in double precision; express the clouds in larger units");
  }
  const std::size_t before = points.size();
  divide_by_unit(out);
  if (points.size() < 3 && points.size() < before) {
    return Status(StatusCode::kInvalidArgument,
                  "radius " + num(radius) + " is too small for the " + name + ", which spans " +
                      num(out->extent) + ": in units of " + num(out->unit) +
                      " its squared distances overflow a double; express the clouds in other "
                      "units or raise the radius");
  }
  if (points.size() < 3) return too_few(name, points.size(), in.size(), out->dropped, out->leaf);
  return Status::Ok();
}

}  // namespace detail
}  // namespace PPCR_ABI_NAMESPACE
}  // namespace ppcr
