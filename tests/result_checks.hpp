// result_checks.hpp - comparisons of registration results shared by the tests.
#pragma once

#include <catch2/catch.hpp>
#include <cstddef>

#include "ppcr/result.hpp"

namespace test_checks {

/// The result's pose, costs, counts, scale, information, quality measures and history, compared
/// exactly (the differential and determinism tests: the same computation by two paths).
inline void check_identical(const ppcr::RegistrationResult& a, const ppcr::RegistrationResult& b) {
  REQUIRE(a.status.ok());
  REQUIRE(b.status.ok());
  CHECK(a.T_target_source.matrix() == b.T_target_source.matrix());
  CHECK(a.stop_reason == b.stop_reason);
  CHECK(a.iterations == b.iterations);
  CHECK(a.lm_iterations == b.lm_iterations);
  CHECK(a.lm_successful_steps == b.lm_successful_steps);
  CHECK(a.final_cost == b.final_cost);
  CHECK(a.initial_cost == b.initial_cost);
  CHECK(a.scale == b.scale);
  CHECK(a.information == b.information);
  CHECK(a.covariance == b.covariance);
  CHECK(a.degenerate_directions == b.degenerate_directions);
  CHECK(a.correspondences == b.correspondences);
  CHECK(a.source_points == b.source_points);
  CHECK(a.target_points == b.target_points);
  CHECK(a.source_non_finite == b.source_non_finite);
  CHECK(a.target_non_finite == b.target_non_finite);
  CHECK(a.source_duplicates == b.source_duplicates);
  CHECK(a.target_duplicates == b.target_duplicates);
  CHECK(a.radius == b.radius);
  CHECK(a.target_spacing == b.target_spacing);
  CHECK(a.target_surface_noise == b.target_surface_noise);
  CHECK(a.fitness == b.fitness);
  CHECK(a.inlier_rmse == b.inlier_rmse);
  CHECK(a.overlap == b.overlap);
  CHECK(a.close_fraction == b.close_fraction);
  CHECK(a.quality == b.quality);
  REQUIRE(a.history.size() == b.history.size());
  for (std::size_t i = 0; i < a.history.size(); ++i) {
    INFO("history row " << i);
    CHECK(a.history[i].T_target_source.matrix() == b.history[i].T_target_source.matrix());
    CHECK(a.history[i].final_cost == b.history[i].final_cost);
    CHECK(a.history[i].scale == b.history[i].scale);
  }
}

}  // namespace test_checks
