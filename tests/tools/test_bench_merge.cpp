// ppcr_bench's shards and merge (tools/bench/shard.hpp, merge.hpp, results_csv.hpp): shards'
// CSVs written by the bench's own row writer merge back into the whole run, in problem order and
// with the exact values; every way the shards can disagree is refused with the file and line.
#include <unistd.h>

#include <catch2/catch.hpp>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <limits>
#include <sstream>
#include <string>
#include <vector>

#include "bench/merge.hpp"
#include "bench/results_csv.hpp"
#include "bench/shard.hpp"
#include "bench/summary.hpp"

namespace {

// One folder per process: ctest runs the test cases in parallel.
const std::string kDir = std::string(PPCR_BENCH_TEST_DIR) + "/" + std::to_string(getpid());

bool contains(const std::string& s, const std::string& part) {
  return s.find(part) != std::string::npos;
}

ppcr_bench::RunInfo run_info() {
  ppcr_bench::RunInfo run;
  run.label = "ppcr, \"tuned\"";  // a comma and quotes: the field is quoted
  run.settings = "--radius=0.02 --method=ppcr problems=0123456789abcdef version=test";
  run.problem_count = 7;
  run.success_rotation_deg = 1.0;
  run.success_translation = 0.002;
  return run;
}

// Problem i's row: values that need all 17 digits to come back exactly; problem 3 failed to run.
ppcr_bench::ProblemRow problem_row(std::size_t i) {
  ppcr_bench::ProblemRow row;
  row.index = i;
  row.id = "p" + std::to_string(i);
  row.outcome.error = (i + 1) / 3.0 * 1e-3;
  row.outcome.rotation_error_deg = std::sqrt(2.0) * (i % 3);
  row.outcome.translation_error = 0.001 * std::sqrt(static_cast<double>(i));
  row.outcome.iterations = static_cast<int>(10 + i);
  row.outcome.time_ms = 1.25 * i;
  row.result.ok = i != 3;
  row.result.stop_reason = "cost_drop";
  row.result.quality = "good";
  return row;
}

// Writes shard `shard` of `count` with the bench's writer (rows in reverse: order must not matter).
std::string write_shard(std::size_t shard, std::size_t count,
                        const ppcr_bench::RunInfo& run = run_info()) {
  std::filesystem::create_directories(kDir);
  const std::string path = kDir + "/shard_" + std::to_string(shard) + ".csv";
  std::ofstream out(path);
  out << ppcr_bench::csv_header() << "\n";
  for (std::size_t i = run.problem_count; i-- > 0;) {
    if (i % count == shard) out << ppcr_bench::format_row(run, problem_row(i));
  }
  return path;
}

std::string write_text(const std::string& name, const std::string& text) {
  std::filesystem::create_directories(kDir);
  const std::string path = kDir + "/" + name;
  std::ofstream(path) << text;
  return path;
}

std::string merge_error(const std::vector<std::string>& paths) {
  ppcr_bench::MergedRun merged;
  const ppcr::Status s = ppcr_bench::merge_shards(paths, &merged);
  return s.ok() ? std::string("(merged)") : s.message();
}

}  // namespace

TEST_CASE("shard I/N puts each problem in exactly one shard and names bad values", "[bench]") {
  ppcr_bench::Shard s;
  REQUIRE(ppcr_bench::parse_shard("2/3", &s).ok());
  CHECK((s.index == 2 && s.count == 3));
  CHECK((s.has(2) && s.has(5) && !s.has(3) && !s.has(0)));
  for (std::size_t i = 0; i < 20; ++i) {
    int owners = 0;
    for (std::size_t k = 0; k < 4; ++k) owners += ppcr_bench::Shard{k, 4}.has(i) ? 1 : 0;
    CHECK(owners == 1);
  }
  CHECK(ppcr_bench::parse_shard("4/4", &s).message() == "--shard 4/4: I must be in [0, N)");
  CHECK(ppcr_bench::parse_shard("0/0", &s).message() == "--shard 0/0: N must be at least 1");
  for (const char* bad : {"", "3", "-1/4", "1/", "/4", "a/b", "1/4/2", " 1/4", "1.0/4"}) {
    INFO(bad);
    const ppcr::Status status = ppcr_bench::parse_shard(bad, &s);
    CHECK(!status.ok());
    CHECK(contains(status.message(), std::string("--shard ") + bad + ": expected I/N"));
  }
}

