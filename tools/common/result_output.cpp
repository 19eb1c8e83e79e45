// result_output.cpp - JSON, trace CSV and matrix text of a registration result.
#include "common/result_output.hpp"

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <fstream>

namespace ppcr_tools {

nlohmann::ordered_json matrix_json(const Eigen::Ref<const Eigen::MatrixXd>& M) {
  nlohmann::ordered_json rows = nlohmann::ordered_json::array();
  for (Eigen::Index r = 0; r < M.rows(); ++r) {
    nlohmann::ordered_json row = nlohmann::ordered_json::array();
    for (Eigen::Index c = 0; c < M.cols(); ++c) row.push_back(M(r, c));
    rows.push_back(row);
  }
  return rows;
}

nlohmann::ordered_json result_json(const ppcr::RegistrationResult& r, double time_ms,
                                   bool automatic_radius, const ppcr::PoseErrors* gt) {
  nlohmann::ordered_json j;
  j["transform"] = matrix_json(r.T_target_source.matrix());
  j["status"] = ppcr::to_string(r.status.code());
  if (!r.status.ok()) j["message"] = r.status.message();
  j["converged"] = r.converged();
  j["stop_reason"] = ppcr::to_string(r.stop_reason);
  j["iterations"] = r.iterations;
  j["lm_iterations"] = r.lm_iterations;
  j["lm_successful_steps"] = r.lm_successful_steps;
  j["initial_cost"] = r.initial_cost;
  j["final_cost"] = r.final_cost;
  j["radius_used"] = r.radius;
  j["radius_source"] = automatic_radius ? "auto" : "user";
  j["source_voxel_used"] = r.source_voxel;
  j["target_voxel_used"] = r.target_voxel;
  j["scale"] = r.scale;
  j["target_surface_noise"] = r.target_surface_noise;
  j["time_ms"] = time_ms;
  j["correspondences"] = r.correspondences;
  j["matched_source_points"] = r.matched_source_points;
  j["source_points"] = r.source_points;
  j["target_points"] = r.target_points;
  j["source_non_finite"] = r.source_non_finite;
  j["target_non_finite"] = r.target_non_finite;
  j["source_duplicates"] = r.source_duplicates;
  j["target_duplicates"] = r.target_duplicates;
  j["fitness"] = r.fitness;
  j["inlier_rmse"] = r.inlier_rmse;
  j["overlap"] = r.overlap;
  j["close_fraction"] = r.close_fraction;
  j["target_spacing"] = r.target_spacing;
  j["quality"] = ppcr::to_string(r.quality);
  j["quality_reason"] = r.quality_reason;
  j["quality_ms"] = r.quality_ms;
  j["degenerate_directions"] = r.degenerate_directions;
  j["information"] = matrix_json(r.information);
  j["covariance"] = matrix_json(r.covariance);
  if (gt != nullptr) {
    j["rotation_error_deg"] = gt->rotation_error_deg;
    j["translation_error"] = gt->translation_error;
    j["benchmark_error"] = gt->benchmark_error;
  }
  return j;
}

ppcr::Status write_trace_csv(const std::string& path,
                             const std::vector<ppcr::IterationRecord>& history,
                             const ppcr::PointCloud& source, const Eigen::Isometry3d* T_gt) {
  std::FILE* f = std::fopen(path.c_str(), "w");
  if (f == nullptr) {
    return ppcr::Status(ppcr::StatusCode::kIoError,
                        path + ": cannot open for writing: " + std::strerror(errno));
  }
  std::fprintf(f,
               "iteration,phase,successful_steps,unsuccessful_steps,initial_cost,final_cost,"
               "cost_drop,mse_prev,mse_ground_truth,benchmark_error,scale,correspondences,"
               "matched_source_points,tx,ty,tz,qx,qy,qz,qw,time_ms\n");
  for (const ppcr::IterationRecord& h : history) {
    const Eigen::Quaterniond q(h.T_target_source.linear());
    const Eigen::Vector3d t = h.T_target_source.translation();
    char gt[96] = ",";
    if (T_gt != nullptr) {
      const ppcr::PoseErrors e = ppcr::evaluate(source, h.T_target_source, *T_gt);
      std::snprintf(gt, sizeof(gt), "%.17g,%.17g", e.mse, e.benchmark_error);
    }
    std::fprintf(f,
                 "%d,%s,%d,%d,%.17g,%.17g,%.17g,%.17g,%s,%.17g,%zu,%zu,%.17g,%.17g,%.17g,%.17g,"
                 "%.17g,%.17g,%.17g,%.6f\n",
                 h.iteration, h.coarse ? "coarse" : "fine", h.successful_steps,
                 h.unsuccessful_steps, h.initial_cost, h.final_cost, h.cost_drop, h.mse_prev, gt,
                 h.scale, h.correspondences, h.matched_source_points, t.x(), t.y(), t.z(), q.x(),
                 q.y(), q.z(), q.w(), h.time_ms);
  }
  const bool ok = std::ferror(f) == 0;
  const int write_errno = errno;
  if (std::fclose(f) != 0 || !ok) {
    return ppcr::Status(ppcr::StatusCode::kIoError,
                        path + ": write failed: " + std::strerror(ok ? errno : write_errno));
  }
  return ppcr::Status::Ok();
}

std::string matrix_text(const Eigen::Matrix4d& M) {
  std::string out;
  char line[160];
  for (int r = 0; r < 4; ++r) {
    std::snprintf(line, sizeof(line), "%.17g %.17g %.17g %.17g\n", M(r, 0), M(r, 1), M(r, 2),
                  M(r, 3));
    out += line;
  }
  return out;
}

}  // namespace ppcr_tools
