// ppcr_bench - the point clouds registration benchmark's protocol on a problem file.
//
// For each problem: P = the source cloud (already in the ground-truth frame), S = T0 P; S and
// the target are voxel-filtered once (the same input for every method); the method registers S
// onto the target from identity, giving T_est; the error is the benchmark's
//   e = mean_i |P_i - Q_i| / |P_i - c|,  Q = T_est S,  c = centroid of P,
// on the full-resolution source, with the rotation and translation errors of T_est against
// T0^-1. Time is the method's registration call only (no I/O, no filtering).
//
// --methods a,b,... runs several methods on the same problems in one process, every method on a
// problem before the next problem (starting with a different method each problem), so that a
// change of the machine's load hits all alike, and prints one table with each method's time
// relative to the first's (comparison.hpp). --shard I/N runs the problems i with i mod N = I (a
// batch over processes or hosts); --merge puts the shards' CSVs back together and prints the
// unsharded run's summary (merge.hpp).
#include <unistd.h>

#include <CLI/CLI.hpp>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "bench/comparison.hpp"
#include "bench/merge.hpp"
#include "bench/method.hpp"
#include "bench/problems.hpp"
#include "bench/results_csv.hpp"
#include "bench/run_settings.hpp"
#include "bench/shard.hpp"
#include "bench/summary.hpp"
#include "common/openmp_environment.hpp"
#include "common/registration_flags.hpp"
#include "common/result_output.hpp"
#include "common/usage_error.hpp"
#include "ppcr/io.hpp"
#include "ppcr/metrics.hpp"
#include "ppcr/se3.hpp"
#include "ppcr/version.hpp"
#include "ppcr/voxel.hpp"

namespace {

int fail(const std::string& message) {
  std::fprintf(stderr, "ppcr_bench: error: %s\n", message.c_str());
  return 1;
}

std::string folder_of(const std::string& path) {
  const std::size_t slash = path.find_last_of('/');
  return slash == std::string::npos ? "." : path.substr(0, slash);
}

// Clouds read once per path, and their voxel-filtered versions.
class CloudCache {
 public:
  CloudCache(std::string root, double target_voxel)
      : root_(std::move(root)), voxel_(target_voxel) {}

  ppcr::Status raw(const std::string& path, const ppcr::PointCloud** cloud) {
    auto it = raw_.find(path);
    if (it == raw_.end()) {
      ppcr::PointCloud c;
      ppcr::Status s = ppcr::io::read_cloud(root_ + "/" + path, &c);
      if (!s.ok()) return s;
      it = raw_.emplace(path, std::move(c)).first;
    }
    *cloud = &it->second;
    return ppcr::Status::Ok();
  }

  ppcr::Status filtered_target(const std::string& path, const ppcr::PointCloud** cloud) {
    auto it = filtered_.find(path);
    if (it == filtered_.end()) {
      const ppcr::PointCloud* raw_cloud = nullptr;
      ppcr::Status s = raw(path, &raw_cloud);
      if (!s.ok()) return s;
      ppcr::PointCloud c = *raw_cloud;
      if (voxel_ > 0.0) {
        s = ppcr::voxel_downsample(*raw_cloud, voxel_, &c);
        if (!s.ok()) return s;
      }
      it = filtered_.emplace(path, std::move(c)).first;
    }
    *cloud = &it->second;
    return ppcr::Status::Ok();
  }

