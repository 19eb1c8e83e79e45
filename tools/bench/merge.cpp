// merge.cpp - putting the shards' CSVs back together.
#include "bench/merge.hpp"

#include <unistd.h>

#include <cstdio>
#include <fstream>
#include <iterator>
#include <set>
#include <sstream>

namespace ppcr_bench {
namespace {

ppcr::Status error(const std::string& message) {
  return ppcr::Status(ppcr::StatusCode::kParseError, message);
}

std::string shorten(const std::string& text) {
  return text.size() <= 120 ? text : text.substr(0, 117) + "...";
}

// The settings' words found in `a` and not in `b`, for saying what differs.
std::string only_in(const std::string& a, const std::string& b) {
  std::istringstream wa(a), wb(b);
  std::set<std::string> words_b{std::istream_iterator<std::string>(wb), {}};
  std::string out;
  for (std::istream_iterator<std::string> w(wa), end; w != end; ++w) {
    if (words_b.count(*w) == 0) out += (out.empty() ? "" : " ") + *w;
  }
  return out.empty() ? "(none)" : out;
}

// Why `row` cannot be in the same run as `first` (read at `first_at`), or "" when it can.
std::string conflict(const RunInfo& row, const RunInfo& first, const std::string& first_at) {
  if (row.label != first.label) {
    return "method '" + row.label + "' differs from '" + first.label + "' at " + first_at;
  }
  if (row.settings != first.settings) {
    return "settings differ from " + first_at + "'s: here " +
           only_in(row.settings, first.settings) + ", there " +
           only_in(first.settings, row.settings) +
           " (the shards of one run take the same flags and problem file)";
  }
  if (row.problem_count != first.problem_count ||
      row.success_rotation_deg != first.success_rotation_deg ||
      row.success_translation != first.success_translation) {
    return "problem_count, success_rotation or success_translation differs from " + first_at;
  }
  return "";
}

struct Slot {
  std::string at;  // file:line, empty while no shard has the problem
  ReadRow row;
  std::string line;
};

class Merger {
 public:
  ppcr::Status read(const std::string& path) {
    std::ifstream in(path);
    if (!in) return error(path + ": cannot open the shard's CSV");
    std::string line;
    if (!std::getline(in, line)) {
      return error(path + ":1: empty, expected the header of ppcr_bench --out");
    }
    if (!line.empty() && line.back() == '\r') line.pop_back();
    if (line != csv_header()) {
      return error(path +
                   ":1: not the header of this ppcr_bench's --out (a CSV from another "
                   "version, or not a shard's): got '" +
                   shorten(line) + "'");
    }
    for (int line_no = 2; std::getline(in, line); ++line_no) {
      if (!line.empty() && line.back() == '\r') line.pop_back();
      if (line.empty()) continue;
      const ppcr::Status s = add(path + ":" + std::to_string(line_no), line);
      if (!s.ok()) return s;
    }
    if (in.bad()) return error(path + ": read failed");
    return ppcr::Status::Ok();
  }

  ppcr::Status finish(const std::vector<std::string>& paths, MergedRun* merged) const {
    if (first_at_.empty()) return error("no problem row in " + list(paths));
    std::vector<std::size_t> missing;
    for (std::size_t i = 0; i < slots_.size(); ++i) {
      if (slots_[i].at.empty()) missing.push_back(i);
    }
    if (!missing.empty()) {
      std::string which;
      for (std::size_t k = 0; k < missing.size() && k < 10; ++k) {
        which += (k ? ", " : "") + std::to_string(missing[k]);
      }
      return error(std::to_string(missing.size()) + " of " + std::to_string(slots_.size()) +
                   " problems are in no shard (problem_index " + which +
                   (missing.size() > 10 ? ", ..." : "") +
                   "): a shard's CSV is not given or was cut short; read " + list(paths));
    }
    MergedRun m;
    m.run = first_;
    for (const Slot& slot : slots_) {
      m.outcomes.push_back(slot.row.outcome);
      if (!slot.row.ok) ++m.failures;
      m.lines.push_back(slot.line);
    }
    *merged = std::move(m);
    return ppcr::Status::Ok();
  }

 private:
  static std::string list(const std::vector<std::string>& paths) {
    std::string text;
    for (const std::string& p : paths) text += (text.empty() ? "" : ", ") + p;
    return text;
  }

  ppcr::Status add(const std::string& at, const std::string& line) {
    ReadRow row;
    const ppcr::Status s = parse_row(line, &row);
    if (!s.ok()) return error(at + ": " + s.message());
    if (first_at_.empty()) {
      first_ = row.run;
      first_at_ = at;
      slots_.resize(first_.problem_count);
    }
    const std::string why = conflict(row.run, first_, first_at_);
    if (!why.empty()) return error(at + ": " + why);
    Slot& slot = slots_[row.index];
    if (!slot.at.empty()) {
      return error(at + ": problem_index " + std::to_string(row.index) + " (id " + row.id +
                   ") is also at " + slot.at +
                   ": a CSV given twice, or shards run with different --shard N");
    }
    slot = Slot{at, std::move(row), line};
    return ppcr::Status::Ok();
  }

  RunInfo first_;
  std::string first_at_;
  std::vector<Slot> slots_;  // by problem_index
};

}  // namespace

ppcr::Status merge_shards(const std::vector<std::string>& paths, MergedRun* merged) {
  Merger merger;
  for (const std::string& path : paths) {
    const ppcr::Status s = merger.read(path);
    if (!s.ok()) return s;
  }
  return merger.finish(paths, merged);
}

ppcr::Status write_merged_csv(const std::string& path, const MergedRun& merged) {
  const std::string temporary = path + ".partial." + std::to_string(getpid());
  std::FILE* out = std::fopen(temporary.c_str(), "w");
  if (out == nullptr) {
    return ppcr::Status(ppcr::StatusCode::kIoError,
                        path + ": cannot write (its temporary " + temporary + " cannot be opened)");
  }
  bool ok = std::fprintf(out, "%s\n", csv_header().c_str()) > 0;
  for (const std::string& line : merged.lines) {
    ok = ok && std::fprintf(out, "%s\n", line.c_str()) > 0;
  }
  ok = std::fclose(out) == 0 && ok;
  if (!ok || std::rename(temporary.c_str(), path.c_str()) != 0) {
    std::remove(temporary.c_str());
    return ppcr::Status(ppcr::StatusCode::kIoError, path + ": write failed");
  }
  return ppcr::Status::Ok();
}

}  // namespace ppcr_bench
