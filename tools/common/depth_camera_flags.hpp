// depth_camera_flags.hpp - the flags that say how a depth image (.png) becomes a cloud, shared by
// ppcr_cli and ppcr_odometry: --depth-intrinsics FX FY CX CY and --depth-scale S.
#pragma once

#include <CLI/CLI.hpp>

#include "ppcr/io.hpp"

namespace ppcr_tools {

/// Adds the flags to `app`; parsing fills *camera (ppcr::io::DepthCamera's defaults, TUM's, stay
/// where a flag is not given). An fx or fy that is not > 0 is a usage error naming it.
void add_depth_camera_flags(CLI::App& app, ppcr::io::DepthCamera* camera);

}  // namespace ppcr_tools
