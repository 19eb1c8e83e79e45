#!/usr/bin/env bash
# The main job, from a fresh Debian 12 machine, with no download: installs what is missing (only
# what the demo uses: tools/install_deps.sh demo), builds ppcr (Release), renders a synthetic room
# scanned from two poses (exact ground truth), registers the pair with ppcr_cli and again from
# Python (where python/cmake_flags.sh finds pybind11, Python's headers and numpy), and prints the
# recovered transform and its errors.
# With ../shared/data present it also registers the real bunny pair (the paper's 45-degree case).
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
cd "$root"
"$root/tools/install_deps.sh" demo
python_flags=$("$root/python/cmake_flags.sh")
# shellcheck disable=SC2086
cmake -S . -B build/release -DCMAKE_BUILD_TYPE=Release -DPPCR_BUILD_TESTS=OFF $python_flags \
  > /dev/null
targets=(ppcr_cli ppcr_synth ppcr_odometry)
[[ -n $python_flags ]] && targets+=(ppcr_python)
cmake --build build/release -j "${PPCR_JOBS:-2}" --target "${targets[@]}"
bin=build/release/tools
out=build/demo
mkdir -p "$out"
echo "== a synthetic room scanned from two poses (ppcr_synth), ground truth known exactly"
"$bin/synth/ppcr_synth" "$out" --scene room --seed 7 --noise 0.005 --rotation 15 --translation 0.5
echo "== ppcr_cli $out/source.ply $out/target.ply --radius 0.5 --source-voxel 0.05 --target-voxel 0.05"
"$bin/ppcr_cli" "$out/source.ply" "$out/target.ply" --radius 0.5 --source-voxel 0.05 \
  --target-voxel 0.05 --ground-truth "$out/ground_truth.txt"
if [[ -n $python_flags ]]; then
  python=${python_flags##*Python_EXECUTABLE=}
  echo "== the same pair from Python: PYTHONPATH=build/release/python $python"
  PYTHONPATH=build/release/python "$python" - "$out" <<'PY'
import sys
import numpy as np
import ppcr

folder = sys.argv[1]
source = ppcr.read_point_cloud(f"{folder}/source.ply")  # (N, 3) float64 arrays
target = ppcr.read_point_cloud(f"{folder}/target.ply")
r = ppcr.register(source, target, radius=0.5, source_voxel=0.05, target_voxel=0.05)
print(r)
print(np.array2string(r.transformation, precision=6, suppress_small=True))
truth = np.loadtxt(f"{folder}/ground_truth.txt")
R = truth[:3, :3].T @ r.transformation[:3, :3]
angle = np.degrees(np.arccos(np.clip((np.trace(R) - 1) / 2, -1, 1)))
print(f"rotation error {angle:.4f} deg, translation error "
      f"{np.linalg.norm(truth[:3, 3] - r.transformation[:3, 3]):.6g}")
PY
fi
data=${PPCR_DATA_DIR:-$root/../shared/data}
if [[ -f $data/bunny/bun045.ply ]]; then
  echo "== the real bunny pair, 45 degrees apart, from identity"
  "$bin/ppcr_cli" "$data/bunny/bun045.ply" "$data/bunny/bun000.ply" --radius 0.02 \
    --source-voxel 0.002 --target-voxel 0.002 --ground-truth "$data/bunny/bun045_gt.txt"
fi
