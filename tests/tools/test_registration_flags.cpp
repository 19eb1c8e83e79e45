// The registration flags of ppcr_cli and ppcr_bench (tools/common/registration_flags.hpp):
// parsed values reach RegistrationOptions, defaults are the library's, and a bad value is
// refused with a message naming the flag and the value seen.
#include <algorithm>
#include <catch2/catch.hpp>
#include <fstream>
#include <functional>
#include <iterator>
#include <regex>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "common/registration_flags.hpp"
#include "common/usage_error.hpp"

namespace {

struct Parsed {
  ppcr::Status status;
  ppcr::RegistrationOptions options;
};

Parsed parse(const std::string& command_line) {
  CLI::App app;
  ppcr_tools::RegistrationFlags flags;
  ppcr_tools::add_registration_flags(app, &flags);
  app.parse(command_line, false);
  Parsed p;
  p.status = ppcr_tools::to_options(flags, &p.options);
  return p;
}

// Every field of the options, by the name the flag table uses, as text (doubles in hex: exact).
std::string text(double v) {
  std::ostringstream out;
  out << std::hexfloat << v;
  return out.str();
}
template <class T>
std::string text(T v) {
  return std::to_string(static_cast<long long>(v));
}
using Getter = std::function<std::string(const ppcr::RegistrationOptions&)>;
#define PPCR_FIELD(name)                                                   \
  {                                                                        \
#name, [](const ppcr::RegistrationOptions& o) { return text(o.name); } \
  }
const std::vector<std::pair<std::string, Getter>>& option_fields() {
  static const std::vector<std::pair<std::string, Getter>> kFields = {
      PPCR_FIELD(radius),
      PPCR_FIELD(max_neighbours),
      PPCR_FIELD(error_model),
      PPCR_FIELD(dof),
      PPCR_FIELD(source_voxel),
      PPCR_FIELD(target_voxel),
      PPCR_FIELD(criteria),
      PPCR_FIELD(max_iterations),
      PPCR_FIELD(num_threads),
      PPCR_FIELD(record_history),
      {"on_iteration",
       [](const ppcr::RegistrationOptions& o) { return std::string(o.on_iteration ? "1" : "0"); }},
      PPCR_FIELD(expert.weight_model),
      PPCR_FIELD(expert.scale_mode),
      PPCR_FIELD(expert.scale),
      PPCR_FIELD(expert.em_coarse_drop),
      PPCR_FIELD(expert.em_coarse_patience),
      PPCR_FIELD(expert.em_min_shrink),
      PPCR_FIELD(expert.em_min_scale),
      PPCR_FIELD(expert.normal_neighbours),
      PPCR_FIELD(expert.plane_epsilon),
      PPCR_FIELD(expert.source_normals),
      PPCR_FIELD(expert.reject_boundary),
      PPCR_FIELD(expert.noise_floor),
      PPCR_FIELD(expert.fixed_iterations),
      PPCR_FIELD(expert.cost_drop_threshold),
      PPCR_FIELD(expert.cost_drop_patience),
      PPCR_FIELD(expert.cost_drop_max_motion),
      PPCR_FIELD(expert.acceleration_memory),
      PPCR_FIELD(expert.mse_ratio_threshold),
      PPCR_FIELD(expert.mse_patience),
      PPCR_FIELD(expert.successful_steps_threshold),
      PPCR_FIELD(expert.successful_steps_patience),
      PPCR_FIELD(expert.lm_max_iterations),
      PPCR_FIELD(expert.lm_function_tolerance),
      PPCR_FIELD(expert.lm_fine_function_tolerance),
      PPCR_FIELD(expert.neighbour_cache),
      PPCR_FIELD(expert.coarse_stride)};
  return kFields;
}
#undef PPCR_FIELD

// The fields the tools leave at the library's defaults (no flag): a library caller's concerns
// (history, callback) and settings without a measured reason to expose them.
const std::set<std::string> kNoFlag = {"record_history", "on_iteration", "expert.em_coarse_drop",
                                       "expert.successful_steps_patience",
                                       "expert.lm_max_iterations"};

// The names of the data members declared in `struct name { ... };` of the header's text.
std::vector<std::string> declared_fields(const std::string& header, const std::string& name) {
  const std::size_t begin = header.find("\nstruct " + name + " {");
  const std::size_t end = header.find("\n};", begin);
  std::vector<std::string> fields;
  if (begin == std::string::npos || end == std::string::npos) return fields;
  std::istringstream body(header.substr(begin, end - begin));
  const std::regex member(
      R"(^  (?!static|//|struct|enum)[A-Za-z0-9_:]+(<.*>)?\s+([a-z_][a-z0-9_]*)\s*(=[^;]*)?;)");
  std::string line;
  std::smatch m;
  while (std::getline(body, line)) {
    if (std::regex_search(line, m, member)) fields.push_back(m[2]);
  }
  return fields;
}

bool contains(const std::string& s, const std::string& part) {
  return s.find(part) != std::string::npos;
}

}  // namespace

