// depth_camera_flags.cpp - --depth-intrinsics and --depth-scale.
#include "common/depth_camera_flags.hpp"

#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "common/registration_flags.hpp"

namespace ppcr_tools {

void add_depth_camera_flags(CLI::App& app, ppcr::io::DepthCamera* camera) {
  const ppcr::io::DepthCamera defaults;
  const auto str = [](double v) { return CLI::detail::to_string(v); };
  app.add_option_function<std::vector<double>>(
         "--depth-intrinsics",
         [camera](const std::vector<double>& v) {
           const char* names[] = {"FX", "FY", "CX", "CY"};
           for (int i = 0; i < 4; ++i) {
             if (!std::isfinite(v[i]) || (i < 2 && !(v[i] > 0.0))) {
               throw CLI::ValidationError("--depth-intrinsics",
                                          std::string(names[i]) + " = " + std::to_string(v[i]) +
                                              (i < 2 ? ": must be > 0" : ": must be finite"));
             }
           }
           camera->fx = v[0], camera->fy = v[1], camera->cx = v[2], camera->cy = v[3];
         },
         "depth images (.png): the pinhole camera's fx fy cx cy, pixels (default TUM's " +
             str(defaults.fx) + " " + str(defaults.fy) + " " + str(defaults.cx) + " " +
             str(defaults.cy) + "; TUM's Freiburg 1 frames: 517.3 516.5 318.6 255.3)")
      ->expected(4)
      ->type_name("FX FY CX CY")
      ->group("Depth images");
  app.add_option("--depth-scale", camera->depth_scale,
                 "depth images: stored value per metre (default " + str(defaults.depth_scale) +
                     ", TUM's; 1000 for millimetres)")
      ->check(finite_positive())
      ->group("Depth images");
}

}  // namespace ppcr_tools
