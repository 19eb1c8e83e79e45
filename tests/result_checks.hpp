// result_checks.hpp - comparisons of registration results shared by the tests.
#pragma once

#include <catch2/catch.hpp>
#include <cstddef>

#include "ppcr/result.hpp"

namespace test_checks {

/// Everything a result holds that is computed from floating-point sums, compared exactly (the
/// differential and determinism tests: the same computation by two paths).
inline void check_identical(const ppcr::RegistrationResult& a, const ppcr::RegistrationResult& b) {
  REQUIRE(a.status.ok());
  REQUIRE(b.status.ok());
  CHECK(a.T_target_source.matrix() == b.T_target_source.matrix());
  CHECK(a.stop_reason == b.stop_reason);
  CHECK(a.iterations == b.iterations);
  CHECK(a.lm_iterations == b.lm_iterations);
  CHECK(a.final_cost == b.final_cost);
  CHECK(a.initial_cost == b.initial_cost);
  CHECK(a.scale == b.scale);
  CHECK(a.information == b.information);
  CHECK(a.degenerate_directions == b.degenerate_directions);
  CHECK(a.correspondences == b.correspondences);
  CHECK(a.fitness == b.fitness);
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
