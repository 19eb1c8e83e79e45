// usage_error.hpp - a command-line mistake told the way a user can act on: an unknown flag is
// named, with the known flag closest to it ("--raduis: unknown flag; did you mean --radius?").
#pragma once

#include <CLI/CLI.hpp>
#include <string>

namespace ppcr_tools {

/// The message for a parse error of `app` on argv: for arguments CLI11 did not expect, each
/// unknown flag with its closest known flag (edit distance at most 3, or one of the two a prefix
/// of the other); otherwise CLI11's own message.
std::string usage_error(const CLI::App& app, const CLI::ParseError& error, int argc,
                        const char* const* argv);

/// The closest of app's long flags to `flag` (both with their leading dashes), or "" when none
/// is close (used by usage_error; exposed for its test).
std::string closest_flag(const CLI::App& app, const std::string& flag);

}  // namespace ppcr_tools
