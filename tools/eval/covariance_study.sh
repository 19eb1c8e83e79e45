#!/usr/bin/env bash
# covariance_study.sh OUT_DIR [BENCH_BINARY] [SYNTH_BINARY] - the covariance's calibration study
# (docs/COVARIANCE.md).
#
# 1. Independent scan pairs: make_wide_set.sh with SEEDS (default 40) seeds x 1 problem for each
#    of its 9 groups (3 scenes x 3 noise models: 360 problems, each its own scene, poses, noise
#    and start), run by run_wide.sh with the protocol's options (tools/eval/protocol.txt), with
#    the shared bunny and lidar sets.
# 2. Repeated noise draws: one pair per scene (the first seed of room_gauss, street_gauss and
#    objects_gauss), scanned again DRAWS times (default 20) with ppcr_synth --noise-draw 1..DRAWS.
# Then covariance_report.py prints the NEES per group and half (odd seeds "select", where the
# estimator's constants were chosen; even seeds "report") and the draws' spread against the
# reported covariance. Binaries default to build/eval-helper/tools/{bench,synth}/. Deterministic
# but for the times; 3 minutes on one core.
set -euo pipefail
out=${1:?usage: covariance_study.sh OUT_DIR [BENCH_BINARY] [SYNTH_BINARY]}
here=$(cd "$(dirname "$0")" && pwd)
bench=${2:-$here/../../build/eval-helper/tools/bench/ppcr_bench}
synth=${3:-$here/../../build/eval-helper/tools/synth/ppcr_synth}
draws=${DRAWS:-20}
[ -x "$bench" ] || { echo "covariance_study.sh: no ppcr_bench at $bench" >&2; exit 2; }
[ -x "$synth" ] || { echo "covariance_study.sh: no ppcr_synth at $synth" >&2; exit 2; }

SEEDS=${SEEDS:-40} PROBLEMS=1 "$here/make_wide_set.sh" "$out/pairs" "$synth"
WIDE_SET="$out/pairs" "$here/run_wide.sh" "$bench" "$out" independent

# The first seed of each group (make_wide_set.sh: group g uses seeds 100 g + 1 ...) and its
# ppcr_synth options, read back from the pair's own log line is not possible: repeated here.
declare -A pair_options=(
  [room_gauss]="--scene room --noise 0.01 --translation 1.5 --max-problem-translation 0.5 --seed 1"
  [street_gauss]="--scene street --noise 0.02 --translation 4 --max-problem-translation 2 --seed 301"
  [objects_gauss]="--scene objects --sensor camera --noise 0.002 --translation 0.3 --max-problem-translation 0.06 --seed 601"
)
mkdir -p "$out/draws"
for group in room_gauss street_gauss objects_gauss; do
  scene=${group%%_*}
  options=$(grep -E "^$scene " "$here/protocol.txt" | cut -d' ' -f2-)
  for ((d = 1; d <= draws; ++d)); do
    dir="$out/draws/$group/draw$d"
    mkdir -p "$out/draws/$group"
    # shellcheck disable=SC2086  # the options are words
    "$synth" "$dir" ${pair_options[$group]} --rotation 15 --problems 1 \
      --min-problem-rotation 0 --max-problem-rotation 30 --noise-draw "$d" > "$dir.log" 2>&1 ||
      { cat "$dir.log" >&2; exit 1; }
    # shellcheck disable=SC2086
    "$bench" "$dir/problems.txt" $options --threads 1 --quiet --label draws \
      --out "$out/draws/${group}__draw$d.csv" > "$dir.bench.log" 2>&1 ||
      { cat "$dir.bench.log" >&2; exit 1; }
  done
done
python3 "$here/covariance_report.py" "$out/independent" --draws "$out/draws"