TEST_CASE("CSV fields with commas and quotes, and numbers, come back as written", "[bench]") {
  const std::vector<std::string> texts = {"plain", "a,b", "say \"hi\"", "", "\",\""};
  std::string line;
  for (const std::string& t : texts) line += (line.empty() ? "" : ",") + ppcr_bench::csv_field(t);
  std::vector<std::string> fields;
  REQUIRE(ppcr_bench::split_csv_line(line, &fields));
  CHECK(fields == texts);
  CHECK(!ppcr_bench::split_csv_line("a,\"b", &fields));
  CHECK(ppcr_bench::round_trip(0.05) == "0.05");
  CHECK(ppcr_bench::round_trip(1.0) == "1");
  const double third = 1.0 / 3.0;
  CHECK(std::strtod(ppcr_bench::round_trip(third).c_str(), nullptr) == third);
}

TEST_CASE("merged shards are the whole run, in problem order, values exact", "[bench]") {
  std::vector<std::string> paths;
  for (std::size_t k : {2, 0, 1}) paths.push_back(write_shard(k, 3));
  ppcr_bench::MergedRun merged;
  const ppcr::Status s = ppcr_bench::merge_shards(paths, &merged);
  INFO(s.message());
  REQUIRE(s.ok());
  const ppcr_bench::RunInfo run = run_info();
  CHECK(merged.run.label == run.label);
  CHECK(merged.run.settings == run.settings);
  CHECK(merged.run.success_translation == run.success_translation);
  CHECK(merged.failures == 1);
  REQUIRE(merged.outcomes.size() == run.problem_count);
  REQUIRE(merged.lines.size() == run.problem_count);
  for (std::size_t i = 0; i < run.problem_count; ++i) {
    const ppcr_bench::ProblemRow expected = problem_row(i);
    CHECK(merged.outcomes[i].error == expected.outcome.error);
    CHECK(merged.outcomes[i].rotation_error_deg == expected.outcome.rotation_error_deg);
    CHECK(merged.outcomes[i].translation_error == expected.outcome.translation_error);
    CHECK(merged.outcomes[i].iterations == expected.outcome.iterations);
    CHECK(merged.lines[i] + "\n" == ppcr_bench::format_row(run, expected));
  }
  // The merged CSV is the unsharded run's: the same writer's rows, in problem order.
  const std::string out = kDir + "/merged.csv";
  REQUIRE(ppcr_bench::write_merged_csv(out, merged).ok());
  std::ifstream in(out);
  std::stringstream text;
  text << in.rdbuf();
  std::string whole = ppcr_bench::csv_header() + "\n";
  for (std::size_t i = 0; i < run.problem_count; ++i) {
    whole += ppcr_bench::format_row(run, problem_row(i));
  }
  CHECK(text.str() == whole);
}

TEST_CASE("a problem in two shards is refused, naming both places", "[bench]") {
  const std::string a = write_shard(0, 2);
  const std::string copy = write_text("copy.csv", [&] {
    std::ifstream in(a);
    std::stringstream t;
    t << in.rdbuf();
    return t.str();
  }());
  const std::string message = merge_error({a, write_shard(1, 2), copy});
  CHECK(contains(message, copy + ":2: problem_index 6 (id p6) is also at " + a + ":2"));
}

TEST_CASE("a missing shard is refused, naming the problems in none", "[bench]") {
  const std::string message = merge_error({write_shard(0, 3), write_shard(2, 3)});
  CHECK(contains(message, "2 of 7 problems are in no shard (problem_index 1, 4)"));
}

