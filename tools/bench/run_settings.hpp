// run_settings.hpp - what makes two ppcr_bench runs the same run: the flags that change results
// (method, label, limit, registration flags, success bounds, ...), the problem list and the
// version. Every shard writes it into its CSV; a merge refuses shards whose settings differ.
#pragma once

#include <CLI/CLI.hpp>
#include <string>
#include <vector>

#include "bench/problems.hpp"

namespace ppcr_bench {

/// The option's name as typed: `--radius`, or `PROBLEMS` for the positional.
std::string flag_name(const CLI::Option& option);

/// Flags that only say where to read and write or how to show progress: shards on different
/// hosts may set them differently.
bool is_local_flag(const std::string& name);

/// `--flag=value ...` for every flag set on the parsed `app` but the local ones (sorted by name;
/// numbers in their shortest exact form, so 0.020 and 0.02 agree), then `problems=<digest of the
/// problem list>` and `version=<ppcr version>`.
std::string run_settings(const CLI::App& app, const std::vector<Problem>& problems);

}  // namespace ppcr_bench
