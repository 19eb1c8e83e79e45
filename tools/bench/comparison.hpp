// comparison.hpp - several methods run on the same problems (ppcr_bench --methods a,b,...): each
// method's summary beside the others', with its time relative to the first method's, printed as
// one table (or one JSON object).
#pragma once

#include <cstddef>
#include <string>
#include <vector>

#include "bench/summary.hpp"

namespace ppcr_bench {

/// One method's outcomes, outcome k being problem k for every method of the comparison.
struct MethodOutcomes {
  std::string label;
  std::vector<ProblemOutcome> outcomes;
  std::size_t failures = 0;  // problems the method failed to run
};

struct ComparisonRow {
  std::string label;
  Summary summary;
  std::size_t failures = 0;
  // Time relative to the first method: the median over the problems of this method's time over
  // the first method's on the same problem, and the ratio of the two median times. NaN when the
  // first method has no positive time.
  double median_time_ratio = 0.0;
  double ratio_of_median_times = 0.0;
};

/// The rows, in the order of `methods`; every method must have the first method's problem count.
std::vector<ComparisonRow> compare(const std::vector<MethodOutcomes>& methods,
                                   double success_rotation_deg, double success_translation);

/// Prints the comparison on stdout: a Markdown table with a line saying what the columns are,
/// or, with json, one object {"problems", "ratio_to", "methods": [summary_json + the ratios]}.
void print_comparison(const std::vector<ComparisonRow>& rows, double success_rotation_deg,
                      double success_translation, bool json);

}  // namespace ppcr_bench
