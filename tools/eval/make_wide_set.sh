#!/usr/bin/env bash
# make_wide_set.sh OUT_DIR [SYNTH_BINARY] - the wide evaluation's synthetic problems.
#
# Writes OUT_DIR/<scene>_<noise>/seed<N>/{source,target,source_gt_frame}.ply, ground_truth.txt
# and problems.txt (ppcr_synth's files: benchmark-format problems with exact ground truth), for
# 3 scenes x 3 noise models x SEEDS seeds x PROBLEMS problems (default 8 x 6: 432 problems), and
# OUT_DIR/manifest.txt: one line "<group> <problems.txt path>" per scan pair.
#   scenes: room (indoor), street (outdoor), objects (tabletop, depth camera)
#   noise:  gauss (constant Gaussian range noise), range (sigma = a * range),
#           depthcam (a depth camera's limited field of view and disparity quantisation:
#           depth steps q z^2)
# Group g (0..8, in the order below) uses seeds 100 g + 1 .. 100 g + SEEDS: ppcr_synth draws the
# layout, the sensor poses and the problems' starts from the seed alone, so distinct seeds give
# every problem its own scene and start.
# Starts: rotation uniform in [MIN_ROTATION, MAX_ROTATION] degrees (default [0, 30]) about a
# random axis through the source centroid, translation uniform in [0, 2 x the group's radius]
# (tools/eval/protocol.txt). The verdict's evaluation uses MIN_ROTATION=30 MAX_ROTATION=90.
# SYNTH_BINARY defaults to build/eval-helper/tools/synth/ppcr_synth. Deterministic.
set -euo pipefail
out=${1:?usage: make_wide_set.sh OUT_DIR [SYNTH_BINARY]}
here=$(cd "$(dirname "$0")" && pwd)
synth=${2:-$here/../../build/eval-helper/tools/synth/ppcr_synth}
seeds=${SEEDS:-8}
problems=${PROBLEMS:-6}
min_rotation=${MIN_ROTATION:-0}
max_rotation=${MAX_ROTATION:-30}
[ -x "$synth" ] || { echo "make_wide_set.sh: no ppcr_synth at $synth" >&2; exit 2; }
mkdir -p "$out"
: > "$out/manifest.txt"

camera=(--sensor camera)
# group -> ppcr_synth options (scene, sensor, noise, sensor motion, start translation)
declare -A group_options=(
  [room_gauss]="--scene room --noise 0.01 --translation 1.5 --max-problem-translation 0.5"
  [room_range]="--scene room --noise-per-metre 0.003 --translation 1.5 --max-problem-translation 0.5"
  [room_depthcam]="--scene room ${camera[*]} --max-range 8 --depth-quantisation 0.003 --translation 0.5 --max-problem-translation 0.5"
  [street_gauss]="--scene street --noise 0.02 --translation 4 --max-problem-translation 2"
  [street_range]="--scene street --noise-per-metre 0.002 --translation 4 --max-problem-translation 2"
  [street_depthcam]="--scene street ${camera[*]} --hfov 90 --fov-up 25 --fov-down -25 --steps 320 --beams 160 --max-range 40 --depth-quantisation 0.0005 --translation 3 --max-problem-translation 2"
  [objects_gauss]="--scene objects ${camera[*]} --noise 0.002 --translation 0.3 --max-problem-translation 0.06"
  [objects_range]="--scene objects ${camera[*]} --noise-per-metre 0.004 --translation 0.3 --max-problem-translation 0.06"
  [objects_depthcam]="--scene objects ${camera[*]} --depth-quantisation 0.003 --translation 0.3 --max-problem-translation 0.06"
)
g=0
for group in room_gauss room_range room_depthcam street_gauss street_range street_depthcam \
             objects_gauss objects_range objects_depthcam; do
  for ((seed = 100 * g + 1; seed <= 100 * g + seeds; ++seed)); do
    dir="$out/$group/seed$seed"
    mkdir -p "$out/$group"
    # shellcheck disable=SC2086  # the options are words
    "$synth" "$dir" ${group_options[$group]} --seed "$seed" --rotation 15 \
      --problems "$problems" \
      --min-problem-rotation "$min_rotation" --max-problem-rotation "$max_rotation" > "$dir.log" 2>&1 ||
      { cat "$dir.log" >&2; exit 1; }
    echo "$group $dir/problems.txt" >> "$out/manifest.txt"
  done
  g=$((g + 1))
done
echo "make_wide_set.sh: $(wc -l < "$out/manifest.txt") scan pairs, $((seeds * problems * 9)) problems in $out"
