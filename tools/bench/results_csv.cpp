// results_csv.cpp - the per-problem CSV's writer and the reader of what a merge needs.
#include "bench/results_csv.hpp"

#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <iterator>

namespace ppcr_bench {
namespace {

// The columns, in order. New columns go at the end: scripts read the file by column name.
constexpr const char* kColumns[] = {"id",
                                    "method",
                                    "error",
                                    "rotation_error_deg",
                                    "translation_error",
                                    "iterations",
                                    "stop_reason",
                                    "converged",
                                    "ok",
                                    "time_ms",
                                    "source_points",
                                    "target_points",
                                    "success",
                                    "fitness",
                                    "inlier_rmse",
                                    "overlap",
                                    "close_fraction",
                                    "scale",
                                    "target_surface_noise",
                                    "target_spacing",
                                    "degenerate_directions",
                                    "quality",
                                    "quality_ms",
                                    "radius",
                                    "problem_index",
                                    "problem_count",
                                    "success_rotation",
                                    "success_translation",
                                    "settings",
                                    "nees",
                                    "error_twist",
                                    "covariance"};
constexpr std::size_t kColumnCount = std::size(kColumns);

std::size_t column(const std::string& name) {
  for (std::size_t k = 0; k < kColumnCount; ++k) {
    if (name == kColumns[k]) return k;
  }
  std::abort();  // a name not in kColumns: a programming error in this file
}

std::string number(const char* format, double value) {
  char text[64];
  std::snprintf(text, sizeof text, format, value);
  return text;
}

// n numbers in one field, separated by spaces (round_trip each).
std::string numbers(const double* values, int n) {
  std::string text;
  for (int i = 0; i < n; ++i) text += (i == 0 ? "" : " ") + round_trip(values[i]);
  return text;
}

std::string whole(std::size_t value) { return std::to_string(value); }

ppcr::Status bad_field(const char* name, const std::string& value, const char* expected) {
  return ppcr::Status(ppcr::StatusCode::kParseError, std::string("column ") + name + ": expected " +
                                                         expected + ", got '" + value + "'");
}

// Reads column `name` of `fields` as a number (nan and inf allowed: a failed run's errors).
ppcr::Status read_double(const std::vector<std::string>& fields, const char* name, double* value) {
  const std::string& text = fields[column(name)];
  char* end = nullptr;
  errno = 0;
  *value = std::strtod(text.c_str(), &end);
  if (text.empty() || *end != '\0' || errno == ERANGE) return bad_field(name, text, "a number");
  return ppcr::Status::Ok();
}

ppcr::Status read_whole(const std::vector<std::string>& fields, const char* name,
                        std::size_t* value) {
  const std::string& text = fields[column(name)];
  if (text.empty() || text.size() > 18 ||
      text.find_first_not_of("0123456789") != std::string::npos) {
    return bad_field(name, text, "a whole number");
  }
  *value = static_cast<std::size_t>(std::strtoull(text.c_str(), nullptr, 10));
  return ppcr::Status::Ok();
}

}  // namespace

std::string round_trip(double value) {
  char text[64];
  for (int digits = 15; digits <= 17; ++digits) {
    std::snprintf(text, sizeof text, "%.*g", digits, value);
    if (std::strtod(text, nullptr) == value) break;  // NaN never compares equal: 17 digits
  }
  return text;
}

const std::string& csv_header() {
  static const std::string header = [] {
    std::string h;
    for (const char* name : kColumns) h += (h.empty() ? "" : ",") + std::string(name);
    return h;
  }();
  return header;
}

std::string csv_field(const std::string& text) {
  if (text.find_first_of(",\"\n\r") == std::string::npos) return text;
  std::string quoted = "\"";
  for (char c : text) quoted += c == '"' ? std::string("\"\"") : std::string(1, c);
  return quoted + "\"";
}

bool split_csv_line(const std::string& line, std::vector<std::string>* fields) {
  fields->assign(1, std::string());
  bool quoted = false;
  for (std::size_t k = 0; k < line.size(); ++k) {
    const char c = line[k];
    if (quoted && c == '"' && k + 1 < line.size() && line[k + 1] == '"') {
      fields->back() += '"';
      ++k;
    } else if (c == '"') {
      quoted = !quoted;
    } else if (c == ',' && !quoted) {
      fields->emplace_back();
    } else {
      fields->back() += c;
    }
  }
  return !quoted;
}

std::string format_row(const RunInfo& run, const ProblemRow& row) {
  const ProblemOutcome& o = row.outcome;
  const MethodResult& r = row.result;
  const bool success = o.rotation_error_deg < run.success_rotation_deg &&
                       o.translation_error < run.success_translation;  // summarize()'s rule
  const std::string fields[] = {csv_field(row.id),
                                csv_field(run.label),
                                round_trip(o.error),
                                round_trip(o.rotation_error_deg),
                                round_trip(o.translation_error),
                                std::to_string(o.iterations),
                                csv_field(r.stop_reason),
                                r.converged ? "1" : "0",
                                r.ok ? "1" : "0",
                                number("%.3f", o.time_ms),
                                whole(row.source_points),
                                whole(row.target_points),
                                success ? "1" : "0",
                                number("%.6g", r.fitness),
                                number("%.6g", r.inlier_rmse),
                                number("%.6g", r.overlap),
                                number("%.6g", r.close_fraction),
                                number("%.6g", r.scale),
                                number("%.6g", r.target_surface_noise),
                                number("%.6g", r.target_spacing),
                                std::to_string(r.degenerate_directions),
                                csv_field(r.quality),
                                number("%.3f", r.quality_ms),
                                number("%.9g", r.radius),
                                whole(row.index),
                                whole(run.problem_count),
                                round_trip(run.success_rotation_deg),
                                round_trip(run.success_translation),
                                csv_field(run.settings),
                                number("%.6g", o.nees),
                                numbers(o.error_twist.data(), 6),
                                numbers(r.covariance.data(), 36)};
  static_assert(std::size(fields) == kColumnCount, "one field per column");
  std::string line;
  for (const std::string& f : fields) line += (line.empty() ? "" : ",") + f;
  return line + "\n";
}

ppcr::Status parse_row(const std::string& line, ReadRow* row) {
  std::vector<std::string> f;
  if (!split_csv_line(line, &f)) {
    return ppcr::Status(ppcr::StatusCode::kParseError, "a quoted field is not closed");
  }
  if (f.size() != kColumnCount) {
    return ppcr::Status(
        ppcr::StatusCode::kParseError,
        "expected " + std::to_string(kColumnCount) + " fields, got " + std::to_string(f.size()));
  }
  ReadRow r;
  r.id = f[column("id")];
  r.run.label = f[column("method")];
  r.run.settings = f[column("settings")];
  const std::string& ok = f[column("ok")];
  if (ok != "0" && ok != "1") return bad_field("ok", ok, "0 or 1");
  r.ok = ok == "1";
  double iterations = 0.0;
  ppcr::Status s = read_double(f, "error", &r.outcome.error);
  if (s.ok()) s = read_double(f, "rotation_error_deg", &r.outcome.rotation_error_deg);
  if (s.ok()) s = read_double(f, "translation_error", &r.outcome.translation_error);
  if (s.ok()) s = read_double(f, "iterations", &iterations);
  if (s.ok()) s = read_double(f, "time_ms", &r.outcome.time_ms);
  if (s.ok()) s = read_whole(f, "problem_index", &r.index);
  if (s.ok()) s = read_whole(f, "problem_count", &r.run.problem_count);
  if (s.ok()) s = read_double(f, "success_rotation", &r.run.success_rotation_deg);
  if (s.ok()) s = read_double(f, "success_translation", &r.run.success_translation);
  if (!s.ok()) return s;
  if (iterations != std::floor(iterations) || std::fabs(iterations) > 1e9) {
    return bad_field("iterations", f[column("iterations")], "a whole number");
  }
  r.outcome.iterations = static_cast<int>(iterations);
  if (r.index >= r.run.problem_count) {
    return bad_field("problem_index", f[column("problem_index")],
                     ("a number below problem_count " + f[column("problem_count")]).c_str());
  }
  *row = std::move(r);
  return ppcr::Status::Ok();
}

}  // namespace ppcr_bench
