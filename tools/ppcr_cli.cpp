// ppcr_cli - register SOURCE onto TARGET with Probabilistic Point Clouds Registration.
//
// Prints the 4x4 transform mapping SOURCE into TARGET's frame (or one JSON object with --json).
// Exit 0 on success; 1 with a one-line error on stderr for bad input, a failed registration or
// an output (stdout included) that could not be written; 2 for bad command-line usage; 3 when
// the registration ran and its outputs were written but the result is not to be trusted: its
// verdict is "failed" (RegistrationResult::quality) or its fitness is below --min-fitness.
#include <unistd.h>

#include <CLI/CLI.hpp>
#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <iostream>
#include <string>

#include "common/depth_camera_flags.hpp"
#include "common/openmp_environment.hpp"
#include "common/registration_flags.hpp"
#include "common/result_output.hpp"
#include "common/usage_error.hpp"
#include "ppcr/io.hpp"
#include "ppcr/metrics.hpp"
#include "ppcr/registration.hpp"
#include "ppcr/version.hpp"

namespace {

int fail(const std::string& message) {
  std::fprintf(stderr, "ppcr_cli: error: %s\n", message.c_str());
  return 1;
}

struct Arguments {
  std::string source_path, target_path, initial_path, gt_path;
  std::string out_transform, out_cloud, trace;
  bool json = false, verbose = false, quiet = false;
  double min_fitness = 0.0;
  ppcr::io::DepthCamera depth_camera;
  ppcr_tools::RegistrationFlags flags;
};

const char* kOutputGroup = "Input and output";

void add_arguments(CLI::App& app, Arguments* a) {
  app.add_option("SOURCE", a->source_path,
                 "cloud to move (PLY, PCD, XYZ/CSV, KITTI .bin, or a depth image .png)")
      ->required();
  app.add_option("TARGET", a->target_path, "reference cloud")->required();
  ppcr_tools::add_registration_flags(app, &a->flags);
  ppcr_tools::add_depth_camera_flags(app, &a->depth_camera);
  app.add_option("--initial", a->initial_path, "initial guess: a 4x4 rigid transform (text file)")
      ->check(ppcr_tools::non_empty())
      ->group(kOutputGroup);
  app.add_option("--ground-truth", a->gt_path,
                 "true 4x4 transform mapping SOURCE into TARGET's frame: adds rotation, "
                 "translation and benchmark errors to the result")
      ->check(ppcr_tools::non_empty())
      ->group(kOutputGroup);
  app.add_option("--output-transform", a->out_transform, "write the 4x4 result to this file")
      ->check(ppcr_tools::non_empty())
      ->group(kOutputGroup);
  app.add_option("--output-cloud", a->out_cloud,
                 "write the aligned full-resolution source (format by extension)")
      ->check(ppcr_tools::non_empty())
      ->group(kOutputGroup);
  app.add_option("--trace", a->trace, "write one CSV row per outer iteration")
      ->check(ppcr_tools::non_empty())
      ->group(kOutputGroup);
  app.add_flag("--json", a->json, "print one JSON object to stdout instead of the matrix")
      ->group(kOutputGroup);
  app.add_option("--min-fitness", a->min_fitness,
                 "exit with status 3 when the result's fitness (fraction of source points with a "
                 "target point within the radius) is below this, in [0, 1] (default 0: no check)")
      ->check(ppcr_tools::non_empty())
      ->check(CLI::Range(0.0, 1.0).description(""))  // the help says the range
      ->group(kOutputGroup);
  app.add_flag("--verbose", a->verbose, "per-iteration progress on stderr")->group(kOutputGroup);
  app.add_flag("--quiet", a->quiet, "nothing on stderr but errors")->group(kOutputGroup);
}

// stdout could not take what was printed (a full disk, a closed pipe).
bool stdout_failed() {
  std::cout.flush();
  return std::fflush(stdout) != 0 || std::ferror(stdout) != 0 || !std::cout;
}

// Parses argv; returns -1 to go on, or the exit status (help, version, usage error).
int parse(int argc, char** argv, Arguments* a) {
  CLI::App app{
      "Registers SOURCE onto TARGET with Probabilistic Point Clouds Registration (PPCR) and prints "
      "the 4x4 transform mapping SOURCE into TARGET's frame. Clouds: PLY, PCD, XYZ/CSV, KITTI "
      ".bin; depth images: 16-bit PNG.",
      "ppcr_cli"};
  app.set_version_flag("--version", std::string("ppcr_cli ") + PPCR_VERSION_STRING);
  app.footer(
      "Examples:\n"
      "  ppcr_cli scan.ply map.pcd\n"
      "      prints the 4x4 transform; the radius is automatic\n"
      "  ppcr_cli bun045.ply bun000.ply --radius 0.02 --voxel 0.002 --json --output-cloud out.ply\n"
      "      a radius covering the misalignment, both clouds voxel-filtered; one JSON object\n"
      "      (pose, verdict, fitness) on stdout, the aligned source written\n"
      "\n"
      "Exit status: 0 registered; 1 bad input, a failed registration or an output not written;\n"
      "2 bad command line; 3 registered, but the verdict is failed or the fitness is below\n"
      "--min-fitness.");
  add_arguments(app, a);
  try {
    app.parse(argc, argv);
  } catch (const CLI::CallForHelp& e) {
    const int code = app.exit(e);
    return stdout_failed() ? fail(std::string("stdout: ") + std::strerror(errno)) : code;
  } catch (const CLI::CallForAllHelp& e) {
    const int code = app.exit(e);
    return stdout_failed() ? fail(std::string("stdout: ") + std::strerror(errno)) : code;
  } catch (const CLI::CallForVersion& e) {
    const int code = app.exit(e);
    return stdout_failed() ? fail(std::string("stdout: ") + std::strerror(errno)) : code;
  } catch (const CLI::ParseError& e) {
    std::fprintf(stderr, "ppcr_cli: error: %s (see --help)\n",
                 ppcr_tools::usage_error(app, e, argc, argv).c_str());
    return 2;
  }
  if (a->quiet) a->verbose = false;
  return -1;
}

// Every output path, before the registration runs: not empty, and creatable or writable.
ppcr::Status check_outputs(const Arguments& a) {
  const std::pair<const char*, const std::string*> outputs[] = {
      {"--output-transform", &a.out_transform},
      {"--output-cloud", &a.out_cloud},
      {"--trace", &a.trace}};
  for (const auto& [flag, path] : outputs) {
    if (path->empty()) continue;
    const bool existed = access(path->c_str(), F_OK) == 0;
    std::FILE* f = std::fopen(path->c_str(), "a");
    if (f == nullptr) {
      return ppcr::Status(
          ppcr::StatusCode::kIoError,
          std::string(flag) + " " + *path + ": cannot write: " + std::strerror(errno));
    }
    std::fclose(f);
    if (!existed) std::remove(path->c_str());
  }
  // The cloud's format comes from its extension: an unknown one is bad usage, refused now rather
  // than after the registration.
  const ppcr::io::Format out_format = ppcr::io::format_from_extension(a.out_cloud);
  if (!a.out_cloud.empty() &&
      (out_format == ppcr::io::Format::kAuto || out_format == ppcr::io::Format::kDepthPng)) {
    return ppcr::Status(ppcr::StatusCode::kInvalidArgument,
                        "--output-cloud " + a.out_cloud +
                            ": not a cloud format to write; expected .ply, .pcd, .xyz, .txt, .csv, "
                            ".pts or .bin (KITTI)");
  }
  return ppcr::Status::Ok();
}

struct Inputs {
  ppcr::PointCloud source, target;
  ppcr::io::ReadReport source_report, target_report;
  Eigen::Isometry3d T_initial = Eigen::Isometry3d::Identity();
  Eigen::Isometry3d T_gt = Eigen::Isometry3d::Identity();
  bool has_gt = false;
};

ppcr::Status read_inputs(const Arguments& a, Inputs* in) {
  ppcr::Status s =
      ppcr::io::read_cloud(a.source_path, a.depth_camera, &in->source, &in->source_report);
  if (s.ok()) {
    s = ppcr::io::read_cloud(a.target_path, a.depth_camera, &in->target, &in->target_report);
  }
  if (!s.ok()) return s;
  if (!a.initial_path.empty()) {
    s = ppcr::io::read_transform(a.initial_path, &in->T_initial);
    if (!s.ok()) return ppcr::Status(s.code(), "--initial: " + s.message());
  }
  in->has_gt = !a.gt_path.empty();
  if (in->has_gt) {
    s = ppcr::io::read_transform(a.gt_path, &in->T_gt);
    if (!s.ok()) return ppcr::Status(s.code(), "--ground-truth: " + s.message());
  }
  if (!a.quiet) {
    for (const auto* r : {&in->source_report, &in->target_report}) {
      if (r->non_finite_dropped == 0) continue;
      std::fprintf(stderr, "ppcr_cli: %s: dropped %zu non-finite point(s) of %zu\n",
                   r == &in->source_report ? a.source_path.c_str() : a.target_path.c_str(),
                   r->non_finite_dropped, r->points_in_file);
    }
  }
  return ppcr::Status::Ok();
}

void print_iteration(const ppcr::IterationRecord& r) {
  std::fprintf(stderr,
               "iter %3d  %-6s  steps %2d/%-2d  cost %.6g -> %.6g  drop %+.3e  scale %.4g  "
               "pairs %zu  %.1f ms\n",
               r.iteration, r.coarse ? "coarse" : "fine", r.successful_steps, r.unsuccessful_steps,
               r.initial_cost, r.final_cost, r.cost_drop, r.scale, r.correspondences, r.time_ms);
}

ppcr::Status write_outputs(const Arguments& a, const Inputs& in,
                           const ppcr::RegistrationResult& result) {
  ppcr::Status s;
  if (!a.trace.empty()) {
    s = ppcr_tools::write_trace_csv(a.trace, result.history, in.source,
                                    in.has_gt ? &in.T_gt : nullptr);
    if (!s.ok()) return s;
  }
  if (!a.out_transform.empty()) {
    s = ppcr::io::write_transform(a.out_transform, result.T_target_source);
    if (!s.ok()) return s;
  }
  if (!a.out_cloud.empty()) {
    ppcr::PointCloud aligned(in.source.size());
    for (std::size_t i = 0; i < in.source.size(); ++i) {
      aligned[i] = result.T_target_source * in.source[i];
    }
    s = ppcr::io::write_cloud(a.out_cloud, aligned);
  }
  return s;
}

void print_summary(const ppcr::RegistrationResult& result, double time_ms,
                   const ppcr::PoseErrors* gt) {
  std::fprintf(stderr,
               "ppcr_cli: %s after %d iterations (%s), %.1f ms; quality %s; fitness %.4f, inlier "
               "RMSE %.6g, overlap %.4f, on the surface %.4f; radius %.6g",
               result.converged() ? "converged" : "stopped", result.iterations,
               ppcr::to_string(result.stop_reason), time_ms, ppcr::to_string(result.quality),
               result.fitness, result.inlier_rmse, result.overlap, result.close_fraction,
               result.radius);
  if (result.status.ok() && result.iterations > 0) {
    // The loosest direction of each block of the covariance, as 1-sigma.
    const auto largest = [](const Eigen::Matrix3d& block) {
      return std::sqrt(
          std::max(Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(block, Eigen::EigenvaluesOnly)
                       .eigenvalues()[2],
                   0.0));
    };
    const double degrees_per_radian = 180.0 / std::acos(-1.0);
    std::fprintf(stderr, "; 1-sigma %.2g deg, %.2g",
                 largest(result.covariance.topLeftCorner<3, 3>()) * degrees_per_radian,
                 largest(result.covariance.bottomRightCorner<3, 3>()));
  }
  if (gt != nullptr) {
    std::fprintf(stderr, "; rotation error %.4f deg, translation error %.6g, benchmark error %.6g",
                 gt->rotation_error_deg, gt->translation_error, gt->benchmark_error);
  }
  std::fprintf(stderr, "\n");
  if (result.source_duplicates + result.target_duplicates > 0) {
    std::fprintf(stderr,
                 "ppcr_cli: copies of a point registered once: %zu in the source, %zu in the "
                 "target\n",
                 result.source_duplicates, result.target_duplicates);
  }
}

// The exit status of a registration that ran: 3 when its verdict is failed or its fitness is
// below --min-fitness (with the reason on stderr), else 0; a weak verdict is a warning.
int judge(const Arguments& a, const ppcr::RegistrationResult& result) {
  if (result.fitness < a.min_fitness) {
    std::fprintf(stderr, "ppcr_cli: error: fitness %.4f is below --min-fitness %g\n",
                 result.fitness, a.min_fitness);
    return 3;
  }
  if (result.quality == ppcr::Quality::kFailed) {
    std::fprintf(stderr, "ppcr_cli: error: the registration failed its quality check: %s\n",
                 result.quality_reason);
    return 3;
  }
  if (result.quality == ppcr::Quality::kWeak && !a.quiet) {
    std::fprintf(stderr, "ppcr_cli: warning: weak result: %s\n", result.quality_reason);
  }
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  ppcr_tools::use_passive_openmp_threads(argv);  // idle OpenMP threads sleep
  Arguments a;
  const int parsed = parse(argc, argv, &a);
  if (parsed >= 0) return parsed;
  ppcr::RegistrationOptions options;
  ppcr::Status s = ppcr_tools::to_options(a.flags, &options);
  if (!s.ok()) {
    std::fprintf(stderr, "ppcr_cli: error: %s\n", s.message().c_str());
    return 2;
  }
  s = check_outputs(a);
  if (s.code() == ppcr::StatusCode::kInvalidArgument) {
    std::fprintf(stderr, "ppcr_cli: error: %s\n", s.message().c_str());
    return 2;
  }
  if (!s.ok()) return fail(s.message());
  Inputs in;
  s = read_inputs(a, &in);
  if (!s.ok()) return fail(s.message());
  if (a.verbose) {
    std::fprintf(stderr, "ppcr_cli: source %zu points, target %zu points\n", in.source.size(),
                 in.target.size());
    options.on_iteration = [](const ppcr::IterationRecord& r) {
      print_iteration(r);
      return true;
    };
  }
  options.record_history = !a.trace.empty();

  const auto start = std::chrono::steady_clock::now();
  // A Registration rather than ppcr::align(), so that the clouds as read are freed once the
  // registration holds its prepared copies (24 B per point less at the peak; the source only
  // when no output reads it), and the registration's buffers before the outputs are written.
  // A refused target makes align() refused with its status.
  ppcr::RegistrationResult result;
  {
    ppcr::Registration registration(options);
    (void)registration.set_target(in.target);
    ppcr::PointCloud().swap(in.target);
    const bool source_read_after = in.has_gt || !a.trace.empty() || !a.out_cloud.empty();
    result = source_read_after ? registration.align(in.source, in.T_initial)
                               : registration.align(std::move(in.source), in.T_initial);
  }
  const double time_ms =
      std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
  // The points the readers dropped count with those the registration dropped.
  result.source_non_finite += in.source_report.non_finite_dropped;
  result.target_non_finite += in.target_report.non_finite_dropped;
  ppcr::PoseErrors gt;
  if (in.has_gt) gt = ppcr::evaluate(in.source, result.T_target_source, in.T_gt);
  if (a.json) {
    std::printf("%s\n",
                ppcr_tools::result_json(
                    result, time_ms, options.radius == ppcr::RegistrationOptions::kAutomaticRadius,
                    in.has_gt ? &gt : nullptr)
                    .dump(2)
                    .c_str());
  }
  if (!result.status.ok()) return fail(ppcr_tools::with_flag_names(result.status).message());
  s = write_outputs(a, in, result);
  if (!s.ok()) return fail(s.message());
  if (!a.json) std::printf("%s", ppcr_tools::matrix_text(result.T_target_source.matrix()).c_str());
  if (stdout_failed()) return fail(std::string("stdout: write failed: ") + std::strerror(errno));
  if (!a.quiet) print_summary(result, time_ms, in.has_gt ? &gt : nullptr);
  return judge(a, result);
}
