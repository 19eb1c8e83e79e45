// ppcr_bench --methods' table (tools/bench/comparison.hpp): each method's summary and its time
// relative to the first method's, both the median of the per-problem ratios and the ratio of the
// median times, against values worked out by hand.
#include <catch2/catch.hpp>
#include <cmath>
#include <vector>

#include "bench/comparison.hpp"

namespace {

using ppcr_bench::MethodOutcomes;
using ppcr_bench::ProblemOutcome;

// A method whose problem k took times[k] ms with benchmark error errors[k]; problem k succeeds
// (rotation 0.5 deg, translation 0.001, under the bounds 1 deg and 0.002) unless fails[k].
MethodOutcomes method(const char* label, const std::vector<double>& times,
                      const std::vector<double>& errors, const std::vector<bool>& fails) {
  MethodOutcomes m;
  m.label = label;
  for (std::size_t k = 0; k < times.size(); ++k) {
    ProblemOutcome o;
    o.time_ms = times[k];
    o.error = errors[k];
    o.rotation_error_deg = fails[k] ? 2.0 : 0.5;
    o.translation_error = 0.001;
    o.iterations = static_cast<int>(10 * (k + 1));
    m.outcomes.push_back(o);
  }
  return m;
}

}  // namespace

TEST_CASE("comparison: time ratios to the first method, both kinds", "[bench][comparison]") {
  const MethodOutcomes a =
      method("ppcr", {10, 20, 40, 80}, {0.1, 0.2, 0.3, 0.4}, {false, false, false, false});
  // Per-problem ratios to a: 0.5, 1.5, 1.0, 3.0, median (1.0 + 1.5) / 2 = 1.25. Median times:
  // a (20 + 40) / 2 = 30, b (30 + 40) / 2 = 35, ratio 35 / 30.
  MethodOutcomes b =
      method("o3d-gicp", {5, 30, 40, 240}, {0.4, 0.1, 0.3, 0.2}, {false, true, false, false});
  b.failures = 1;
  const std::vector<ppcr_bench::ComparisonRow> rows = ppcr_bench::compare({a, b}, 1.0, 0.002);
  REQUIRE(rows.size() == 2);
  CHECK(rows[0].label == "ppcr");
  CHECK(rows[0].median_time_ratio == 1.0);
  CHECK(rows[0].ratio_of_median_times == 1.0);
  CHECK(rows[1].label == "o3d-gicp");
  CHECK(rows[1].failures == 1);
  CHECK(rows[1].median_time_ratio == Approx(1.25).epsilon(1e-15));
  CHECK(rows[1].ratio_of_median_times == Approx(35.0 / 30.0).epsilon(1e-15));
  // The summaries are summarize()'s: b's errors sorted 0.1 0.2 0.3 0.4, median 0.25, q0.75 at
  // position 2.25: 0.3 + 0.25 x 0.1; 3 of 4 succeed; iterations 10..40, mean 25.
  CHECK(rows[1].summary.problems == 4);
  CHECK(rows[1].summary.median == Approx(0.25).epsilon(1e-15));
  CHECK(rows[1].summary.q75 == Approx(0.325).epsilon(1e-15));
  CHECK(rows[1].summary.success == 0.75);
  CHECK(rows[1].summary.mean_iterations == 25.0);
  CHECK(rows[1].summary.median_ms == 35.0);
  CHECK(rows[0].summary.success == 1.0);
}

TEST_CASE("comparison: a problem where the first method took no time has no ratio",
          "[bench][comparison]") {
  const MethodOutcomes a = method("ppcr", {0, 10, 10}, {1, 1, 1}, {false, false, false});
  const MethodOutcomes b = method("pcl-icp", {7, 20, 40}, {1, 1, 1}, {false, false, false});
  // Ratios on problems 1 and 2 only: 2 and 4, median 3 (with problem 0 it would be inf or 4).
  const std::vector<ppcr_bench::ComparisonRow> rows = ppcr_bench::compare({a, b}, 1.0, 0.002);
  CHECK(rows[1].median_time_ratio == 3.0);
  CHECK(rows[1].ratio_of_median_times == 2.0);  // 20 / 10

  const MethodOutcomes zero = method("ppcr", {0, 0}, {1, 1}, {false, false});
  const MethodOutcomes c = method("pcl-icp", {1, 2}, {1, 1}, {false, false});
  const std::vector<ppcr_bench::ComparisonRow> none = ppcr_bench::compare({zero, c}, 1.0, 0.002);
  CHECK(std::isnan(none[1].median_time_ratio));
  CHECK(std::isnan(none[1].ratio_of_median_times));
}