TEST_CASE("a wrong or missing header, an unreadable file and a bad row are named", "[bench]") {
  const std::string old_header = write_text("old.csv", "id,method,error\np0,ppcr,0.1\n");
  CHECK(contains(merge_error({old_header}), old_header + ":1: not the header"));
  const std::string empty = write_text("empty.csv", "");
  CHECK(contains(merge_error({empty}), empty + ":1: empty"));
  CHECK(contains(merge_error({kDir + "/absent.csv"}), kDir + "/absent.csv: cannot open"));
  std::string row = ppcr_bench::format_row(run_info(), problem_row(0));
  row.replace(row.find("p0,"), 3, "p0,\"");  // an unclosed quote
  const std::string bad = write_text("bad.csv", ppcr_bench::csv_header() + "\n\n" + row);
  CHECK(contains(merge_error({bad}), bad + ":3: a quoted field is not closed"));
  std::string short_row = ppcr_bench::format_row(run_info(), problem_row(0));
  short_row.replace(short_row.find(",cost_drop,"), 11, ",");  // a field less
  const std::string short_file =
      write_text("short.csv", ppcr_bench::csv_header() + "\n" + short_row);
  CHECK(contains(merge_error({short_file}), short_file + ":2: expected 32 fields, got 31"));
  std::string nan_index = ppcr_bench::format_row(run_info(), problem_row(0));
  nan_index.replace(nan_index.find(",0,7,"), 5, ",x,7,");
  const std::string index_file =
      write_text("index.csv", ppcr_bench::csv_header() + "\n" + nan_index);
  CHECK(contains(merge_error({index_file}),
                 index_file + ":2: column problem_index: expected a whole number, got 'x'"));
}

TEST_CASE("shards of different methods or settings are refused, saying what differs", "[bench]") {
  ppcr_bench::RunInfo other = run_info();
  other.settings = "--radius=0.03 --method=ppcr problems=0123456789abcdef version=test";
  const std::string a = write_shard(0, 2);
  const std::string b = write_text("other_settings.csv", "");
  std::filesystem::rename(write_shard(1, 2, other), b);
  const std::string message = merge_error({a, b});
  CHECK(contains(message, b + ":2: settings differ from " + a +
                              ":2's: here --radius=0.03, "
                              "there --radius=0.02"));
  other = run_info();
  other.label = "pcl-gicp";
  std::filesystem::rename(write_shard(1, 2, other), b);
  CHECK(contains(merge_error({a, b}), b + ":2: method 'pcl-gicp' differs"));
}

TEST_CASE("the merged CSV is written whole or not at all", "[bench]") {
  ppcr_bench::MergedRun merged;
  REQUIRE(ppcr_bench::merge_shards({write_shard(0, 1)}, &merged).ok());
  const std::string out = kDir + "/no_such_folder/merged.csv";
  const ppcr::Status s = ppcr_bench::write_merged_csv(out, merged);
  CHECK(!s.ok());
  CHECK(contains(s.message(), "no_such_folder/merged.csv"));
  CHECK(!std::filesystem::exists(out));
  for (const auto& entry : std::filesystem::directory_iterator(kDir)) {
    CHECK(!contains(entry.path().string(), ".partial."));
  }
}

TEST_CASE("normalised_error is e^T C^-1 e, NaN for a covariance that is not positive definite",
          "[bench]") {
  Eigen::Matrix<double, 6, 1> e;
  e << 1, 2, 0, 0, 3, 0;
  Eigen::Matrix<double, 6, 6> C = Eigen::Matrix<double, 6, 6>::Identity();
  C(0, 0) = 4.0;  // 1^2 / 4
  C(1, 1) = 0.5;  // 2^2 / 0.5
  C(4, 4) = 9.0;  // 3^2 / 9
  CHECK(ppcr_bench::normalised_error(e, C) == Approx(0.25 + 8.0 + 1.0));
  C(0, 1) = C(1, 0) = 0.5;  // correlated: against the explicit inverse
  CHECK(ppcr_bench::normalised_error(e, C) == Approx(e.dot(C.inverse() * e)));
  Eigen::Matrix<double, 6, 6> singular = C;
  singular(5, 5) = 0.0;
  CHECK(std::isnan(ppcr_bench::normalised_error(e, singular)));
  CHECK(std::isnan(ppcr_bench::normalised_error(
      e, Eigen::Matrix<double, 6, 6>::Constant(std::numeric_limits<double>::quiet_NaN()))));
}
