// pair_log.cpp - CSV rows of the per-pair quality.
#include "odometry/pair_log.hpp"

#include <cstdio>

namespace ppcr_odometry {
namespace {

// A CSV field: quoted, with quotes doubled, when it holds a comma, a quote or a line break.
std::string field(const std::string& text) {
  if (text.find_first_of(",\"\n\r") == std::string::npos) return text;
  std::string quoted = "\"";
  for (const char c : text) {
    quoted += c;
    if (c == '"') quoted += '"';
  }
  return quoted + '"';
}

std::string number(double value, const char* format) {
  char text[64];
  std::snprintf(text, sizeof(text), format, value);
  return text;
}

}  // namespace

ppcr::Status PairLog::open(const std::string& path) {
  ppcr::Status s = file_.open(path);
  if (s.ok()) {
    s = file_.write_line(
        "scan,file,method,fitness,quality,quality_reason,inlier_rmse,iterations,stop_reason,"
        "time_ms");
  }
  return s;
}

ppcr::Status PairLog::append(std::size_t scan, const std::string& file, const std::string& method,
                             const PairOutcome& outcome, double time_ms) {
  if (!file_.is_open()) return ppcr::Status::Ok();  // no --pairs
  const ppcr::RegistrationResult& r = outcome.result;
  const bool measured = outcome.has_measures;
  const std::string row =
      std::to_string(scan) + ',' + field(file) + ',' + field(method) + ',' +
      (measured ? number(r.fitness, "%.6f") : "") + ',' +
      (measured ? ppcr::to_string(r.quality) : "") + ',' + field(r.quality_reason) + ',' +
      (measured ? number(r.inlier_rmse, "%.6g") : "") + ',' + std::to_string(r.iterations) + ',' +
      field(outcome.stop_reason) + ',' + number(time_ms, "%.3f");
  return file_.write_line(row);
}

}  // namespace ppcr_odometry
