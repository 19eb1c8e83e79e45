#!/usr/bin/env bash
# ppcr_bench --methods: two methods on the same problems in one process. Without the peers the
# two are ppcr and ppcr-reuse (ppcr in the loop usage), whose results must be equal: the test
# checks the table and the CSV against the single-method runs of the same problems, the time
# ratios against ones recomputed from the CSV, that one method through --methods prints what
# --method prints, and the refusals. The problems come from a small synthetic pair rendered by
# ppcr_synth, so the test needs no shared data.
# Usage: test_bench_methods.sh PPCR_BENCH PPCR_SYNTH WORK_DIR
# Exit 0 passed, 1 failed. The files of a failed run stay in WORK_DIR/<pid>.
set -euo pipefail
bench=$1 synth=$2 work=$3/$$
# shellcheck source=bench_test_common.sh
source "$(dirname "$0")/bench_test_common.sh"

rm -rf "$work"
mkdir -p "$work"
problems=$(make_problems "$synth" "$work/pair")
flags=(--radius 0.05 --source-voxel 0.005 --target-voxel 0.005 --success-translation 0.003 --quiet)

# The references: each method alone.
"$bench" "$problems" "${flags[@]}" --method ppcr --out "$work/ppcr.csv" > "$work/ppcr.txt"
"$bench" "$problems" "${flags[@]}" --method ppcr-reuse --out "$work/reuse.csv" > "$work/reuse.txt"
grep -q "^method ppcr, 10 problems (0 failed to run)$" "$work/ppcr.txt" ||
  fail "the single run did not run the 10 problems: $(cat "$work/ppcr.txt")"

# One method through --methods: the single-method summary, as before.
"$bench" "$problems" "${flags[@]}" --methods ppcr > "$work/one.txt"
mask_text() { sed -E 's/time median [0-9.]+ ms  max [0-9.]+ ms/time median - ms  max - ms/' "$1"; }
diff <(mask_text "$work/ppcr.txt") <(mask_text "$work/one.txt") ||
  fail "--methods ppcr does not print --method ppcr's summary"

# Both at once: the table, the JSON, and every method's rows in the CSV.
"$bench" "$problems" "${flags[@]}" --methods ppcr,ppcr-reuse --out "$work/both.csv" \
  > "$work/both.txt"
"$bench" "$problems" "${flags[@]}" --methods ppcr,ppcr-reuse --json --out "$work/json.csv" \
  > "$work/both.json"

python3 - "$work" << 'PY' || fail "the comparison does not match the single runs (above)"
import csv, json, statistics, sys

work = sys.argv[1]
def rows(name):
    with open(f"{work}/{name}") as f:
        return list(csv.DictReader(f))
def summary_line(name, start):
    return next(l for l in open(f"{work}/{name}") if l.startswith(start)).split()

problems = 10
both, alone = rows("both.csv"), {"ppcr": rows("ppcr.csv"), "ppcr-reuse": rows("reuse.csv")}
errors = []
def check(ok, what):
    if not ok:
        errors.append(what)

# The CSV: every method's 10 rows, each equal to the method's own run but for the timings and
# the settings (which name --methods); ppcr-reuse's results equal ppcr's.
check(len(both) == 2 * problems, f"{len(both)} rows in both.csv, expected {2 * problems}")
skip = {"time_ms", "quality_ms", "settings"}
for method, reference in alone.items():
    mine = [r for r in both if r["method"] == method]
    check(len(mine) == problems, f"{len(mine)} rows of {method}")
    for a, b in zip(mine, reference):
        diff = [k for k in a if k not in skip and a[k] != b[k]]
        check(not diff, f"{method} problem {a['id']}: {diff} differ from its own run")
for a, b in zip(alone["ppcr"], alone["ppcr-reuse"]):
    diff = [k for k in a if k not in skip | {"method"} and a[k] != b[k]]
    check(not diff, f"ppcr-reuse differs from ppcr on problem {a['id']}: {diff}")

# The table's rows: the single runs' figures (same format), and the ratios of the JSON.
table = {l.split("|")[1].strip(): [c.strip() for c in l.split("|")[2:-1]]
         for l in open(f"{work}/both.txt") if l.startswith("| ppcr")}
check(list(table) == ["ppcr", "ppcr-reuse"], f"table rows {list(table)}")
for method, name in (("ppcr", "ppcr.txt"), ("ppcr-reuse", "reuse.txt")):
    error = summary_line(name, "error median")
    success = summary_line(name, "success")
    iterations = summary_line(name, "mean iterations")
    want = ["0", error[2], error[4], error[6], success[1] + " %", iterations[2]]
    check(table[method][:6] == want, f"table row {method} {table[method][:6]}, expected {want}")
check(table["ppcr"][7:] == ["1", "1"], f"ppcr's own ratios {table['ppcr'][7:]}")

# The ratios, recomputed from the same run's CSV: its times are written to 0.001 ms and the
# table's ratios to 3 digits, hence the tolerances.
def ratios(csv_name):
    t = {m: [float(r["time_ms"]) for r in rows(csv_name) if r["method"] == m] for m in alone}
    return (statistics.median(b / a for a, b in zip(t["ppcr"], t["ppcr-reuse"])),
            statistics.median(t["ppcr-reuse"]) / statistics.median(t["ppcr"]))
def near(value, want, tolerance):
    return abs(value - want) <= tolerance * want
for value, want, name in zip(map(float, table["ppcr-reuse"][7:]), ratios("both.csv"),
                             ("median per problem", "ratio of medians")):
    check(near(value, want, 0.01), f"table ratio, {name}: {value}, from the CSV {want}")
j = json.load(open(f"{work}/both.json"))
check(j["problems"] == problems and j["ratio_to"] == "ppcr", f"JSON head {j}")
check([m["method"] for m in j["methods"]] == ["ppcr", "ppcr-reuse"], "JSON methods")
for m in j["methods"]:
    check(m["problems"] == problems and m["failures"] == 0, f"JSON {m}")
reuse = j["methods"][1]
for key, want in zip(("median_time_ratio", "ratio_of_median_times"), ratios("json.csv")):
    check(near(reuse[key], want, 0.002), f"JSON {key} {reuse[key]}, from the CSV {want}")
for e in errors:
    print("  " + e, file=sys.stderr)
sys.exit(1 if errors else 0)
PY

# Refusals: a clear message naming the flag and the value, a non-zero status, no output.
expect_error 1 "--methods ppcr,nope: 'nope' is unknown or not built (available: ppcr ppcr-reuse" \
  "$bench" "$problems" "${flags[@]}" --methods ppcr,nope
expect_error 1 "--methods ppcr,ppcr-reuse,ppcr: 'ppcr' is given twice" \
  "$bench" "$problems" "${flags[@]}" --methods ppcr,ppcr-reuse,ppcr
expect_error 2 "give --method or --methods, not both" \
  "$bench" "$problems" "${flags[@]}" --method ppcr --methods ppcr,ppcr-reuse
expect_error 2 "--shard takes one method, got --methods ppcr,ppcr-reuse" \
  "$bench" "$problems" "${flags[@]}" --methods ppcr,ppcr-reuse --shard 0/2
expect_error 2 "--label takes one method" \
  "$bench" "$problems" "${flags[@]}" --methods ppcr,ppcr-reuse --label x
expect_error 1 "--reuse is for --method ppcr alone" \
  "$bench" "$problems" "${flags[@]}" --methods ppcr,ppcr-reuse --reuse

rm -rf "$work"
echo "PASS: --methods ppcr,ppcr-reuse: one table and one CSV, equal to the single runs"
