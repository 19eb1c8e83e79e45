// registration_flags.cpp - CLI flags -> RegistrationOptions.
#include "common/registration_flags.hpp"

#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <map>
#include <memory>
#include <sstream>
#include <utility>

namespace ppcr_tools {
namespace {

ppcr::Status bad(const std::string& flag, const std::string& value, const std::string& why) {
  return ppcr::Status(ppcr::StatusCode::kInvalidArgument, flag + " '" + value + "': " + why);
}

std::string str(double v) {
  std::ostringstream s;
  s << v;
  return s.str();
}

// text as a finite number (the whole of it, in range), else false.
bool parse_finite(const std::string& text, double* v) {
  errno = 0;
  char* end = nullptr;
  *v = std::strtod(text.c_str(), &end);
  return !text.empty() && *end == '\0' && errno == 0 && std::isfinite(*v);
}

template <class T>
CLI::Option* value(CLI::App& app, const char* flag, T* target, const std::string& help,
                   const char* group) {
  return app.add_option(flag, *target, help)->check(non_empty())->group(group);
}

// A switch: FLAG turns it on, --no-... off; the last one given wins.
void on_off(CLI::App& app, const std::string& flag, bool* target, const std::string& help) {
  const std::string negation = "--no-" + flag.substr(2);
  app.add_flag(
         flag + ",!" + negation, *target,
         help + std::string(" (default ") + (*target ? "on" : "off") + "; " + negation + ": off)")
      ->group(kExpertGroup);
}

// --help without CLI11's value of a negated flag ("--x,--no-x{false}"): the text says it; and
// without its count of an option's values where the value names already say it
// ("FX FY CX CY x 4").
class HelpFormatter : public CLI::Formatter {
 public:
  std::string make_option_opts(const CLI::Option* option) const override {
    std::string opts = CLI::Formatter::make_option_opts(option);
    const std::string count = " x " + std::to_string(option->get_expected_min());
    if (option->get_type_name().find(' ') != std::string::npos) {
      const std::size_t at = opts.find(count);
      if (at != std::string::npos) opts.erase(at, count.size());
    }
    return opts;
  }

