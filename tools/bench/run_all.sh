#!/usr/bin/env bash
# Runs every ppcr_bench method (ppcr variants and every peer this build has) on both benchmark
# sets with the protocol of the docs' reference figures, and writes per-problem CSVs, JSON
# summaries and a markdown table. Every "ppcr vs X" figure in the docs comes from one such run.
#
#   tools/bench/run_all.sh [OUT_DIR]        (default OUT_DIR: build/bench-results)
#
# Environment:
#   PPCR_BUILD_DIR   build folder, configured Release with -DPPCR_BUILD_PEERS=ON and
#                    (re)built here (default build/peers)
#   PPCR_JOBS        build jobs (default 2)
#   PPCR_DATA_DIR    folder holding benchmark/ (default ../shared/data beside the project)
#   PPCR_BENCH_LIMIT run only the first N problems of each set (default: all; for quick checks)
#   PPCR_BENCH_SETS  sets to run (default "bunny lidar")
#   PPCR_SKIP_BUILD  1 = use the existing ppcr_bench in PPCR_BUILD_DIR as it is
#
# Outputs in OUT_DIR: <set>_<method>.csv (one row per problem), <set>_<method>.json (summary),
# <set>_<method>.log (stderr), summary.md (machine, commands, table), summary.json (all rows).
# Needs the peers' packages (Debian: libpcl-dev; libopen3d-dev for the Open3D methods).
set -euo pipefail
root=$(cd "$(dirname "$0")/../.." && pwd)
cd "$root"
out=${1:-build/bench-results}
build=${PPCR_BUILD_DIR:-build/peers}
jobs=${PPCR_JOBS:-2}
data_dir=${PPCR_DATA_DIR:-$root/../shared/data}
data=$(cd "$data_dir" 2>/dev/null && pwd || echo "$data_dir")/benchmark
limit=${PPCR_BENCH_LIMIT:-0}
sets=${PPCR_BENCH_SETS:-bunny lidar}

if [[ ${PPCR_SKIP_BUILD:-0} != 1 ]]; then
  echo "== build ppcr_bench with peers in $build"
  cmake -S . -B "$build" -DCMAKE_BUILD_TYPE=Release -DPPCR_BUILD_PEERS=ON -DPPCR_BUILD_TESTS=OFF
  cmake --build "$build" -j "$jobs" --target ppcr_bench
fi
bench="$build/tools/bench/ppcr_bench"
[[ -x $bench ]] || { echo "run_all.sh: $bench not found (build it first)" >&2; exit 1; }
for s in $sets; do
  [[ -f $data/${s}_local.txt ]] || { echo "run_all.sh: $data/${s}_local.txt not found" >&2; exit 1; }
done
mkdir -p "$out"

# Every method this build offers, from the --method help ("registration method: a b c (default").
methods=$("$bench" --help | tr '\n' ' ' | sed -n 's/.*registration method:\([^(]*\)(default.*/\1/p')
[[ -n $methods ]] || { echo "run_all.sh: cannot read the method list from --help" >&2; exit 1; }

# The protocol of the reference figures, per set (tools/bench/protocol.txt).
# shellcheck source=protocol.sh
source "$root/tools/bench/protocol.sh"
protocol() { bench_protocol "$1" || exit 1; }

# Runs: label|ppcr_bench arguments. ppcr in ten variants, then every peer.
# ppcr: the defaults (plane model); sn = with source normals (issue #8); sn-mse = source normals
# with the cost-drop + MSE-prev criterion (docs/TERMINATION.md section 10); sn-nf = source
# normals and the EM scale floored at the target's surface noise; sn-nf-dof1 = the same with
# Student-t dof 1 (docs/BENCHMARK.md); sn-nf08-dof125 = source normals, floor 0.8 x the surface
# noise, dof 1.25 (a setting of BENCHMARK.md that beats every peer on both sets);
# sn-nf08-dof125-k5-cs3 = the same with 5 target neighbours per source point and the coarse
# phase on every 3rd source point (issue #8's setting within issue #6's time budget);
# point = the paper's error with our EM scale and motion guard; paper = the paper's own
# settings (point errors, raw units, cost drop alone).
runs=("ppcr|--method ppcr" "ppcr-sn|--method ppcr --source-normals"
      "ppcr-sn-mse|--method ppcr --source-normals --criterion cost-drop,mse-prev"
      "ppcr-sn-nf|--method ppcr --source-normals --noise-floor 1"
      "ppcr-sn-nf-dof1|--method ppcr --source-normals --noise-floor 1 --dof 1"
      "ppcr-sn-nf08-dof125|--method ppcr --source-normals --noise-floor 0.8 --dof 1.25"
      "ppcr-sn-nf08-dof125-k5-cs3|--method ppcr --source-normals --noise-floor 0.8 --dof 1.25 --max-neighbours 5 --coarse-stride 3"
      "ppcr-point|--method ppcr --error-model point"
      "ppcr-gaussian|--method ppcr --gaussian"
      "ppcr-paper|--method ppcr --error-model point --scale raw --motion-guard 0")
