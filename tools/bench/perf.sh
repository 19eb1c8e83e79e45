#!/usr/bin/env bash
# Speed and memory measurements behind docs/PERFORMANCE.md (issue #6). Every figure of that page
# comes from one run of this script; it writes raw outputs and perf.md in OUT_DIR.
#
#   tools/bench/perf.sh [BUILD_DIR] [OUT_DIR]   (defaults: build/test-release, build/perf)
#
# BUILD_DIR must be a Release build with tools and benchmarks (tools/test.sh's release stage
# makes one: -DPPCR_BUILD_TOOLS=ON -DPPCR_BUILD_BENCHMARKS=ON). Needs ../shared/data (or
# $PPCR_DATA_DIR), /usr/bin/time and python3 with matplotlib for the scaling plot.
#   PERF_REPEAT=3      repetitions of each single registration (the median is reported)
#   PERF_LIMIT=50      benchmark problems per set for the end-to-end timings
#   PERF_SIZES="16:1024 64:2048 128:8192"   synthetic street scans, beams:steps
set -euo pipefail
root=$(cd "$(dirname "$0")/../.." && pwd)
# shellcheck source=protocol.sh
source "$root/tools/bench/protocol.sh"
cd "$root"
build=${1:-build/test-release}
out=${2:-build/perf}
data=${PPCR_DATA_DIR:-$root/../shared/data}
repeat=${PERF_REPEAT:-3}
limit=${PERF_LIMIT:-50}
sizes=${PERF_SIZES:-16:1024 64:2048 128:8192}
cli=$build/tools/ppcr_cli
bench=$build/tools/bench/ppcr_bench
synth=$build/tools/synth/ppcr_synth
micro=$build/benchmarks/ppcr_microbench
for exe in "$cli" "$bench" "$synth" "$micro"; do
  [[ -x $exe ]] || { echo "perf.sh: $exe not found (build $build with tools and benchmarks)" >&2; exit 1; }
done
[[ -d $data/benchmark ]] || { echo "perf.sh: $data/benchmark not found" >&2; exit 1; }
mkdir -p "$out"
md=$out/perf.md
py=/usr/bin/python3

# Runs ppcr_cli $repeat times under /usr/bin/time -v; prints "median_ms peak_rss_kb json_of_last".
single() {
  local tag=$1
  shift
  local i
  for ((i = 0; i < repeat; i++)); do
    /usr/bin/time -v -o "$out/$tag.time.$i" "$cli" "$@" --json --quiet >"$out/$tag.json.$i"
  done
  "$py" - "$out" "$tag" "$repeat" <<'EOF'
import json, re, statistics, sys
out, tag, n = sys.argv[1], sys.argv[2], int(sys.argv[3])
ms, rss = [], []
for i in range(n):
    d = json.load(open(f"{out}/{tag}.json.{i}"))
    ms.append(d["time_ms"])
    t = open(f"{out}/{tag}.time.{i}").read()
    rss.append(int(re.search(r"Maximum resident set size \(kbytes\): (\d+)", t).group(1)))
print(f"{statistics.median(ms):.1f} {max(rss)} {d['source_points']} {d['target_points']} "
      f"{d['iterations']} {d['lm_iterations']} {d.get('rotation_error_deg', float('nan')):.3f}")
EOF
}

{
  echo "# perf.sh run"
  echo
  echo "- date: $(date -u '+%Y-%m-%d %H:%M UTC'), host: $(nproc) cores, $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2 | xargs)"
  echo "- load average at start: $(cut -d' ' -f1-3 /proc/loadavg)"
  echo "- build: $build ($(grep -m1 CMAKE_BUILD_TYPE "$build/CMakeCache.txt" | cut -d= -f2))"
  echo
} >"$md"

echo "== end-to-end: ppcr_bench, first $limit problems per set, 1 and 2 threads" >&2
{
  echo "## End to end (ppcr_bench, first $limit problems, defaults, benchmark protocol)"
  echo
  echo "| set | options | threads | median ms | max ms | median error | q0.95 error | mean iterations | CPU s (whole run) |"
  echo "|---|---|---|---|---|---|---|---|---|"
} >>"$md"
for s in bunny lidar; do
  proto=$(bench_protocol "$s")  # tools/bench/protocol.txt
  for run in "defaults|1|" "defaults|2|"; do
    IFS='|' read -r name t extra <<<"$run"
    tag="bench_${s}_t${t}_${extra//[^0-9a-z]/}"
    # shellcheck disable=SC2086
    /usr/bin/time -f "%U %S" -o "$out/$tag.cpu" "$bench" "$data/benchmark/${s}_local.txt" $proto \
      $extra --threads "$t" --limit "$limit" --quiet --json >"$out/$tag.json"
    "$py" -c "import json,sys; d=json.load(open(sys.argv[1])); c=sum(map(float, open(sys.argv[2]).read().split())); print(f\"| $s | $name | $t | {d['median_ms']:.1f} | {d['max_ms']:.1f} | {d['median']:.5f} | {d['q95']:.5f} | {d['mean_iterations']:.1f} | {c:.1f} |\")" \
      "$out/$tag.json" "$out/$tag.cpu" >>"$md"
  done
