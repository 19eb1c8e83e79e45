// results_csv.hpp - ppcr_bench's per-problem CSV (--out): a header, then one row per problem with
// its errors and the method's measures, and what a merge of shards needs to rebuild the whole
// run: the problem's index in the problem file, the number of problems, the success bounds and
// the run's settings. Written and read here only, so the two cannot drift apart.
#pragma once

#include <cstddef>
#include <string>
#include <vector>

#include "bench/method.hpp"
#include "bench/summary.hpp"
#include "ppcr/status.hpp"

namespace ppcr_bench {

/// The header line, without its newline.
const std::string& csv_header();

/// What every row of one run shares.
struct RunInfo {
  std::string label;     // the method column
  std::string settings;  // run_settings(): must be equal in every shard of one run
  std::size_t problem_count = 0;
  double success_rotation_deg = 1.0, success_translation = 0.0;
};

/// One problem's row, as written.
struct ProblemRow {
  std::size_t index = 0;  // in the problem file (after --limit)
  std::string id;
  ProblemOutcome outcome;
  MethodResult result;
  std::size_t source_points = 0, target_points = 0;
};

/// The row's line, newline included. The summary's inputs (error, rotation and translation
/// errors) and the success bounds are written exactly (round_trip), so that a merge of shards
/// reproduces the summary exactly.
std::string format_row(const RunInfo& run, const ProblemRow& row);

/// What a merge reads back from a row.
struct ReadRow {
  RunInfo run;
  std::size_t index = 0;
  std::string id;
  ProblemOutcome outcome;
  bool ok = false;  // the method ran
};

/// Parses one data line; the message names the column and the value seen (the caller adds the
/// file and line).
ppcr::Status parse_row(const std::string& line, ReadRow* row);

/// The shortest decimal text that reads back as exactly `value` (at most 17 significant digits).
std::string round_trip(double value);

/// A field as CSV writes it: quoted (quotes doubled) when it holds a comma, a quote or a newline.
std::string csv_field(const std::string& text);

/// Splits one line into fields (RFC 4180 quoting, no newline inside a field); false when a
/// quote is not closed.
bool split_csv_line(const std::string& line, std::vector<std::string>* fields);

}  // namespace ppcr_bench