for m in $methods; do  # the peers (ppcr-reuse is ppcr's loop usage, the same results)
  [[ $m == ppcr* ]] || runs+=("$m|--method $m")
done

commands=()
failed=0
load_start=$(cut -d' ' -f1-3 /proc/loadavg)
for s in $sets; do
  for run in "${runs[@]}"; do
    label=${run%%|*}
    args=${run#*|}
    cmd="$bench $data/${s}_local.txt $args $(protocol "$s") --threads 1"
    # NDT's cell: 1 cm on the bunny (2 x radius = 4 cm stops ~10x worse), 2 x radius on lidar.
    [[ $label == pcl-ndt && $s == bunny ]] && cmd+=" --ndt-resolution 0.01"
    ((limit > 0)) && cmd+=" --limit $limit"
    cmd+=" --quiet --json --out $out/${s}_${label}.csv"
    commands+=("$cmd")
    echo "== $s $label"
    start=$(date +%s)
    # shellcheck disable=SC2086  # cmd is a word list we built
    if $cmd >"$out/${s}_${label}.json" 2>"$out/${s}_${label}.log"; then
      echo "   $(cat "$out/${s}_${label}.json")  ($(($(date +%s) - start)) s)"
    else
      echo "   FAILED (exit $?), see $out/${s}_${label}.log"
      echo "{\"method\":\"$label\",\"failed\":true}" >"$out/${s}_${label}.json"
      failed=$((failed + 1))
    fi
  done
done

# summary.md: machine, exact commands, table.
model=$(lscpu | sed -n 's/^Model name:[[:space:]]*//p' | head -n 1)
{
  echo "# ppcr_bench: ppcr and peers on the benchmark sets"
  echo
  echo "- date: $(date -u '+%Y-%m-%d %H:%M UTC')"
  echo "- machine: $(nproc) cores (nproc), ${model:-unknown CPU}, load average (1, 5, 15 min) at the start: $load_start, at the end: $(cut -d' ' -f1-3 /proc/loadavg)"
  echo "- $("$bench" --version), commit $(git -C "$root" rev-parse --short HEAD 2>/dev/null || echo unknown)"
  echo "- compiler: $(c++ --version | head -n 1)"
  for p in libpcl-dev libopen3d-dev; do
    v=$(dpkg-query -W -f='${Version}' "$p" 2>/dev/null || true)
    [[ -n $v ]] && echo "- $p $v"
  done
  echo "- protocol: single thread (--threads 1); time is the registration call only (the"
  echo "  peers' cloud conversion, kd-trees, normals / covariances / NDT grid included)"
  echo "- success: rotation error < 1 degree and translation error < the --success-translation bound"
  echo
  echo "Commands:"
  echo
  echo '```'
  printf '%s\n' "${commands[@]}"
  echo '```'
  echo
} >"$out/summary.md"
python3 - "$out" "$sets" "${runs[@]}" >>"$out/summary.md" <<'EOF'
import json, sys
out, sets, runs = sys.argv[1], sys.argv[2].split(), [r.split("|")[0] for r in sys.argv[3:]]
rows = []
print("| set | method | median | q75 | q95 | success | mean iterations | median ms | max ms |")
print("| --- | --- | ---: | ---: | ---: | ---: | ---: | ---: | ---: |")
for s in sets:
    for label in runs:
        with open(f"{out}/{s}_{label}.json") as f:
            j = json.load(f)
        j["set"], j["label"] = s, label
        rows.append(j)
        if j.get("failed"):
            print(f"| {s} | {label} | failed | | | | | | |")
            continue
        print(f"| {s} | {label} | {j['median']:.4g} | {j['q75']:.4g} | {j['q95']:.4g} | "
              f"{100 * j['success']:.0f} % | {j['mean_iterations']:.1f} | "
              f"{j['median_ms']:.0f} | {j['max_ms']:.0f} |")
notes = [r for r in rows if not r.get("failed") and r["failures"]]
if notes:
    print()
for r in notes:
    print(f"- {r['set']} {r['label']}: {r['failures']} problem(s) failed to run "
          f"(counted with the error of the transform returned)")
with open(f"{out}/summary.json", "w") as f:
    json.dump(rows, f, indent=1)
EOF
echo "== wrote $out/summary.md"
cat "$out/summary.md"
((failed == 0)) || { echo "run_all.sh: $failed run(s) failed" >&2; exit 1; }
