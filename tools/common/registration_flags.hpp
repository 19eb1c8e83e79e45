// registration_flags.hpp - the registration options of ppcr_cli and ppcr_bench (a contract:
// scripts depend on these names), bound to a CLI11 app and turned into RegistrationOptions.
#pragma once

#include <CLI/CLI.hpp>
#include <string>
#include <vector>

#include "ppcr/options.hpp"
#include "ppcr/status.hpp"

namespace ppcr_tools {

/// Flag values as typed by the user: numbers bound to the options directly, words kept as text
/// until to_options() reads them.
struct RegistrationFlags {
  ppcr::RegistrationOptions options;
  bool gaussian = false;
  std::string scale = "em";                // em | raw | <s>
  std::string criterion = "cost-drop";     // comma-separated list
  std::string error_model = "plane";       // plane | point
  std::string coarse_stride = "auto";      // auto | integer
  std::string lm_fine_tolerance = "auto";  // auto | number
};

/// The help groups, in the order --help shows them.
constexpr const char* kRegistrationGroup = "Registration";
constexpr const char* kTerminationGroup = "Termination";
constexpr const char* kExpertGroup =
    "Expert (research and speed; the defaults are the measured best)";

/// Refuses an empty value (CLI11 would read '' as 0 or as "not set").
const CLI::Validator& non_empty();

/// Refuses a value that is not a finite number > 0 (CLI11's PositiveNumber lets NaN through).
const CLI::Validator& finite_positive();

/// Adds the user flags (--radius, --max-neighbours, --error-model, --dof, --source-voxel,
/// --target-voxel, --threads), the termination flags (--criterion, --max-iterations,
/// --cost-drop-threshold, --patience, --mse-ratio, --mse-patience, --steps-threshold) and the
/// expert flags (--gaussian, --scale, --coarse-scale, --min-scale, --plane-epsilon,
/// --normal-neighbours, --source-normals, --noise-floor, --motion-guard, --coarse-patience,
/// --scale-shrink, --neighbour-cache, --coarse-stride, --lm-tolerance, --lm-fine-tolerance).
/// Every value flag refuses an empty value. Installs the app's help formatter (no "{false}"
/// after a negated flag).
void add_registration_flags(CLI::App& app, RegistrationFlags* flags);

/// One row per flag and options field it sets: the field's name in RegistrationOptions, "expert."
/// before ExpertOptions's (a flag can set two fields, a field be set by two flags). The one map
/// between flags and fields: with_flag_names() reads it, and
/// tests/tools/test_registration_flags.cpp checks it against every flag of the app and every field
/// of the options (each row's flag, given a value, changes its fields and no other).
struct FlagField {
  const char* flag;
  const char* field;
};
const std::vector<FlagField>& flag_fields();

/// A library message that starts with an option's field name ("source_voxel ...", "radius must
/// be ...") with the flag's name instead.
ppcr::Status with_flag_names(const ppcr::Status& status);

/// Reads the word flags and validates everything into *options. The message names the flag and
/// the value seen.
ppcr::Status to_options(const RegistrationFlags& flags, ppcr::RegistrationOptions* options);

}  // namespace ppcr_tools
