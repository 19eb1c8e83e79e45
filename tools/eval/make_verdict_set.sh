#!/usr/bin/env bash
# make_verdict_set.sh OUT_DIR [SYNTH_BINARY] - the problems the verdict's rules were chosen and
# checked on (docs/BENCHMARK.md, "The verdict"): starts 30 to 90 degrees off, so that a good
# share of the registrations fail.
#   OUT_DIR/wide_set: make_wide_set.sh's 9 synthetic groups, 4 seeds x 6 problems (216)
#   OUT_DIR/shared:   the shared bunny and lidar pairs, 40 problems each (links to the scans in
#                     ../shared/data/benchmark, never copies)
# Then: SHARED_BENCHMARK_DIR=OUT_DIR/shared tools/eval/run_wide.sh BENCH OUT_DIR LABEL
#       tools/eval/verdict_report.py OUT_DIR/LABEL
set -euo pipefail
out=${1:?usage: make_verdict_set.sh OUT_DIR [SYNTH_BINARY]}
here=$(cd "$(dirname "$0")" && pwd)
root=$(cd "$here/../.." && pwd)
benchmark=${SHARED_BENCHMARK_DIR:-$root/../shared/data/benchmark}
[ -d "$benchmark" ] || { echo "make_verdict_set.sh: no $benchmark" >&2; exit 2; }
SEEDS=4 PROBLEMS=6 MIN_ROTATION=30 MAX_ROTATION=90 "$here/make_wide_set.sh" "$out/wide_set" "${2:-}"
mkdir -p "$out/shared"
for set in bunny lidar; do ln -sfn "$(cd "$benchmark/$set" && pwd)" "$out/shared/$set"; done
"$root/tools/bench/make_problems.py" "$benchmark" bunny/bun045.ply bunny/bun000.ply \
  --min-rotation 30 --max-rotation 90 --max-translation 0.02 --count 40 --seed 31 \
  --first-id 7000 --overlap 0.9293 > "$out/shared/bunny_local.txt"
"$root/tools/bench/make_problems.py" "$benchmark" lidar/source.ply lidar/target.ply \
  --min-rotation 30 --max-rotation 90 --max-translation 1 --count 40 --seed 32 \
  --first-id 8000 --overlap 0.8708 > "$out/shared/lidar_local.txt"
echo "make_verdict_set.sh: 216 synthetic and 80 shared-scan problems in $out"
