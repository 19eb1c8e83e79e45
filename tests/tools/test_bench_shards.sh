#!/usr/bin/env bash
# ppcr_bench --shard and --merge as docs/BENCHMARK.md runs them: four shards under GNU parallel,
# then a merge, checked against the reference, the unsharded run of the same problems: the
# summary (text and JSON) and the per-problem CSV must be equal but for the timings. The problems
# come from a small synthetic pair rendered by ppcr_synth, so the test needs no shared data.
# Usage: test_bench_shards.sh PPCR_BENCH PPCR_SYNTH WORK_DIR
# Exit 0 passed, 1 failed, 77 skipped with the marker PPCR-TEST-SKIPPED (GNU parallel not
# installed). The files of a failed run stay in WORK_DIR/<pid>.
set -euo pipefail
bench=$1 synth=$2 work=$3/$$
# shellcheck source=bench_test_common.sh
source "$(dirname "$0")/bench_test_common.sh"

# Debian's moreutils also installs a `parallel`, with other options: only GNU parallel will do.
# Under CI=true or PPCR_STRICT=1 its absence fails the test instead of skipping it.
if ! parallel --version 2>/dev/null | grep -q "GNU parallel"; then
  why="GNU parallel is not installed (Debian: apt-get install parallel; tools/install_deps.sh installs it)"
  if [[ ${CI:-} == true || ${PPCR_STRICT:-} == 1 ]]; then
    fail "$why, and CI=true or PPCR_STRICT=1 requires it"
  fi
  echo "PPCR-TEST-SKIPPED: $why"
  exit 77
fi

rm -rf "$work"
mkdir -p "$work"
problems=$(make_problems "$synth" "$work/pair")
flags=(--radius 0.05 --source-voxel 0.005 --target-voxel 0.005 --success-translation 0.003 --quiet)

# The reference: one unsharded run (text summary and CSV), and its JSON summary.
"$bench" "$problems" "${flags[@]}" --out "$work/whole.csv" > "$work/whole.txt"
"$bench" "$problems" "${flags[@]}" --json > "$work/whole.json"
grep -q "^method ppcr, 10 problems " "$work/whole.txt" ||
  fail "the reference run did not run the 10 problems: $(cat "$work/whole.txt")"

# Four shards at once, as a local run does it.
parallel -q --halt now,fail=1 "$bench" "$problems" "${flags[@]}" --shard {}/4 \
  --out "$work/shard_{}.csv" ::: 0 1 2 3 > "$work/shards.txt"
shards=("$work"/shard_{0,1,2,3}.csv)
for k in 0 1 2 3; do  # problem i in shard i mod 4: 3, 3, 2 and 2 rows
  rows=$(($(wc -l < "$work/shard_$k.csv") - 1))
  [[ $rows -eq $(((10 - k + 3) / 4)) ]] || fail "shard $k has $rows rows"
done

"$bench" --merge "${shards[@]}" --out "$work/merged.csv" > "$work/merged.txt"
"$bench" --merge "${shards[@]}" --json > "$work/merged.json"

# Equal but for the timings.
mask_text() { sed -E 's/time median [0-9.]+ ms  max [0-9.]+ ms/time median - ms  max - ms/' "$1"; }
mask_json() { sed -E 's/"(median_ms|max_ms)":[^,}]*/"\1":-/g' "$1"; }
# The CSV without its time_ms and quality_ms columns (no field of this run holds a comma).
mask_csv() {
  awk -F, 'NR == 1 { for (k = 1; k <= NF; ++k) drop[k] = ($k == "time_ms" || $k == "quality_ms") }
           { line = ""; for (k = 1; k <= NF; ++k) if (!drop[k]) line = line $k ","; print line }' "$1"
}
diff <(mask_text "$work/whole.txt") <(mask_text "$work/merged.txt") ||
  fail "the merged summary differs from the unsharded run's"
diff <(mask_json "$work/whole.json") <(mask_json "$work/merged.json") ||
  fail "the merged JSON summary differs from the unsharded run's"
diff <(mask_csv "$work/whole.csv") <(mask_csv "$work/merged.csv") ||
  fail "the merged CSV differs from the unsharded run's"

# Refusals: a clear message naming the flag or file, a non-zero status, no output written.
expect_error 2 "--shard 4/4: I must be in [0, N)" "$bench" "$problems" "${flags[@]}" --shard 4/4
expect_error 1 "2 of 10 problems are in no shard (problem_index 3, 7)" \
  "$bench" --merge "$work/shard_0.csv" "$work/shard_1.csv" "$work/shard_2.csv" \
  --out "$work/incomplete.csv"
[[ ! -e $work/incomplete.csv ]] || fail "a refused merge wrote its --out"
expect_error 1 "is also at $work/shard_2.csv:2" "$bench" --merge "${shards[@]}" "$work/shard_2.csv"
expect_error 1 "$work/whole.txt:1: not the header" "$bench" --merge "$work/whole.txt"
expect_error 2 "--merge takes the shards' CSVs" "$bench" --merge "${shards[@]}" --radius 1

rm -rf "$work"
echo "PASS: 4 shards under GNU parallel merged into the unsharded run's summary and CSV"