TEST_CASE("no flags give the library's default options", "[tools]") {
  const Parsed p = parse("");
  REQUIRE(p.status.ok());
  const ppcr::RegistrationOptions defaults;
  CHECK(p.options.radius == defaults.radius);
  CHECK(p.options.max_neighbours == defaults.max_neighbours);
  CHECK(p.options.error_model == defaults.error_model);
  CHECK(p.options.expert.neighbour_cache == defaults.expert.neighbour_cache);
  CHECK(p.options.expert.acceleration_memory == defaults.expert.acceleration_memory);
  CHECK(p.options.expert.coarse_stride == defaults.expert.coarse_stride);
  CHECK(p.options.expert.lm_function_tolerance == defaults.expert.lm_function_tolerance);
  CHECK(p.options.expert.lm_fine_function_tolerance == defaults.expert.lm_fine_function_tolerance);
  CHECK(p.options.expert.em_min_shrink == defaults.expert.em_min_shrink);
}

TEST_CASE("the LM tolerance flags reach the LM options", "[tools]") {
  const Parsed p = parse("--lm-tolerance 0.001 --lm-fine-tolerance 0.02 --radius 0.5");
  REQUIRE(p.status.ok());
  CHECK(p.options.expert.lm_function_tolerance == 0.001);
  CHECK(p.options.expert.lm_fine_function_tolerance == 0.02);
  CHECK(p.options.radius == 0.5);
  CHECK(ppcr::validate(p.options).ok());
}

TEST_CASE("the LM fine tolerance flag takes auto (the default) or a number", "[tools]") {
  CHECK(parse("").options.expert.lm_fine_function_tolerance == ppcr::ExpertOptions::kAutomatic);
  const Parsed automatic = parse("--lm-fine-tolerance auto");
  REQUIRE(automatic.status.ok());
  CHECK(automatic.options.expert.lm_fine_function_tolerance == ppcr::ExpertOptions::kAutomatic);
  const Parsed off = parse("--lm-fine-tolerance 0 --scale raw");
  REQUIRE(off.status.ok());
  CHECK(off.options.expert.lm_fine_function_tolerance == 0.0);
}

TEST_CASE("the coarse stride flag takes auto (the default) or an integer in [1, 64]", "[tools]") {
  CHECK(parse("").options.expert.coarse_stride == ppcr::ExpertOptions::kAutomatic);
  CHECK(parse("--coarse-stride auto").options.expert.coarse_stride ==
        ppcr::ExpertOptions::kAutomatic);
  for (int stride : {1, 4, 64}) {
    const Parsed p = parse("--coarse-stride " + std::to_string(stride));
    REQUIRE(p.status.ok());
    CHECK(p.options.expert.coarse_stride == stride);
    CHECK(ppcr::validate(p.options).ok());
  }
  CHECK(parse("--coarse-stride 1 --scale raw").status.ok());  // 1 is every point: no EM needed
}

