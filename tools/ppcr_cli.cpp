// ppcr_cli - register SOURCE onto TARGET with Probabilistic Point Clouds Registration.
//
// Prints the 4x4 transform mapping SOURCE into TARGET's frame (or one JSON object with --json).
// Exit 0 on success; 1 with a one-line error on stderr for bad input or a failed registration;
// 2 for bad command-line usage.
#include <CLI/CLI.hpp>
#include <chrono>
#include <cstdio>
#include <string>

#include "common/registration_flags.hpp"
#include "common/result_output.hpp"
#include "ppcr/io.hpp"
#include "ppcr/metrics.hpp"
#include "ppcr/registration.hpp"
#include "ppcr/version.hpp"

namespace {

int fail(const std::string& message) {
  std::fprintf(stderr, "ppcr_cli: error: %s\n", message.c_str());
  return 1;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{
      "Registers SOURCE onto TARGET with Probabilistic Point Clouds Registration (PPCR) and prints "
      "the 4x4 transform mapping SOURCE into TARGET's frame. Clouds: PLY, PCD, XYZ/CSV.",
      "ppcr_cli"};
  app.set_version_flag("--version", std::string("ppcr_cli ") + PPCR_VERSION_STRING + " (OpenMP " +
                                        PPCR_WITH_OPENMP_STR + ")");
  std::string source_path, target_path, initial_path, gt_path, out_transform, out_cloud, trace;
  bool json = false, verbose = false, quiet = false;
  ppcr_tools::RegistrationFlags flags;
  app.add_option("SOURCE", source_path, "cloud to move (PLY, PCD, XYZ/CSV)")->required();
  app.add_option("TARGET", target_path, "reference cloud")->required();
  ppcr_tools::add_registration_flags(app, &flags);
  app.add_option("--initial", initial_path, "initial guess: a 4x4 rigid transform (text file)");
  app.add_option("--ground-truth", gt_path,
                 "true 4x4 transform mapping SOURCE into TARGET's frame: adds rotation, "
                 "translation and benchmark errors to the result");
  app.add_option("--output-transform", out_transform, "write the 4x4 result to this file");
  app.add_option("--output-cloud", out_cloud,
                 "write the aligned full-resolution source (format by extension)");
  app.add_option("--trace", trace, "write one CSV row per outer iteration");
  app.add_flag("--json", json, "print one JSON object to stdout instead of the matrix");
  app.add_flag("--verbose", verbose, "per-iteration progress on stderr");
  app.add_flag("--quiet", quiet, "nothing on stderr but errors");
  try {
    app.parse(argc, argv);
  } catch (const CLI::CallForHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForAllHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForVersion& e) {
    return app.exit(e);
  } catch (const CLI::ParseError& e) {
    std::fprintf(stderr, "ppcr_cli: error: %s (see --help)\n", e.what());
    return 2;
  }
  if (quiet) verbose = false;

  ppcr::RegistrationOptions options;
  ppcr::Status s = ppcr_tools::to_options(flags, &options);
  if (!s.ok()) {
    std::fprintf(stderr, "ppcr_cli: error: %s\n", s.message().c_str());
    return 2;
  }

  ppcr::PointCloud source, target;
  ppcr::io::ReadReport source_report, target_report;
  s = ppcr::io::read_cloud(source_path, &source, &source_report);
  if (!s.ok()) return fail(s.message());
  s = ppcr::io::read_cloud(target_path, &target, &target_report);
  if (!s.ok()) return fail(s.message());
  if (!quiet) {
    for (const auto* r : {&source_report, &target_report}) {
      if (r->non_finite_dropped > 0) {
        std::fprintf(stderr, "ppcr_cli: %s: dropped %zu non-finite point(s) of %zu\n",
                     r == &source_report ? source_path.c_str() : target_path.c_str(),
                     r->non_finite_dropped, r->points_in_file);
      }
    }
  }
  Eigen::Isometry3d T_initial = Eigen::Isometry3d::Identity(), T_gt;
  if (!initial_path.empty()) {
    s = ppcr::io::read_transform(initial_path, &T_initial);
    if (!s.ok()) return fail("--initial: " + s.message());
  }
  const bool has_gt = !gt_path.empty();
  if (has_gt) {
    s = ppcr::io::read_transform(gt_path, &T_gt);
    if (!s.ok()) return fail("--ground-truth: " + s.message());
  }
  if (verbose) {
    std::fprintf(stderr, "ppcr_cli: source %zu points, target %zu points\n", source.size(),
                 target.size());
    options.on_iteration = [](const ppcr::IterationRecord& r) {
      std::fprintf(stderr,
                   "iter %3d  %-6s  steps %2d/%-2d  cost %.6g -> %.6g  drop %+.3e  scale %.4g  "
                   "pairs %zu  %.1f ms\n",
                   r.iteration, r.coarse ? "coarse" : "fine", r.successful_steps,
                   r.unsuccessful_steps, r.initial_cost, r.final_cost, r.cost_drop, r.scale,
                   r.correspondences, r.time_ms);
      return true;
    };
  }
  options.record_history = !trace.empty();

  const auto start = std::chrono::steady_clock::now();
  const ppcr::RegistrationResult result =
      ppcr::align(source, target, options, T_initial);
  const double time_ms =
      std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();

  ppcr::PoseErrors gt;
  if (has_gt) gt = ppcr::evaluate(source, result.T_target_source, T_gt);
  if (json) {
    std::printf("%s\n",
                ppcr_tools::result_json(result, time_ms, has_gt ? &gt : nullptr).dump(2).c_str());
  }
  if (!result.status.ok()) return fail(result.status.message());

  if (!trace.empty()) {
    s = ppcr_tools::write_trace_csv(trace, result.history, source, has_gt ? &T_gt : nullptr);
    if (!s.ok()) return fail(s.message());
  }
  if (!out_transform.empty()) {
    s = ppcr::io::write_transform(out_transform, result.T_target_source);
    if (!s.ok()) return fail(s.message());
  }
  if (!out_cloud.empty()) {
    ppcr::PointCloud aligned(source.size());
    for (std::size_t i = 0; i < source.size(); ++i) aligned[i] = result.T_target_source * source[i];
    s = ppcr::io::write_cloud(out_cloud, aligned);
    if (!s.ok()) return fail(s.message());
  }
  if (!json) std::printf("%s", ppcr_tools::matrix_text(result.T_target_source.matrix()).c_str());
  if (!quiet) {
    std::fprintf(stderr,
                 "ppcr_cli: %s after %d iterations (%s), %.1f ms, %zu/%zu source points "
                 "matched",
                 result.converged() ? "converged" : "stopped", result.iterations,
                 ppcr::to_string(result.stop_reason), time_ms, result.matched_source_points,
                 result.source_points);
    if (has_gt) {
      std::fprintf(stderr,
                   "; rotation error %.4f deg, translation error %.6g, benchmark error %.6g",
                   gt.rotation_error_deg, gt.translation_error, gt.benchmark_error);
    }
    std::fprintf(stderr, "\n");
  }
  return 0;
}
