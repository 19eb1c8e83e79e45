// summary.cpp - quantiles (numpy's linear interpolation) and the run summary.
#include "bench/summary.hpp"

#include <algorithm>
#include <cmath>
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

}  // namespace ppcr_bench