TEST_CASE("bad flag values are refused, naming the flag and the value", "[tools]") {
  struct Bad {
    const char* line;
    const char* flag;
    const char* value;
  };
  const Bad cases[] = {
      {"--lm-tolerance -1", "--lm-tolerance", "-1"},
      {"--lm-tolerance nan", "--lm-tolerance", "nan"},
      {"--lm-fine-tolerance -0.5", "--lm-fine-tolerance", "-0.5"},
      {"--lm-fine-tolerance inf", "--lm-fine-tolerance", "inf"},
      {"--lm-fine-tolerance -1", "--lm-fine-tolerance", "-1"},
      {"--lm-fine-tolerance fast", "--lm-fine-tolerance", "fast"},
      {"--lm-fine-tolerance 0.01 --scale raw", "--lm-fine-tolerance", "raw"},
      {"--scale-shrink 0", "--scale-shrink", "0"},
      {"--neighbour-cache -2", "--neighbour-cache", "-2"},
      {"--acceleration -1", "--acceleration", "-1"},
      {"--acceleration 9", "--acceleration", "9"},
      {"--coarse-stride 0", "--coarse-stride", "0"},
      {"--coarse-stride 65", "--coarse-stride", "65"},
      {"--coarse-stride 2.5", "--coarse-stride", "2.5"},
      {"--coarse-stride -1", "--coarse-stride", "-1"},
      {"--coarse-stride half", "--coarse-stride", "half"},
      {"--coarse-stride 2 --scale raw", "--coarse-stride", "raw"},
      {"--radius -1", "--radius", "-1"},
  };
  for (const Bad& b : cases) {
    const Parsed p = parse(b.line);
    INFO(b.line << " -> " << p.status.to_string());
    CHECK_FALSE(p.status.ok());
    CHECK(contains(p.status.message(), b.flag));
    CHECK(contains(p.status.message(), b.value));
  }
}

