// usage_error.cpp - see usage_error.hpp.
#include "common/usage_error.hpp"

#include <algorithm>
#include <cstddef>
#include <cstdlib>
#include <vector>

namespace ppcr_tools {
namespace {

// Levenshtein distance (insertions, deletions, substitutions), two rows.
std::size_t edit_distance(const std::string& a, const std::string& b) {
  std::vector<std::size_t> row(b.size() + 1), next(b.size() + 1);
  for (std::size_t j = 0; j <= b.size(); ++j) row[j] = j;
  for (std::size_t i = 1; i <= a.size(); ++i) {
    next[0] = i;
    for (std::size_t j = 1; j <= b.size(); ++j) {
      const std::size_t substitute = row[j - 1] + (a[i - 1] == b[j - 1] ? 0 : 1);
      next[j] = std::min({row[j] + 1, next[j - 1] + 1, substitute});
    }
    row.swap(next);
  }
  return row[b.size()];
}

// Whether `text` is a number (a negative value is an argument, not a flag).
bool is_number(const std::string& text) {
  char* end = nullptr;
  std::strtod(text.c_str(), &end);
  return !text.empty() && end == text.c_str() + text.size();
}

}  // namespace

std::string closest_flag(const CLI::App& app, const std::string& flag) {
  std::string best;
  std::size_t best_distance = 4;  // at most 3 edits
  for (const CLI::Option* option : app.get_options()) {
    for (const std::string& name : option->get_lnames()) {
      const std::string known = "--" + name;
      std::size_t d = edit_distance(flag, known);
      // One a prefix of the other ("--voxel-size" for "--voxel") is close whatever the length.
      if (flag.size() > 4 && (known.rfind(flag, 0) == 0 || flag.rfind(known, 0) == 0)) d = 1;
      if (d < best_distance) best_distance = d, best = known;
    }
  }
  return best;
}

std::string usage_error(const CLI::App& app, const CLI::ParseError& error, int argc,
                        const char* const* argv) {
  if (dynamic_cast<const CLI::ExtrasError*>(&error) == nullptr) return error.what();
  std::string message;
  for (int i = 1; i < argc; ++i) {
    std::string arg = argv[i];
    if (arg.size() < 2 || arg[0] != '-' || is_number(arg)) continue;
    arg = arg.substr(0, arg.find('='));
    if (arg.rfind("--", 0) != 0) continue;
    bool known = false;
    for (const CLI::Option* option : app.get_options()) {
      for (const std::string& name : option->get_lnames()) known = known || arg == "--" + name;
    }
    if (known) continue;
    if (!message.empty()) message += "; ";
    message += arg + ": unknown flag";
    const std::string hint = closest_flag(app, arg);
    if (!hint.empty()) message += "; did you mean " + hint + "?";
  }
  return message.empty() ? std::string(error.what()) : message;
}

}  // namespace ppcr_tools
