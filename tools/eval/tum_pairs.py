#!/usr/bin/env python3
"""tum_pairs.py PPCR_CLI [ppcr_cli flags...] - ppcr_cli on real depth-frame pairs with truth.

The 19 pairs five frames apart of ../shared/data/tum_fr1_rpy (frame k+5 onto frame k, k = 0, 5,
..., 90; $PPCR_DATA_DIR/tum_fr1_rpy if set), each from identity with the Freiburg 1 intrinsics
and the given flags, scored against TUM's ground truth interpolated at the frames' times (linear
in position, slerp in rotation). Right: within 5 degrees and 5 cm (the truth is
good to a few tenths of a degree per frame there: the folder's README). Prints a row per pair
(k, rotation error in degrees, translation error in metres, verdict, ms) and the summary line:
pairs right, median time, wrong pairs the verdict called good.
Example: tools/eval/tum_pairs.py build/tools/ppcr_cli --voxel auto
"""
import json
import os
import pathlib
import subprocess
import sys
import tempfile

import numpy as np

FREIBURG1 = ["517.3", "516.5", "318.6", "255.3"]


def quaternion_matrix(q):
    x, y, z, w = q / np.linalg.norm(q)
    return np.array([[1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)],
                     [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)],
                     [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)]])


def pose_at(truth, t):
    """Camera-to-world pose at time t: TUM's poses (t x y z qx qy qz qw) interpolated."""
    i = int(np.searchsorted(truth[:, 0], t))
    if i == 0 or i == len(truth):
        sys.exit(f"tum_pairs: time {t} is outside the ground truth's span")
    a, b = truth[i - 1], truth[i]
    s = (t - a[0]) / (b[0] - a[0])
    qa, qb = a[4:8], b[4:8]
    if np.dot(qa, qb) < 0:
        qb = -qb
    angle = np.arccos(np.clip(np.dot(qa, qb) / (np.linalg.norm(qa) * np.linalg.norm(qb)), -1, 1))
    q = qa if angle < 1e-12 else (np.sin((1 - s) * angle) * qa + np.sin(s * angle) * qb) / np.sin(angle)
    T = np.eye(4)
    T[:3, :3] = quaternion_matrix(q)
    T[:3, 3] = (1 - s) * a[1:4] + s * b[1:4]
    return T


def main():
    if len(sys.argv) < 2:
        sys.exit(__doc__)
    cli, flags = sys.argv[1], sys.argv[2:]
    data = pathlib.Path(os.environ.get("PPCR_DATA_DIR",
                                       pathlib.Path(__file__).resolve().parents[3] / "shared" / "data"))
    folder = data / "tum_fr1_rpy"
    truth = np.loadtxt(folder / "groundtruth.txt")
    frames = sorted((folder / "depth").glob("*.png"))
    if len(frames) != 100:
        sys.exit(f"tum_pairs: 100 depth frames expected in {folder / 'depth'}, found {len(frames)}")
    rows = []
    with tempfile.TemporaryDirectory() as tmp:
        gt_path = pathlib.Path(tmp) / "gt.txt"
        for k in range(0, 95, 5):
            source, target = frames[k + 5], frames[k]
            T = np.linalg.inv(pose_at(truth, float(target.stem))) @ pose_at(truth, float(source.stem))
            np.savetxt(gt_path, T)
            out = subprocess.run([cli, str(source), str(target), "--depth-intrinsics", *FREIBURG1,
                                  "--ground-truth", str(gt_path), "--json", "--quiet", *flags],
                                 capture_output=True, text=True, check=False)
            if out.returncode not in (0, 3):
                sys.exit(f"tum_pairs: ppcr_cli failed on pair {k}: {out.stderr.strip()}")
            j = json.loads(out.stdout)
            right = j["rotation_error_deg"] < 5 and j["translation_error"] < 0.05
            rows.append((k, j["rotation_error_deg"], j["translation_error"], j["quality"],
                         j["time_ms"], right))
    for k, rot, trans, quality, ms, right in rows:
        print(f"{k:2d} {rot:7.2f} {trans:7.3f} {quality:6s} {ms:8.0f} {'right' if right else 'wrong'}")
    wrong_good = sum(1 for r in rows if not r[5] and r[3] == "good")
    print(f"right {sum(r[5] for r in rows)} of {len(rows)}, median {np.median([r[4] for r in rows]):.0f} ms, "
          f"wrong called good {wrong_good}")


if __name__ == "__main__":
    main()
