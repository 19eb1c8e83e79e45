// outliers.hpp - uniform outliers added to a scan (internal to ppcr_synthetic).
#pragma once

#include <Eigen/Geometry>

#include "ppcr/abi.hpp"
#include "ppcr/types.hpp"
#include "random.hpp"
#include "scene.hpp"

namespace ppcr {
inline namespace PPCR_ABI_NAMESPACE {
namespace synthetic {
namespace internal {

/// Appends round(n f / (1 - f)) points (n = cloud->size(), f = fraction in [0, 1)) drawn
/// uniformly in the part of the scene's bounds within max_range (per axis) of the sensor,
/// expressed in the sensor frame (the whole bounds when that part is empty).
void add_outliers(const Scene& scene, double fraction, double max_range,
                  const Eigen::Isometry3d& world_T_sensor, Rng* rng, PointCloud* cloud);

}  // namespace internal
}  // namespace synthetic
}  // namespace PPCR_ABI_NAMESPACE
}  // namespace ppcr
