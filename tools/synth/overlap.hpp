// overlap.hpp - scan spacing and overlap estimates for ppcr_synth's problem file.
#pragma once

#include <Eigen/Geometry>

#include "ppcr/types.hpp"

namespace ppcr_synth {

/// Resolution of a lidar scan: the median, over the points, of the distance to their 8th
/// nearest other point. A spinning lidar samples densely along each scan line and sparsely
/// across them; the 8th neighbour is typically on the adjacent line, so this is about the gap
/// between lines, the scale at which a surface is covered. 0 for fewer than 9 points.
double scan_spacing(const ppcr::PointCloud& cloud);

/// Fraction of the source points that, mapped by target_T_source, have a target point within
/// radius (0 for an empty source).
double overlap_fraction(const ppcr::PointCloud& source, const Eigen::Isometry3d& target_T_source,
                        const ppcr::PointCloud& target, double radius);

}  // namespace ppcr_synth
