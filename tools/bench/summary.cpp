// summary.cpp - quantiles (numpy's linear interpolation), the run summary and its printing.
#include "bench/summary.hpp"

#include <Eigen/Cholesky>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>

namespace ppcr_bench {

double quantile(std::vector<double> v, double q) {
  if (v.empty()) return std::numeric_limits<double>::quiet_NaN();
  std::sort(v.begin(), v.end());
  const double position = q * static_cast<double>(v.size() - 1);
  const std::size_t lo = static_cast<std::size_t>(std::floor(position));
  const std::size_t hi = std::min(lo + 1, v.size() - 1);
  const double f = position - static_cast<double>(lo);
  return v[lo] + f * (v[hi] - v[lo]);
}

double normalised_error(const Eigen::Matrix<double, 6, 1>& e,
                        const Eigen::Matrix<double, 6, 6>& C) {
  const Eigen::LDLT<Eigen::Matrix<double, 6, 6>> ldlt(C);
  if (!C.allFinite() || ldlt.info() != Eigen::Success || !ldlt.isPositive() ||
      !(ldlt.vectorD().minCoeff() > 0.0)) {
    return std::numeric_limits<double>::quiet_NaN();
  }
  return e.dot(ldlt.solve(e));
}

Summary summarize(const std::vector<ProblemOutcome>& outcomes, double success_rotation_deg,
                  double success_translation) {
  Summary s;
  s.problems = outcomes.size();
  if (outcomes.empty()) return s;
  std::vector<double> errors, times;
  std::size_t successes = 0;
  double iterations = 0.0;
  for (const ProblemOutcome& o : outcomes) {
    errors.push_back(o.error);
    times.push_back(o.time_ms);
    iterations += o.iterations;
    if (o.rotation_error_deg < success_rotation_deg && o.translation_error < success_translation) {
      ++successes;
    }
  }
  s.median = quantile(errors, 0.5);
  s.q75 = quantile(errors, 0.75);
  s.q95 = quantile(errors, 0.95);
  s.success = static_cast<double>(successes) / static_cast<double>(outcomes.size());
  s.mean_iterations = iterations / static_cast<double>(outcomes.size());
  s.median_ms = quantile(times, 0.5);
  s.max_ms = *std::max_element(times.begin(), times.end());
  return s;
}

nlohmann::ordered_json summary_json(const Summary& sum, const SummaryContext& c) {
  nlohmann::ordered_json j;
  j["method"] = c.label;
  j["problems"] = sum.problems;
  j["median"] = sum.median;
  j["q75"] = sum.q75;
  j["q95"] = sum.q95;
  j["success"] = sum.success;
  j["mean_iterations"] = sum.mean_iterations;
  j["median_ms"] = sum.median_ms;
  j["max_ms"] = sum.max_ms;
  j["failures"] = c.failures;
  return j;
}

void print_summary(const Summary& sum, const SummaryContext& c) {
  if (c.json) {
    std::printf("%s\n", summary_json(sum, c).dump().c_str());
    return;
  }
  std::printf("method %s, %zu problems (%zu failed to run)\n", c.label.c_str(), sum.problems,
              c.failures);
  std::printf("error median %.6g  q0.75 %.6g  q0.95 %.6g\n", sum.median, sum.q75, sum.q95);
  std::printf("success %.1f %% (rotation < %g deg, translation < %g)\n", 100.0 * sum.success,
              c.success_rotation_deg, c.success_translation);
  std::printf("mean iterations %.2f  time median %.1f ms  max %.1f ms\n", sum.mean_iterations,
              sum.median_ms, sum.max_ms);
}

}  // namespace ppcr_bench
