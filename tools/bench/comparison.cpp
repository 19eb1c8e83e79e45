// comparison.cpp - the methods' summaries side by side and their time ratios.
#include "bench/comparison.hpp"

#include <cstdio>
#include <limits>

namespace ppcr_bench {
namespace {

double time_ratio(const std::vector<ProblemOutcome>& method,
                  const std::vector<ProblemOutcome>& first) {
  std::vector<double> ratios;
  for (std::size_t k = 0; k < method.size() && k < first.size(); ++k) {
    if (first[k].time_ms > 0.0) ratios.push_back(method[k].time_ms / first[k].time_ms);
  }
  return quantile(ratios, 0.5);  // NaN when empty
}

}  // namespace

std::vector<ComparisonRow> compare(const std::vector<MethodOutcomes>& methods,
                                   double success_rotation_deg, double success_translation) {
  std::vector<ComparisonRow> rows;
  for (const MethodOutcomes& m : methods) {
    ComparisonRow row;
    row.label = m.label;
    row.summary = summarize(m.outcomes, success_rotation_deg, success_translation);
    row.failures = m.failures;
    row.median_time_ratio = time_ratio(m.outcomes, methods.front().outcomes);
    rows.push_back(row);
  }
  const double first_ms = rows.empty() ? 0.0 : rows.front().summary.median_ms;
  for (ComparisonRow& row : rows) {
    row.ratio_of_median_times = first_ms > 0.0 ? row.summary.median_ms / first_ms
                                               : std::numeric_limits<double>::quiet_NaN();
  }
  return rows;
}

void print_comparison(const std::vector<ComparisonRow>& rows, double success_rotation_deg,
                      double success_translation, bool json) {
  if (rows.empty()) return;
  const std::string& first = rows.front().label;
  if (json) {
    nlohmann::ordered_json j;
    j["problems"] = rows.front().summary.problems;
    j["ratio_to"] = first;
    j["methods"] = nlohmann::ordered_json::array();
    for (const ComparisonRow& r : rows) {
      nlohmann::ordered_json m = summary_json(
          r.summary, {r.label, r.failures, success_rotation_deg, success_translation, true});
      m["median_time_ratio"] = r.median_time_ratio;
      m["ratio_of_median_times"] = r.ratio_of_median_times;
      j["methods"].push_back(m);
    }
    std::printf("%s\n", j.dump().c_str());
    return;
  }
  std::printf(
      "%zu methods on the same %zu problems; success: rotation < %g deg and translation < %g; "
      "time ratio to %s: the median of the per-problem ratios, and the ratio of the median "
      "times\n",
      rows.size(), rows.front().summary.problems, success_rotation_deg, success_translation,
      first.c_str());
  std::printf(
      "| method | failed | median error | q0.75 error | q0.95 error | success | mean iterations "
      "| median ms | time ratio, median per problem | ratio of median times |\n"
      "|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n");
  for (const ComparisonRow& r : rows) {
    const Summary& s = r.summary;
    std::printf("| %s | %zu | %.6g | %.6g | %.6g | %.1f %% | %.2f | %.1f | %.3g | %.3g |\n",
                r.label.c_str(), r.failures, s.median, s.q75, s.q95, 100.0 * s.success,
                s.mean_iterations, s.median_ms, r.median_time_ratio, r.ratio_of_median_times);
  }
}

}  // namespace ppcr_bench
