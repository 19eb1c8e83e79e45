// merge.hpp - `ppcr_bench --merge A.csv B.csv ...`: the per-problem CSVs of the shards of one run
// (--shard I/N) put back together in problem order, so that the summary and the CSV are those of
// the unsharded run (timings aside). Refuses anything that would make them differ: an unreadable
// file, a header that is not ppcr_bench's, a row that does not parse, a problem in two shards or
// in none, shards of different methods or settings.
#pragma once

#include <string>
#include <vector>

#include "bench/results_csv.hpp"
#include "bench/summary.hpp"
#include "ppcr/status.hpp"

namespace ppcr_bench {

struct MergedRun {
  RunInfo run;
  std::vector<ProblemOutcome> outcomes;  // in problem order
  std::size_t failures = 0;              // rows whose method failed to run
  std::vector<std::string> lines;        // the rows as the shards wrote them, in problem order
};

/// Reads and checks every CSV; messages name the file and line (and the other file's line for a
/// conflict). *merged is set only on success.
ppcr::Status merge_shards(const std::vector<std::string>& paths, MergedRun* merged);

/// Writes the merged CSV (header and rows) to `path` through a temporary file renamed at the
/// end: `path` is the complete file or untouched.
ppcr::Status write_merged_csv(const std::string& path, const MergedRun& merged);

}  // namespace ppcr_bench