done

echo "== full-resolution lidar pair, 1 and 2 threads" >&2
{
  echo
  echo "## Full-resolution lidar pair (no voxel filter), radius 1, from identity"
  echo
  echo "| threads | median ms ($repeat runs) | peak RSS KiB | source | target | iterations | LM steps | rotation error deg |"
  echo "|---|---|---|---|---|---|---|---|"
} >>"$md"
for t in 1 2; do
  read -r ms rss ns nt it lm rot < <(single "lidar_full_t$t" "$data/lidar/source.ply" \
    "$data/lidar/target.ply" --radius 1 --threads "$t" --ground-truth "$data/lidar/source_gt.txt")
  echo "| $t | $ms | $rss | $ns | $nt | $it | $lm | $rot |" >>"$md"
done

echo "== scaling: synthetic street scans" >&2
{
  echo
  echo "## Scaling (ppcr_synth street scene, seed 3, noise 1 cm, 3 degrees / 0.5 m apart; radius 1, 1 thread)"
  echo
  echo "| beams x steps | k | median ms | peak RSS KiB | source | target | iterations | LM steps | ms per (source point x iteration) | rotation error deg |"
  echo "|---|---|---|---|---|---|---|---|---|---|"
} >>"$md"
: >"$out/scaling.tsv"
for size in $sizes; do
  beams=${size%%:*}
  steps=${size#*:}
  dir=$out/street_${beams}x$steps
  [[ -f $dir/source.ply ]] || "$synth" "$dir" --scene street --seed 3 --noise 0.01 --rotation 3 \
    --translation 0.5 --beams "$beams" --steps "$steps" --problems 0 >/dev/null 2>&1
  for k in 5 10 20; do
    # k = 5 and 20 only on the middle size (the cost in k).
    [[ $k != 10 && $size != "64:2048" ]] && continue
    read -r ms rss ns nt it lm rot < <(single "street_${beams}x${steps}_k$k" "$dir/source.ply" \
      "$dir/target.ply" --radius 1 --max-neighbours "$k" --threads 1 \
      --ground-truth "$dir/ground_truth.txt")
    per=$("$py" -c "print(f'{$ms / ($ns * $it) * 1e3:.3f} us')")
    echo "| ${beams}x$steps | $k | $ms | $rss | $ns | $nt | $it | $lm | $per | $rot |" >>"$md"
    printf '%s\t%s\t%s\t%s\t%s\t%s\n' "$k" "$ns" "$nt" "$ms" "$rss" "$it" >>"$out/scaling.tsv"
  done
done
"$py" - "$out/scaling.tsv" "$out/scaling.png" <<'EOF' || echo "perf.sh: no plot (matplotlib?)" >&2
import sys
import matplotlib
matplotlib.use("Agg")
import matplotlib.pyplot as plt
rows = [l.split("\t") for l in open(sys.argv[1]) if l.strip()]
k10 = sorted((int(r[1]), float(r[3]), int(r[4]), int(r[5])) for r in rows if r[0] == "10")
fig, ax = plt.subplots(1, 2, figsize=(9, 3.6))
n = [r[0] for r in k10]
ax[0].loglog(n, [r[1] for r in k10], "o-", label="time (ms)")
ax[0].loglog(n, [r[1] / r[3] for r in k10], "s--", label="time per outer iteration (ms)")
ax[0].set_xlabel("source points"); ax[0].legend(); ax[0].grid(True, which="both", alpha=0.3)
ax[1].loglog(n, [r[2] / 1024 for r in k10], "o-", color="C2")
ax[1].set_xlabel("source points"); ax[1].set_ylabel("peak RSS (MiB)"); ax[1].grid(True, which="both", alpha=0.3)
fig.suptitle("ppcr_cli, synthetic street scans, k = 10, 1 thread")
fig.tight_layout()
fig.savefig(sys.argv[2], dpi=110)
EOF

echo "== microbenchmarks" >&2
"$micro" --benchmark_min_time=0.2 >"$out/microbench.txt" 2>&1
{
  echo
  echo "## Microbenchmarks (ppcr_microbench, Google Benchmark)"
  echo
  echo '```'
  grep -E "^(Benchmark|BM_|-)" "$out/microbench.txt"
  echo '```'
  echo
  echo "- load average at the end: $(cut -d' ' -f1-3 /proc/loadavg)"
} >>"$md"
echo "perf.sh: wrote $md" >&2