 private:
  std::string root_;
  double voxel_;
  std::map<std::string, ppcr::PointCloud> raw_, filtered_;
};

void progress(std::size_t done, std::size_t total, double last_error) {
  const int width = 30;
  const int filled = static_cast<int>(width * done / (total ? total : 1));
  std::fprintf(stderr, "\r[%.*s%*s] %zu/%zu  last e=%.5f", filled, "##############################",
               width - filled, "", done, total, last_error);
  if (done == total) std::fprintf(stderr, "\n");
  std::fflush(stderr);
}

struct Arguments {
  std::string problems_path, data_root, method_name = "ppcr", out_csv, trace_dir, label;
  std::string shard_text;
  ppcr_bench::Shard shard;
  std::vector<std::string> merge;    // the shards' CSVs
  std::vector<std::string> methods;  // --methods, or the one --method
  int limit = 0;
  bool json = false, quiet = false, reuse = false;
  double success_translation = -1.0, success_rotation = 1.0, ndt_resolution = 0.0;
  ppcr_tools::RegistrationFlags flags;
};

void add_arguments(CLI::App& app, Arguments* a) {
  app.add_option("PROBLEMS", a->problems_path,
                 "problem file (id source target overlap t1..t12); required unless --merge");
  app.add_option("--data-root", a->data_root,
                 "folder the problem file's cloud paths are relative to (default: its folder)");
  ppcr_tools::add_registration_flags(app, &a->flags);
  std::string method_help = "registration method:";
  for (const std::string& n : ppcr_bench::available_methods()) method_help += " " + n;
  app.add_option("--method", a->method_name, method_help + " (default ppcr)");
  app.add_option("--methods", a->methods,
                 "A,B,...: run these methods on the same problems, every method on a problem "
                 "before the next problem, and print one table with each one's time relative to "
                 "the first's (--out: every method's rows)")
      ->delimiter(',')
      ->type_name("LIST");
  app.add_option("--limit", a->limit, "run only the first N problems");
  app.add_option("--out", a->out_csv, "write one CSV row per problem");
  app.add_option("--shard", a->shard_text,
                 "I/N: run only the problems i (0-based, in file order) with i mod N = I; merge "
                 "the N shards' --out CSVs with --merge")
      ->type_name("I/N");
  app.add_option("--merge", a->merge,
                 "CSV...: instead of running, merge the --out CSVs of the shards of one run and "
                 "print its summary (--json), and write the whole run's CSV with --out")
      ->expected(1, 1 << 20)
      ->type_name("CSV...");
  app.add_flag("--json", a->json, "print the summary as one JSON object");
  app.add_option("--trace-dir", a->trace_dir,
                 "ppcr: write DIR/<id>.csv, one row per outer iteration, with the MSE and "
                 "benchmark error w.r.t. the ground truth (on the registered, filtered source)");
  app.add_flag("--quiet", a->quiet, "no progress bar");
  app.add_option("--label", a->label,
                 "name of this run in the summary and CSV (default: the method)");
  app.add_flag("--reuse", a->reuse,
               "ppcr: one ppcr::Registration for every problem (set_target + align per problem, "
               "the loop usage) instead of ppcr::align per problem; same results");
  app.add_option("--ndt-resolution", a->ndt_resolution,
                 "pcl-ndt cell size, cloud units (default 2 x radius)");
  app.add_option("--success-translation", a->success_translation,
                 "success bound on the translation error, cloud units (default 10 x radius / 100"
                 ", e.g. 2 mm for radius 0.02, 10 cm for radius 1)");
  app.add_option("--success-rotation", a->success_rotation,
                 "success bound on the rotation error, degrees (default 1)");
}

int usage_error(const std::string& message) {
  std::fprintf(stderr, "ppcr_bench: error: %s (see --help)\n", message.c_str());
  return 2;
}

// With --merge only the output flags apply: the shards' CSVs carry the run's settings.
int check_merge_flags(const CLI::App& app) {
  for (const CLI::Option* o : app.get_options()) {
    const std::string name = ppcr_bench::flag_name(*o);
    if (o->count() > 0 && name != "--merge" && name != "--json" && name != "--out" &&
        name != "--quiet") {
      return usage_error("--merge takes the shards' CSVs, --out, --json and --quiet only, got " +
                         name + " (the shards' CSVs carry the run's settings)");
    }
  }
  return -1;
}

std::string method_names() {
  std::string names;
  for (const std::string& n : ppcr_bench::available_methods()) names += " " + n;
  return names;
}

// Sets a->methods (--methods, or the one --method) and a->method_name (the names as given) and
// checks them and the flags that take one method; returns -1 to go on, or the exit status.
int check_methods(const CLI::App& app, Arguments* a) {
  if (app.count("--methods") == 0) {
    a->methods = {a->method_name};
    return -1;
  }
  if (app.count("--method") > 0) return usage_error("give --method or --methods, not both");
  a->method_name.clear();
  for (const std::string& name : a->methods) {
    a->method_name += (a->method_name.empty() ? "" : ",") + name;
  }
  const std::vector<std::string> available = ppcr_bench::available_methods();
  for (std::size_t k = 0; k < a->methods.size(); ++k) {
    const std::string& name = a->methods[k];
    if (std::find(available.begin(), available.end(), name) == available.end()) {
      return fail("--methods " + a->method_name + ": '" + name + "' is unknown or not built " +
                  "(available:" + method_names() + ")");
    }
    if (std::find(a->methods.begin(), a->methods.begin() + k, name) != a->methods.begin() + k) {
      return fail("--methods " + a->method_name + ": '" + name + "' is given twice");
    }
  }
  if (a->methods.size() > 1) {
    for (const char* one : {"--label", "--trace-dir", "--shard"}) {
      if (app.count(one) > 0) {
        return usage_error(
            std::string(one) + " takes one method, got --methods " + a->method_name +
            (std::string(one) == "--shard" ? " (a merge reads one method's shards)" : ""));
      }
    }
  }
  return -1;
}

// Parses argv into *a and *options; returns -1 to go on, or the exit status.
int parse(CLI::App& app, int argc, char** argv, Arguments* a, ppcr::RegistrationOptions* options) {
  app.set_version_flag("--version", std::string("ppcr_bench ") + PPCR_VERSION_STRING);
  add_arguments(app, a);
  try {
    app.parse(argc, argv);
  } catch (const CLI::CallForHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForVersion& e) {
    return app.exit(e);
  } catch (const CLI::ParseError& e) {
    return usage_error(ppcr_tools::usage_error(app, e, argc, argv));
  }
  if (!a->merge.empty()) return check_merge_flags(app);
  if (a->problems_path.empty()) return usage_error("PROBLEMS is required (or --merge CSV...)");
  if (!a->shard_text.empty()) {
    const ppcr::Status s = ppcr_bench::parse_shard(a->shard_text, &a->shard);
    if (!s.ok()) return usage_error(s.message());
  }
  const ppcr::Status s = ppcr_tools::to_options(a->flags, options);
  if (!s.ok()) {
    std::fprintf(stderr, "ppcr_bench: error: %s\n", s.message().c_str());
    return 2;
  }
  if (a->limit < 0) return fail("--limit " + std::to_string(a->limit) + ": expected >= 0");
  const int methods = check_methods(app, a);
  if (methods >= 0) return methods;
  const std::string flag = a->methods.size() > 1 ? "--methods " : "--method ";
  if (a->reuse && a->methods != std::vector<std::string>{"ppcr"}) {
    return fail("--reuse is for --method ppcr alone (beside others: the method ppcr-reuse), got " +
                flag + a->method_name);
  }
  // Every method gets the same filtered clouds, filtered here with one leaf per cloud.
  if (options->source_voxel == ppcr::RegistrationOptions::kAutomaticVoxel ||
      options->target_voxel == ppcr::RegistrationOptions::kAutomaticVoxel) {
    return fail("--voxel auto: ppcr_bench filters every method's clouds itself; give a leaf");
  }
  const bool automatic = options->radius == ppcr::RegistrationOptions::kAutomaticRadius;
  for (const std::string& name : a->methods) {
    if (automatic && name.rfind("ppcr", 0) != 0) {
      return fail(flag + a->method_name + ": " + name +
                  " needs --radius (only ppcr has an automatic one)");
    }
  }
  if (automatic && a->success_translation < 0.0) {
    return fail(
        "--success-translation is needed with an automatic radius (its default is a "
        "tenth of --radius)");
  }
  if (a->success_translation < 0.0) a->success_translation = 0.1 * options->radius;
  return -1;
}

std::unique_ptr<ppcr_bench::Method> make_method(const Arguments& a, const std::string& name,
                                                const ppcr::RegistrationOptions& options) {
  ppcr_bench::MethodSettings settings;
  settings.ppcr = options;
  settings.max_correspondence = options.radius;
  settings.ndt_resolution = a.ndt_resolution > 0.0 ? a.ndt_resolution : 2.0 * options.radius;
  settings.max_iterations = options.max_iterations;
  settings.threads = options.num_threads;
  settings.reuse_registration = a.reuse;
  std::unique_ptr<ppcr_bench::Method> method = ppcr_bench::make_method(name, settings);
  if (method && !a.trace_dir.empty()) method->set_trace(true);
  return method;
}

// One problem's input, the same for every method: S = T0 P, filtered like the target.
struct ProblemInput {
  ppcr::PointCloud S, S_filtered;
  const ppcr::PointCloud* target = nullptr;
  Eigen::Isometry3d T_gt = Eigen::Isometry3d::Identity();
};

ppcr::Status prepare_problem(const ppcr_bench::Problem& p, const ppcr::RegistrationOptions& options,
                             CloudCache* cache, ProblemInput* in) {
  const ppcr::PointCloud* P = nullptr;
  ppcr::Status s = cache->raw(p.source, &P);
  if (s.ok()) s = cache->filtered_target(p.target, &in->target);
  if (!s.ok()) return s;
  in->S.resize(P->size());
  for (std::size_t k = 0; k < P->size(); ++k) in->S[k] = p.T0 * (*P)[k];
  in->S_filtered = in->S;
  if (options.source_voxel > 0.0) {
    s = ppcr::voxel_downsample(in->S, options.source_voxel, &in->S_filtered);
    if (!s.ok()) return ppcr::Status(s.code(), "source: " + s.message());
  }
  in->T_gt = p.T0.inverse();
  return ppcr::Status::Ok();
}

// One method on one problem: its registration call alone is timed; the errors are evaluated
// afterwards on the full-resolution S.
ppcr::Status run_problem(const ppcr_bench::Problem& p, const Arguments& a, const ProblemInput& in,
                         ppcr_bench::Method* method, ppcr_bench::ProblemRow* run) {
  const auto start = std::chrono::steady_clock::now();
  run->result = method->run(in.S_filtered, *in.target);
  const double ms =
      std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
  if (!a.trace_dir.empty()) {
    const ppcr::Status s = ppcr_tools::write_trace_csv(
        a.trace_dir + "/" + p.id + ".csv", run->result.history, in.S_filtered, &in.T_gt);
    if (!s.ok()) return s;
  }
  const ppcr::PoseErrors e = ppcr::evaluate(in.S, run->result.T_target_source, in.T_gt);
  run->outcome.error = e.benchmark_error;
  run->outcome.rotation_error_deg = e.rotation_error_deg;
  run->outcome.translation_error = e.translation_error;
  run->outcome.iterations = run->result.iterations;
  run->outcome.error_twist = ppcr::se3::log(run->result.T_target_source * in.T_gt.inverse());
  run->outcome.nees =
      ppcr_bench::normalised_error(run->outcome.error_twist, run->result.covariance);
  run->outcome.time_ms = ms;
  run->source_points = in.S_filtered.size();
  run->target_points = in.target->size();
  return ppcr::Status::Ok();
}

int merge(const Arguments& a) {
  ppcr_bench::MergedRun m;
  ppcr::Status s = ppcr_bench::merge_shards(a.merge, &m);
  if (s.ok() && !a.out_csv.empty()) s = ppcr_bench::write_merged_csv(a.out_csv, m);
  if (!s.ok()) return fail(s.message());
  const ppcr_bench::RunInfo& r = m.run;
  ppcr_bench::print_summary(
      ppcr_bench::summarize(m.outcomes, r.success_rotation_deg, r.success_translation),
      {r.label, m.failures, r.success_rotation_deg, r.success_translation, a.json});
  return 0;
}

// The problems, after --limit; errors name the file and line.
ppcr::Status load_problems(Arguments* a, std::vector<ppcr_bench::Problem>* problems) {
  const ppcr::Status s = ppcr_bench::read_problems(a->problems_path, problems);
  if (!s.ok()) return s;
  if (a->limit > 0 && static_cast<std::size_t>(a->limit) < problems->size()) {
    problems->resize(a->limit);
  }
  if (a->data_root.empty()) a->data_root = folder_of(a->problems_path);
  return ppcr::Status::Ok();
}

// One method of the run, and what it has produced so far.
struct MethodRun {
  std::unique_ptr<ppcr_bench::Method> method;
  ppcr_bench::RunInfo info;
  ppcr_bench::MethodOutcomes done;
};

// Makes a.methods' methods into *runs; returns -1 to go on, or the exit status.
int make_methods(const CLI::App& app, const Arguments& a, const ppcr::RegistrationOptions& options,
                 const std::vector<ppcr_bench::Problem>& problems, std::vector<MethodRun>* runs) {
  for (const std::string& name : a.methods) {
    MethodRun r;
    r.method = make_method(a, name, options);
    if (!r.method) {
      return fail("--method " + name + ": unknown or not built (available:" + method_names() + ")");
    }
    r.info = {a.label.empty() ? r.method->name() : a.label, ppcr_bench::run_settings(app, problems),
              problems.size(), a.success_rotation, a.success_translation};
    r.done.label = r.info.label;
    runs->push_back(std::move(r));
  }
  return -1;
}

// Every method on one problem, starting with method (turn mod M) so that none always runs first;
// the CSV rows go out in the methods' order.
ppcr::Status run_methods(const ppcr_bench::Problem& p, std::size_t index, std::size_t turn,
                         const Arguments& a, const ProblemInput& input, std::FILE* csv,
                         std::vector<MethodRun>* runs) {
  std::vector<ppcr_bench::ProblemRow> rows(runs->size());
  for (std::size_t k = 0; k < runs->size(); ++k) {
    const std::size_t m = (turn + k) % runs->size();
    rows[m].index = index;
    rows[m].id = p.id;
    const ppcr::Status s = run_problem(p, a, input, (*runs)[m].method.get(), &rows[m]);
    if (!s.ok()) return s;
  }
  for (std::size_t m = 0; m < runs->size(); ++m) {
    MethodRun& r = (*runs)[m];
    r.done.outcomes.push_back(rows[m].outcome);
    if (!rows[m].result.ok) ++r.done.failures;
    if (csv != nullptr) std::fputs(ppcr_bench::format_row(r.info, rows[m]).c_str(), csv);
  }
  return ppcr::Status::Ok();
}

// One method: its summary as always; several: the comparison table.
void print_results(const Arguments& a, const std::vector<MethodRun>& runs) {
  if (runs.size() == 1) {
    const ppcr_bench::MethodOutcomes& d = runs.front().done;
    ppcr_bench::print_summary(
        ppcr_bench::summarize(d.outcomes, a.success_rotation, a.success_translation),
        {d.label, d.failures, a.success_rotation, a.success_translation, a.json});
    return;
  }
  std::vector<ppcr_bench::MethodOutcomes> methods;
  for (const MethodRun& r : runs) methods.push_back(r.done);
  ppcr_bench::print_comparison(
      ppcr_bench::compare(methods, a.success_rotation, a.success_translation), a.success_rotation,
      a.success_translation, a.json);
}

// Runs this shard's problems (every problem without --shard) with every method, writes --out,
// prints the summary or the comparison.
int run(const CLI::App& app, Arguments a, const ppcr::RegistrationOptions& options) {
  std::vector<ppcr_bench::Problem> problems;
  ppcr::Status s = load_problems(&a, &problems);
  if (!s.ok()) return fail(s.message());
  std::vector<MethodRun> runs;
  const int made = make_methods(app, a, options, problems, &runs);
  if (made >= 0) return made;
  std::FILE* csv = nullptr;
  if (!a.out_csv.empty()) {
    csv = std::fopen(a.out_csv.c_str(), "w");
    if (csv == nullptr) return fail(a.out_csv + ": cannot open for writing");
    std::fprintf(csv, "%s\n", ppcr_bench::csv_header().c_str());
  }
  std::vector<std::size_t> mine;  // this shard's problems
  for (std::size_t i = 0; i < problems.size(); ++i) {
    if (a.shard.has(i)) mine.push_back(i);
  }
  const bool bar = !a.quiet && isatty(fileno(stderr));
  CloudCache cache(a.data_root, options.target_voxel);
  for (std::size_t k = 0; k < mine.size(); ++k) {
    const ppcr_bench::Problem& p = problems[mine[k]];
    ProblemInput input;
    s = prepare_problem(p, options, &cache, &input);
    if (s.ok()) s = run_methods(p, mine[k], k, a, input, csv, &runs);
    if (!s.ok()) {
      if (csv != nullptr) std::fclose(csv);
      return fail("problem " + p.id + ": " + s.message());
    }
    if (bar) progress(k + 1, mine.size(), runs.front().done.outcomes.back().error);
  }
  if (csv != nullptr && std::fclose(csv) != 0) return fail(a.out_csv + ": write failed");
  print_results(a, runs);
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  ppcr_tools::use_passive_openmp_threads(argv);  // idle OpenMP threads sleep
  Arguments a;
  ppcr::RegistrationOptions options;
  CLI::App app{
      "Runs the point clouds registration benchmark protocol on a problem file and "
      "prints the error quantiles, success rate, iterations and time.",
      "ppcr_bench"};
  const int parsed = parse(app, argc, argv, &a, &options);
  if (parsed >= 0) return parsed;
  return a.merge.empty() ? run(app, a, options) : merge(a);
}