// The flag table (registration_flags.hpp) against the app's flags and the options' fields: every
// flag has a row, every row a flag; every field of the public header is set by a flag or left
// at its default on purpose (kNoFlag), so a new option or flag cannot go unmapped.
TEST_CASE("the flag table covers every flag and every option field", "[tools]") {
  CLI::App app;
  ppcr_tools::RegistrationFlags flags;
  ppcr_tools::add_registration_flags(app, &flags);
  std::set<std::string> app_flags, table_flags, table_fields;
  for (const CLI::Option* option : app.get_options()) {
    for (const std::string& name : option->get_lnames()) {
      if (name != "help") app_flags.insert("--" + name);
    }
  }
  for (const ppcr_tools::FlagField& row : ppcr_tools::flag_fields()) {
    table_flags.insert(row.flag);
    table_fields.insert(row.field);
  }
  // --no-source-normals and --no-reject-boundary are the negations of their rows' flags.
  app_flags.erase("--no-source-normals");
  app_flags.erase("--no-reject-boundary");
  CHECK(app_flags == table_flags);

  std::ifstream in(PPCR_OPTIONS_HEADER);
  REQUIRE(in);
  const std::string header((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  std::set<std::string> declared;
  for (const std::string& f : declared_fields(header, "RegistrationOptions")) declared.insert(f);
  for (const std::string& f : declared_fields(header, "ExpertOptions"))
    declared.insert("expert." + f);
  declared.erase("expert");  // the ExpertOptions member itself
  std::set<std::string> listed;
  for (const auto& field : option_fields()) listed.insert(field.first);
  CHECK(declared.size() > 30);
  CHECK(declared == listed);  // this test's list is the header's, field for field
  for (const std::string& field : listed) {
    INFO(field);
    CHECK((table_fields.count(field) + kNoFlag.count(field)) == 1);
  }
  for (const std::string& field : table_fields) CHECK(listed.count(field) == 1);
}

// Each flag, given a value other than the default, changes exactly the fields its rows name
// (and those of the companion flags a combination needs), and no other.
TEST_CASE("each flag changes its table fields and no other", "[tools]") {
  // A command line per flag: the flag with a non-default value, and what it needs besides.
  const std::vector<std::pair<std::string, std::string>> kLines = {
      {"--radius", "--radius 0.5"},
      {"--max-neighbours", "--max-neighbours 9"},
      {"--error-model", "--error-model point"},
      {"--dof", "--dof 3"},
      {"--voxel", "--voxel 0.05"},
      {"--source-voxel", "--source-voxel 0.01"},
      {"--target-voxel", "--target-voxel 0.02"},
      {"--threads", "--threads 2"},
      {"--criterion", "--criterion mse-prev"},
      {"--max-iterations", "--max-iterations 40"},
      {"--cost-drop-threshold", "--cost-drop-threshold 0.02"},
      {"--patience", "--patience 6"},
      {"--mse-ratio", "--mse-ratio 3"},
      {"--mse-patience", "--mse-patience 5"},
      {"--steps-threshold", "--steps-threshold 2"},
      {"--gaussian", "--gaussian"},
      {"--coarse-scale", "--coarse-scale 0.2"},
      {"--scale", "--scale 0.3"},
      {"--min-scale", "--min-scale 0.001"},
      {"--coarse-patience", "--coarse-patience 7"},
      {"--scale-shrink", "--scale-shrink 0.5"},
      {"--plane-epsilon", "--plane-epsilon 0.1"},
      {"--normal-neighbours", "--normal-neighbours 12"},
      {"--source-normals", "--no-source-normals"},
      {"--reject-boundary", "--no-reject-boundary"},
      {"--noise-floor", "--noise-floor 0.5"},
      {"--motion-guard", "--motion-guard 0.05"},
      {"--acceleration", "--acceleration 2"},
      {"--neighbour-cache", "--neighbour-cache 2"},
      {"--coarse-stride", "--coarse-stride 3"},
      {"--lm-tolerance", "--lm-tolerance 1e-4"},
      {"--lm-fine-tolerance", "--lm-fine-tolerance 0.001"}};
  const ppcr::RegistrationOptions defaults;
  std::set<std::string> covered;
  for (const auto& [flag, line] : kLines) {
    INFO(line);
    covered.insert(flag);
    const Parsed p = parse(line);
    REQUIRE(p.status.ok());
    std::set<std::string> expected;
    for (const ppcr_tools::FlagField& row : ppcr_tools::flag_fields()) {
      if (flag == row.flag) expected.insert(row.field);
    }
    std::set<std::string> changed;
    for (const auto& [name, get] : option_fields()) {
      if (get(p.options) != get(defaults)) changed.insert(name);
    }
    CHECK(changed == expected);
  }
  std::set<std::string> table_flags;
  for (const ppcr_tools::FlagField& row : ppcr_tools::flag_fields()) table_flags.insert(row.flag);
  CHECK(covered == table_flags);
}

TEST_CASE("closest_flag: the known flag within three edits, or a prefix", "[tools]") {
  CLI::App app;
  ppcr_tools::RegistrationFlags flags;
  ppcr_tools::add_registration_flags(app, &flags);
  CHECK(ppcr_tools::closest_flag(app, "--raduis") == "--radius");
  CHECK(ppcr_tools::closest_flag(app, "--treads") == "--threads");
  CHECK(ppcr_tools::closest_flag(app, "--sourcevoxel") == "--source-voxel");
  CHECK(ppcr_tools::closest_flag(app, "--voxel-size") == "--voxel");
  CHECK(ppcr_tools::closest_flag(app, "--completely-else") == "");
}

TEST_CASE("a switch and its negation: the last one given wins", "[tools]") {
  CHECK_FALSE(parse("--source-normals --no-source-normals").options.expert.source_normals);
  CHECK(parse("--no-source-normals --source-normals").options.expert.source_normals);
  CHECK_FALSE(parse("--reject-boundary --no-reject-boundary").options.expert.reject_boundary);
  CHECK(parse("--no-reject-boundary --reject-boundary").options.expert.reject_boundary);
}

TEST_CASE("a bad leaf is named by the flag given, and auto is the automatic leaf", "[tools]") {
  Parsed p = parse("--source-voxel -2");
  CHECK(p.status.message().rfind("--source-voxel", 0) == 0);
  p = parse("--target-voxel -0.5");
  CHECK(p.status.message().rfind("--target-voxel", 0) == 0);
  p = parse("--voxel -2");
  CHECK_FALSE(p.status.ok());
  constexpr double kAuto = ppcr::RegistrationOptions::kAutomaticVoxel;
  p = parse("--voxel auto");
  REQUIRE(p.status.ok());
  CHECK(p.options.source_voxel == kAuto);
  CHECK(p.options.target_voxel == kAuto);
  p = parse("--source-voxel AUTO --target-voxel 0.1");
  REQUIRE(p.status.ok());
  CHECK(p.options.source_voxel == kAuto);
  CHECK(p.options.target_voxel == 0.1);
  CHECK_THROWS_AS(parse("--voxel automatic"), CLI::ConversionError);  // not a number or auto
}