  std::string make_option_name(const CLI::Option* option, bool positional) const override {
    std::string name = CLI::Formatter::make_option_name(option, positional);
    for (std::size_t open = name.find('{'); open != std::string::npos; open = name.find('{')) {
      const std::size_t close = name.find('}', open);
      if (close == std::string::npos) break;
      name.erase(open, close - open + 1);
    }
    return name;
  }
};

void add_user_flags(CLI::App& app, RegistrationFlags* f) {
  ppcr::RegistrationOptions& o = f->options;
  value(app, "--radius", &o.radius,
        "association radius, cloud units; it must cover the misalignment (default: automatic, " +
            str(ppcr::RegistrationOptions::kAutomaticRadiusSpacings) +
            " x the filtered target's median point spacing; 0 asks for it too)",
        kRegistrationGroup);
  value(app, "--max-neighbours", &o.max_neighbours,
        "target points associated with each source point (default " +
            std::to_string(o.max_neighbours) + ")",
        kRegistrationGroup);
  value(app, "--error-model", &f->error_model,
        "plane (the error along the target's surface normal; default) or point (the paper's)",
        kRegistrationGroup);
  value(app, "--dof", &o.dof,
        "Student-t degrees of freedom, any finite value > 0 (default " + str(o.dof) +
            "); as it grows the weights tend to --gaussian's, reached to 1e-9 from about 1e12",
        kRegistrationGroup);
  // "auto": RegistrationOptions::kAutomaticVoxel, the leaf that leaves about
  // kAutomaticVoxelPoints points.
  const CLI::Transformer automatic_leaf(
      std::map<std::string, std::string>{{"auto", str(ppcr::RegistrationOptions::kAutomaticVoxel)}},
      CLI::ignore_case);
  const std::string automatic = "; auto: the leaf leaving about " +
                                std::to_string(ppcr::RegistrationOptions::kAutomaticVoxelPoints) +
                                " points";
  CLI::Option* voxel =
      app.add_option_function<double>(
             "--voxel",
             [o = &f->options](double leaf) { o->source_voxel = o->target_voxel = leaf; },
             "voxel-grid leaf for both clouds, cloud units (sets --source-voxel and "
             "--target-voxel" +
                 automatic + ")")
          ->check(non_empty())
          ->transform(CLI::Transformer(automatic_leaf).description(""))
          ->group(kRegistrationGroup);
  value(app, "--source-voxel", &o.source_voxel,
        "voxel-grid leaf for the source, cloud units (default 0 = off" + automatic + ")",
        kRegistrationGroup)
      ->transform(CLI::Transformer(automatic_leaf).description(""));
  value(app, "--target-voxel", &o.target_voxel,
        "voxel-grid leaf for the target, cloud units (default 0 = off" + automatic + ")",
        kRegistrationGroup)
      ->transform(CLI::Transformer(automatic_leaf).description(""));
  voxel->excludes("--source-voxel")->excludes("--target-voxel");
  value(app, "--threads", &o.num_threads, "threads (default 1; results do not depend on it)",
        kRegistrationGroup);
}

void add_termination_flags(CLI::App& app, RegistrationFlags* f) {
  ppcr::RegistrationOptions& o = f->options;
  ppcr::ExpertOptions& e = o.expert;
  value(app, "--criterion", &f->criterion,
        "cost-drop (default), mse-prev, successful-steps, fixed, or a comma-separated "
        "combination (stops when any fires)",
        kTerminationGroup);
  value(app, "--max-iterations", &o.max_iterations,
        "cap on outer iterations; with --criterion fixed, the iterations run (default " +
            std::to_string(o.max_iterations) + ")",
        kTerminationGroup);
  value(app, "--cost-drop-threshold", &e.cost_drop_threshold,
        "cost-drop: relative drop counted as low (default " + str(e.cost_drop_threshold) + ")",
        kTerminationGroup);
  value(app, "--patience", &e.cost_drop_patience,
        "cost-drop: consecutive low iterations tolerated (default " +
            std::to_string(e.cost_drop_patience) + ")",
        kTerminationGroup);
  value(app, "--mse-ratio", &e.mse_ratio_threshold,
        "mse-prev: low when MSE_t < MSE_{t-1} / this (default " + str(e.mse_ratio_threshold) + ")",
        kTerminationGroup);
  value(app, "--mse-patience", &e.mse_patience,
        "mse-prev: consecutive low iterations tolerated (default " +
            std::to_string(e.mse_patience) + ")",
        kTerminationGroup);
  value(app, "--steps-threshold", &e.successful_steps_threshold,
        "successful-steps: low when LM accepted at most this many steps (default " +
            std::to_string(e.successful_steps_threshold) + ")",
        kTerminationGroup);
}

void add_expert_flags(CLI::App& app, RegistrationFlags* f) {
  ppcr::ExpertOptions& e = f->options.expert;
  app.add_flag("--gaussian", f->gaussian, "Gaussian weights (paper eq. 2) instead of Student-t")
      ->group(kExpertGroup);
  value(app, "--scale", &f->scale,
        "E-step scale: em (coarse-to-fine, default), raw (the paper's unit variance), or a "
        "fixed value in cloud units",
        kExpertGroup);
  value(app, "--coarse-scale", &e.scale, "em: the coarse scale, cloud units (0 = radius / 2)",
        kExpertGroup);
  value(app, "--min-scale", &e.em_min_scale, "em: floor on the scale, cloud units (0 = none)",
        kExpertGroup);
  value(app, "--coarse-patience", &e.em_coarse_patience,
        "em: settled iterations ending the coarse phase (default " +
            std::to_string(e.em_coarse_patience) + ")",
        kExpertGroup);
  value(
      app, "--scale-shrink", &e.em_min_shrink,
      "em: s^2 shrinks by at most this factor per iteration (default " + str(e.em_min_shrink) + ")",
      kExpertGroup);
  value(
      app, "--plane-epsilon", &e.plane_epsilon,
      "plane: in-plane weight of Omega = n n^T + epsilon I (default " + str(e.plane_epsilon) + ")",
      kExpertGroup);
  value(app, "--normal-neighbours", &e.normal_neighbours,
        "plane: points per normal fit (default " + std::to_string(e.normal_neighbours) + ")",
        kExpertGroup);
  on_off(app, "--source-normals", &e.source_normals,
         "plane: pairs use the mean of both clouds' normals");
  on_off(app, "--reject-boundary", &e.reject_boundary,
         "plane + em: after the coarse phase, leave out source points whose nearest target point "
         "lies on the target's boundary");
  value(app, "--noise-floor", &e.noise_floor,
        "plane + em: floor the scale at this multiple of the target's surface noise (default " +
            str(e.noise_floor) + "; 0 = off)",
        kExpertGroup);
  value(app, "--motion-guard", &e.cost_drop_max_motion,
        "cost-drop: a low iteration must move the source by less than this fraction of the "
        "radius, RMS (default " +
            str(e.cost_drop_max_motion) + "; 0 = the paper's rule)",
        kExpertGroup);
  value(app, "--acceleration", &e.acceleration_memory,
        "em coarse phase: Anderson acceleration of the pose with this memory m, from the last "
        "m + 1 iterations (default " +
            std::to_string(e.acceleration_memory) + "; 0 = the paper's plain loop)",
        kExpertGroup);
  value(app, "--neighbour-cache", &e.neighbour_cache,
        "extra candidates cached per source point (default " + std::to_string(e.neighbour_cache) +
            "; 0 = none; same result either way)",
        kExpertGroup);
  value(app, "--coarse-stride", &f->coarse_stride,
        "em: register every n-th source point while the scale settles (the coarse phase and "
        "its halving): auto (2 with the plane model, 1 with the point model) or an integer in "
        "[1, 64]",
        kExpertGroup);
  value(app, "--lm-tolerance", &e.lm_function_tolerance,
        "inner LM: stop after a step lowering the cost by less than this fraction (default " +
            str(e.lm_function_tolerance) + ")",
        kExpertGroup);
  value(app, "--lm-fine-tolerance", &f->lm_fine_tolerance,
        "em: --lm-tolerance of the fine phase: auto (1e-2, at most --cost-drop-threshold, with "
        "the plane model and cost-drop alone) or a number (0 = --lm-tolerance throughout)",
        kExpertGroup);
}

// The word flags into *o.
ppcr::Status read_words(const RegistrationFlags& f, ppcr::RegistrationOptions* o) {
  ppcr::ExpertOptions& e = o->expert;
  e.weight_model = f.gaussian ? ppcr::WeightModel::kGaussian : ppcr::WeightModel::kStudentT;
  if (f.scale == "em") {
    e.scale_mode = ppcr::ScaleMode::kEM;
  } else if (f.scale == "raw") {
    e.scale_mode = ppcr::ScaleMode::kRaw;
  } else {
    double s = 0.0;
    if (!(parse_finite(f.scale, &s) && s > 0.0)) {
      return bad("--scale", f.scale, "expected em, raw or a positive number");
    }
    e.scale_mode = ppcr::ScaleMode::kFixed;
    e.scale = s;
  }
  o->criteria = 0;
  std::stringstream list(f.criterion);
  std::string name;
  static const std::pair<const char*, ppcr::Criterion> kCriteria[] = {
      {"cost-drop", ppcr::kCriterionCostDrop},
      {"mse-prev", ppcr::kCriterionMsePrev},
      {"successful-steps", ppcr::kCriterionSuccessfulSteps},
      {"fixed", ppcr::kCriterionFixed}};
  while (std::getline(list, name, ',')) {
    bool known = false;
    for (const auto& [word, bit] : kCriteria) {
      if (name == word) o->criteria |= bit, known = true;
    }
    if (!known) {
      return bad("--criterion", f.criterion,
                 "unknown criterion '" + name +
                     "' (expected cost-drop, mse-prev, successful-steps or fixed)");
    }
  }
  e.fixed_iterations = o->max_iterations;
  if (f.error_model == "point") {
    o->error_model = ppcr::ErrorModel::kPoint;
  } else if (f.error_model != "plane") {
    return bad("--error-model", f.error_model, "expected point or plane");
  }
  if (f.coarse_stride != "auto") {
    double v = 0.0;
    if (!(parse_finite(f.coarse_stride, &v) && v >= 1.0 && v <= 64.0 && v == std::floor(v))) {
      return bad("--coarse-stride", f.coarse_stride, "expected auto or an integer in [1, 64]");
    }
    e.coarse_stride = static_cast<int>(v);
  }
  if (f.lm_fine_tolerance != "auto") {
    double v = 0.0;
    if (!(parse_finite(f.lm_fine_tolerance, &v) && v >= 0.0)) {
      return bad("--lm-fine-tolerance", f.lm_fine_tolerance, "expected auto or a number >= 0");
    }
    e.lm_fine_function_tolerance = v;
  }
  return ppcr::Status::Ok();
}

// Settings that only act with another one: refused rather than ignored.
ppcr::Status check_combinations(const RegistrationFlags& f, const ppcr::RegistrationOptions& o) {
  const ppcr::ExpertOptions& e = o.expert;
  const bool em = e.scale_mode == ppcr::ScaleMode::kEM;
  // (--source-normals, --noise-floor and --acceleration, on by default, are unused by the point
  // model and the noise floor and the acceleration by the raw and fixed scales, as the library
  // documents.)
  const std::pair<bool, std::pair<const char*, std::string>> needs_em[] = {
      {e.em_min_scale > 0.0, {"--min-scale", str(e.em_min_scale)}},
      {e.coarse_stride > 1, {"--coarse-stride", f.coarse_stride}},
      {e.lm_fine_function_tolerance > 0.0, {"--lm-fine-tolerance", f.lm_fine_tolerance}}};
  for (const auto& [set, flag] : needs_em) {
    if (set && !em) return bad(flag.first, flag.second, "needs --scale em, got --scale " + f.scale);
  }
  return ppcr::Status::Ok();
}

}  // namespace

const std::vector<FlagField>& flag_fields() {
  // --coarse-scale before --scale: a message about expert.scale names --coarse-scale, unless it is
  // about the fixed scale (with_flag_names).
  static const std::vector<FlagField> kTable = {
      {"--radius", "radius"},
      {"--max-neighbours", "max_neighbours"},
      {"--error-model", "error_model"},
      {"--dof", "dof"},
      {"--source-voxel", "source_voxel"},
      {"--target-voxel", "target_voxel"},
      {"--voxel", "source_voxel"},  // after: a message about source_voxel names --source-voxel
      {"--voxel", "target_voxel"},
      {"--threads", "num_threads"},
      {"--criterion", "criteria"},
      {"--max-iterations", "max_iterations"},
      {"--max-iterations", "expert.fixed_iterations"},
      {"--cost-drop-threshold", "expert.cost_drop_threshold"},
      {"--patience", "expert.cost_drop_patience"},
      {"--mse-ratio", "expert.mse_ratio_threshold"},
      {"--mse-patience", "expert.mse_patience"},
      {"--steps-threshold", "expert.successful_steps_threshold"},
      {"--gaussian", "expert.weight_model"},
      {"--coarse-scale", "expert.scale"},
      {"--scale", "expert.scale_mode"},
      {"--scale", "expert.scale"},
      {"--min-scale", "expert.em_min_scale"},
      {"--coarse-patience", "expert.em_coarse_patience"},
      {"--scale-shrink", "expert.em_min_shrink"},
      {"--plane-epsilon", "expert.plane_epsilon"},
      {"--normal-neighbours", "expert.normal_neighbours"},
      {"--source-normals", "expert.source_normals"},
      {"--reject-boundary", "expert.reject_boundary"},
      {"--noise-floor", "expert.noise_floor"},
      {"--motion-guard", "expert.cost_drop_max_motion"},
      {"--acceleration", "expert.acceleration_memory"},
      {"--neighbour-cache", "expert.neighbour_cache"},
      {"--coarse-stride", "expert.coarse_stride"},
      {"--lm-tolerance", "expert.lm_function_tolerance"},
      {"--lm-fine-tolerance", "expert.lm_fine_function_tolerance"}};
  return kTable;
}

ppcr::Status with_flag_names(const ppcr::Status& s) {
  const std::string& message = s.message();
  // Returns s with `prefix` (a field's name and a space) replaced by flag, if it starts with it.
  auto renamed = [&](const std::string& prefix, const char* flag) {
    const std::string rest = message.substr(prefix.size());
    const bool rule = rest.rfind("must be ", 0) == 0;
    return ppcr::Status(s.code(), std::string(flag) + (rule ? ": " : " ") + rest);
  };
  const std::string fixed_scale = "expert.scale (fixed scale) ";
  if (message.rfind(fixed_scale, 0) == 0) return renamed(fixed_scale, "--scale");
  for (const FlagField& row : flag_fields()) {
    const std::string prefix = std::string(row.field) + " ";
    if (message.rfind(prefix, 0) == 0) return renamed(prefix, row.flag);
  }
  return s;
}

const CLI::Validator& finite_positive() {
  static const CLI::Validator validator(
      [](std::string& value) -> std::string {
        double v = 0.0;
        return parse_finite(value, &v) && v > 0.0 ? std::string()
                                                  : "must be finite and > 0, got " + value;
      },
      "", "finite-positive");
  return validator;
}

const CLI::Validator& non_empty() {
  static const CLI::Validator validator(
      [](std::string& value) -> std::string {
        return value.empty() ? std::string("an empty value is not a value") : std::string();
      },
      "", "non-empty");
  return validator;
}

void add_registration_flags(CLI::App& app, RegistrationFlags* f) {
  app.formatter(std::make_shared<HelpFormatter>());
  add_user_flags(app, f);
  add_termination_flags(app, f);
  add_expert_flags(app, f);
}

ppcr::Status to_options(const RegistrationFlags& f, ppcr::RegistrationOptions* o) {
  *o = f.options;
  ppcr::Status s = read_words(f, o);
  if (s.ok()) s = check_combinations(f, *o);
  if (s.ok()) s = with_flag_names(ppcr::validate(*o));
  return s;
}

}  // namespace ppcr_tools
