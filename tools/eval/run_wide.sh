#!/usr/bin/env bash
# run_wide.sh BENCH_BINARY OUT_DIR LABEL [-- ppcr_bench flags...] - one setting on the wide set.
#
# Runs BENCH_BINARY (ppcr_bench) with --threads 1 on the shared sets
# (../shared/data/benchmark/{bunny,lidar}_local.txt, or $SHARED_BENCHMARK_DIR) and on every
# problem file of the wide set (OUT_DIR/wide_set/manifest.txt, made by make_wide_set.sh; or
# $WIDE_SET), each with its group's options from tools/eval/protocol.txt followed by the flags
# after --, one process at a time. Writes one CSV per problem file (ppcr_bench --out: one row per
# problem) as OUT_DIR/LABEL/<group>__<seed>.csv (bunny.csv, lidar.csv for the shared sets), the
# flags in OUT_DIR/LABEL/flags.txt and the CPU time in OUT_DIR/LABEL/time.txt.
# Summarise with: tools/eval/summarise.py OUT_DIR/LABEL [more runs...]
set -euo pipefail
bench=${1:?usage: run_wide.sh BENCH_BINARY OUT_DIR LABEL [-- flags...]}
out=${2:?usage: run_wide.sh BENCH_BINARY OUT_DIR LABEL [-- flags...]}
label=${3:?usage: run_wide.sh BENCH_BINARY OUT_DIR LABEL [-- flags...]}
shift 3
[ "${1:-}" = "--" ] && shift
flags=("$@")
here=$(cd "$(dirname "$0")" && pwd)
root=$(cd "$here/../.." && pwd)
shared=${SHARED_BENCHMARK_DIR:-$root/../shared/data/benchmark}
wide=${WIDE_SET:-$out/wide_set}
[ -x "$bench" ] || { echo "run_wide.sh: no ppcr_bench at $bench" >&2; exit 2; }
[ -f "$wide/manifest.txt" ] || { echo "run_wide.sh: no $wide/manifest.txt (make_wide_set.sh)" >&2; exit 2; }

protocol() {  # options of a group: its own line, else its scene's (room_gauss -> room)
  local line
  line=$(grep -E "^$1 " "$here/protocol.txt" || grep -E "^${1%%_*} " "$here/protocol.txt") ||
    { echo "run_wide.sh: no protocol line for $1" >&2; exit 2; }
  echo "${line#* }"
}
for set in bunny lidar; do  # the shared sets keep tools/bench/protocol.txt's options
  [ "$(protocol $set)" = "$(grep -E "^$set " "$root/tools/bench/protocol.txt" | cut -d' ' -f2-)" ] ||
    { echo "run_wide.sh: $set differs from tools/bench/protocol.txt" >&2; exit 2; }
done

dir="$out/$label"
mkdir -p "$dir"
printf '%s\n' "${flags[*]:-}" > "$dir/flags.txt"
run() {  # run GROUP NAME PROBLEMS
  # shellcheck disable=SC2046  # the protocol's options are words
  "$bench" "$3" $(protocol "$1") "${flags[@]}" --threads 1 --quiet --label "$label" \
    --out "$dir/$2.csv" > "$dir/$2.log" 2>&1 || { cat "$dir/$2.log" >&2; exit 1; }
}
start=$(date +%s)
times_before=$(awk '{print $14 + $15 + $16 + $17}' /proc/$$/stat)
run bunny bunny "$shared/bunny_local.txt"
run lidar lidar "$shared/lidar_local.txt"
while read -r group problems; do
  run "$group" "${group}__$(basename "$(dirname "$problems")")" "$problems"
done < "$wide/manifest.txt"
ticks=$(getconf CLK_TCK)
cpu=$(awk -v t="$ticks" -v b="$times_before" '{printf "%.1f", ($14 + $15 + $16 + $17 - b) / t}' /proc/$$/stat)
echo "wall $(( $(date +%s) - start )) s, cpu $cpu s" | tee "$dir/time.txt"
