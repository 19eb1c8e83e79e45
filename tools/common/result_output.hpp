// result_output.hpp - what the tools print and write: the JSON result, the per-iteration trace
// (CSV, the columns of the termination issue), the 4x4 transform as text.
#pragma once

#include <Eigen/Geometry>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "ppcr/metrics.hpp"
#include "ppcr/registration.hpp"
#include "ppcr/status.hpp"

namespace ppcr_tools {

/// Row-major nested arrays (the 4x4 transform, the 6x6 information and covariance).
nlohmann::ordered_json matrix_json(const Eigen::Ref<const Eigen::MatrixXd>& M);

/// The result object of ppcr_cli --json (keys documented in README).
/// automatic_radius: the options asked for the automatic radius (JSON radius_source).
nlohmann::ordered_json result_json(const ppcr::RegistrationResult& result, double time_ms,
                                   bool automatic_radius, const ppcr::PoseErrors* gt);

/// One CSV row per outer iteration: iteration, phase (coarse or fine), successful_steps,
/// unsuccessful_steps, initial_cost, final_cost, cost_drop, mse_prev, mse_ground_truth,
/// benchmark_error, scale, correspondences, matched_source_points, tx, ty, tz, qx, qy, qz, qw,
/// time_ms (last, so that traces compare with it cut off). The ground-truth columns are
/// evaluated here on `source` (the registered cloud) when T_gt is given, else empty.
ppcr::Status write_trace_csv(const std::string& path,
                             const std::vector<ppcr::IterationRecord>& history,
                             const ppcr::PointCloud& source, const Eigen::Isometry3d* T_gt);

/// Four lines of four numbers (17 significant digits).
std::string matrix_text(const Eigen::Matrix4d& M);

}  // namespace ppcr_tools
