#!/usr/bin/env bash
# bench_sequences.sh - the "Sequences" table of docs/BENCHMARK.md: a room and a street sequence
# from ppcr_synth --sequence, registered by ppcr and by every peer ppcr_odometry offers, scan to
# scan (--local-map 1) and onto a local map of the last 5 scans, each trajectory scored against
# the exact ground truth (ATE RMSE after rigid alignment, RPE per metre for steps of one scan).
# One method at a time, under nice (the machine is shared).
#
#   tools/odometry/bench_sequences.sh BUILD_DIR OUT_DIR [SCANS]
#
# BUILD_DIR: a build with PPCR_BUILD_TOOLS=ON (and PPCR_BUILD_PEERS=ON for the peers).
# Prints one markdown row per (scene, method, settings) on stdout; the trajectories, per-pair
# CSVs and logs stay in OUT_DIR.
set -euo pipefail
build=${1:?usage: bench_sequences.sh BUILD_DIR OUT_DIR [SCANS]}
out=${2:?usage: bench_sequences.sh BUILD_DIR OUT_DIR [SCANS]}
scans=${3:-200}
synth=$build/tools/synth/ppcr_synth
odometry=$build/tools/odometry/ppcr_odometry
mkdir -p "$out"

# The settings every method shares per scene (as the bench's protocol: a radius covering the
# guess's error, the same voxel-filtered clouds, and for a local map the same leaf); ppcr also
# runs with its defaults alone.
declare -A shared=(
  [room]="--radius 0.25 --source-voxel 0.05 --target-voxel 0.05"
  [street]="--radius 1.0 --source-voxel 0.1 --target-voxel 0.1"
)
declare -A map=([room]="--local-map 5 --map-voxel 0.05" [street]="--local-map 5 --map-voxel 0.1")
declare -A noise=([room]=0.01 [street]=0.02)

methods=$("$odometry" --help | sed -n 's/.*--method TEXT:{\(.*\)}.*/\1/p' | tr ',' ' ')
echo "| scene | method | settings | ATE RMSE (m) | RPE (% of distance) | RPE (deg/m) | scans/s |"
echo "|---|---|---|---:|---:|---:|---:|"
for scene in room street; do
  dir=$out/$scene
  [ -f "$dir/ground_truth_kitti.txt" ] ||
    nice "$synth" "$dir" --sequence "$scans" --scene "$scene" --noise "${noise[$scene]}" \
      --seed 1 > /dev/null
  # ppcr also with a smaller in-plane weight of its plane error (an expert setting, not the
  # default: docs/BENCHMARK.md says why).
  eps="--plane-epsilon 0.005"
  runs=("ppcr|defaults (local map 5)|" "ppcr|defaults, --local-map 1|--local-map 1")
  sm=${shared[$scene]} lm=${map[$scene]}
  runs+=("ppcr|shared, local map|$sm $lm" "ppcr|shared, scan to scan|$sm --local-map 1"
    "ppcr|shared, local map, $eps|$sm $lm $eps"
    "ppcr|shared, scan to scan, $eps|$sm --local-map 1 $eps")
  for method in $methods; do  # the peers
    if [ "$method" != ppcr ]; then
      runs+=("$method|shared, scan to scan|$sm --local-map 1" "$method|shared, local map|$sm $lm")
    fi
  done
  for run in "${runs[@]}"; do
    IFS='|' read -r method label flags <<< "$run"
    name=$dir/$method-${label//[^a-z0-9.]/_}
    # shellcheck disable=SC2086  # flags is a list of words
    nice "$odometry" "$dir/scans" --method "$method" $flags --kitti "$name.kitti" \
      --pairs "$name.csv" 2> "$name.log" || echo "($method failed: see $name.log)" >&2
    read -r _ _ _ ate _ rpe _ rot _ < <("$odometry" --evaluate "$dir/ground_truth_kitti.txt" \
      "$name.kitti")
    rate=$(sed -n 's/.*: \([0-9.]*\) scans\/s.*/\1/p' "$name.log" | tail -1)
    echo "| $scene | $method | $label | $ate | $rpe | $rot | $rate |"
  done
done
