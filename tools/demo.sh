#!/usr/bin/env bash
# The main job, from a fresh Debian 12 machine, with no download: installs what is missing,
# builds ppcr (Release), renders a synthetic room scanned from two poses (exact ground truth),
# registers the pair with ppcr_cli and prints the recovered transform and its errors.
# With ../shared/data present it also registers the real bunny pair (the paper's 45-degree case).
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
cd "$root"
"$root/tools/install_deps.sh"
cmake -S . -B build/release -DCMAKE_BUILD_TYPE=Release -DPPCR_BUILD_TESTS=OFF > /dev/null
cmake --build build/release -j "${PPCR_JOBS:-2}" --target ppcr_cli ppcr_synth
bin=build/release/tools
out=build/demo
mkdir -p "$out"
echo "== a synthetic room scanned from two poses (ppcr_synth), ground truth known exactly"
"$bin/synth/ppcr_synth" "$out" --scene room --seed 7 --noise 0.005 --rotation 15 --translation 0.5
echo "== ppcr_cli $out/source.ply $out/target.ply --radius 0.5 --source-voxel 0.05 --target-voxel 0.05"
"$bin/ppcr_cli" "$out/source.ply" "$out/target.ply" --radius 0.5 --source-voxel 0.05 \
  --target-voxel 0.05 --ground-truth "$out/ground_truth.txt"
data=${PPCR_DATA_DIR:-$root/../shared/data}
if [[ -f $data/bunny/bun045.ply ]]; then
  echo "== the real bunny pair, 45 degrees apart, from identity"
  "$bin/ppcr_cli" "$data/bunny/bun045.ply" "$data/bunny/bun000.ply" --radius 0.02 \
    --source-voxel 0.002 --target-voxel 0.002 --ground-truth "$data/bunny/bun045_gt.txt"
fi
