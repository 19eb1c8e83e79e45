// summary.hpp - quantiles and the summary of a benchmark run, and its printing.
#pragma once

#include <Eigen/Core>
#include <cstddef>
#include <limits>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

namespace ppcr_bench {

/// Quantile with linear interpolation between order statistics (numpy's default, "type 7").
/// Returns NaN for an empty sample.
double quantile(std::vector<double> values, double q);

struct Summary {
  std::size_t problems = 0;
  double median = 0.0, q75 = 0.0, q95 = 0.0;  // of the benchmark error
  double success = 0.0;                       // fraction in [0, 1]
  double mean_iterations = 0.0;
  double median_ms = 0.0, max_ms = 0.0;
};

struct ProblemOutcome {
  double error = 0.0;  // benchmark error
  double rotation_error_deg = 0.0;
  double translation_error = 0.0;
  int iterations = 0;
  double time_ms = 0.0;
  // The pose error as a twist, delta = log(T_estimate T_true^-1) (rotation first, radians and
  // cloud units: RegistrationResult::covariance's parameterisation), and its normalised squared
  // error delta^T C^-1 delta under the method's covariance C (NaN without one).
  Eigen::Matrix<double, 6, 1> error_twist = Eigen::Matrix<double, 6, 1>::Zero();
  double nees = std::numeric_limits<double>::quiet_NaN();
};

/// e^T C^-1 e (the normalised estimation error squared); NaN when C is not finite or not
/// positive definite.
double normalised_error(const Eigen::Matrix<double, 6, 1>& e, const Eigen::Matrix<double, 6, 6>& C);

/// success: rotation error < success_rotation_deg and translation error < success_translation.
Summary summarize(const std::vector<ProblemOutcome>& outcomes, double success_rotation_deg,
                  double success_translation);

/// What the printed summary says besides the figures.
struct SummaryContext {
  std::string label;         // the method, or --label
  std::size_t failures = 0;  // problems the method failed to run
  double success_rotation_deg = 1.0, success_translation = 0.0;
  bool json = false;  // one JSON object instead of the text lines
};

/// The summary as print_summary's JSON object (method, problems, quantiles, success, iterations,
/// times, failures); a comparison of methods prints one per method.
nlohmann::ordered_json summary_json(const Summary& summary, const SummaryContext& context);

/// Prints the run's summary on stdout: the only printer, for a run and for a merge of shards.
void print_summary(const Summary& summary, const SummaryContext& context);

}  // namespace ppcr_bench
