#!/usr/bin/env python3
"""covariance_report.py RUN_DIR [--draws DRAWS_DIR] - the covariance's calibration table.

RUN_DIR is OUT_DIR/LABEL written by run_wide.sh (one ppcr_bench CSV per problem file, with the
columns nees, error_twist and covariance: RegistrationResult::covariance against the exact
truth). Over the successful problems of each group (rotation error < 1 degree, translation
error < the group's bound), per half of the seeds: "select" (odd seeds, where the estimator's
constants were chosen) and "report" (even seeds), and for the shared sets (bunny, lidar):
  n        successful problems
  nees     mean NEES = e^T C^-1 e, e = log(T_est T_true^-1) (6 for a calibrated C)
  under    share with NEES under the chi-square(6) 95 % bound, 12.592 (95 % if calibrated)
  med      median NEES (5.35 for chi-square(6))
With --draws DRAWS_DIR (ppcr_bench CSVs named <group>__draw<N>.csv: one scan pair per group,
its noise drawn again), per group: the empirical covariance of the error twists against the
mean reported covariance, as the ratio of their traces, rotation and translation blocks apart.
Python 3 standard library only.
"""
import csv
import math
import os
import sys

CHI2_6_95 = 12.591587243743977
SCENES = ["room", "street", "objects"]


def rows(path):
    with open(path) as f:
        return list(csv.DictReader(f))


def seed_of(name):
    """'room_gauss__seed12.csv' -> 12; None for the shared sets."""
    stem = name[:-4]
    if "__seed" not in stem:
        return None
    return int(stem.split("__seed")[1])


def stats(values):
    if not values:
        return "n 0"
    v = sorted(values)
    mid = len(v) // 2
    med = v[mid] if len(v) % 2 else 0.5 * (v[mid - 1] + v[mid])
    under = sum(x < CHI2_6_95 for x in v) / len(v)
    return "n %3d  nees %6.2f  under %5.1f %%  med %5.2f" % (
        len(v), sum(v) / len(v), 100 * under, med)


def calibration(run_dir):
    groups = {}  # (group, half) -> NEES values
    for name in sorted(os.listdir(run_dir)):
        if not name.endswith(".csv"):
            continue
        seed = seed_of(name)
        group = name[:-4].split("__")[0]
        half = "shared" if seed is None else ("select" if seed % 2 else "report")
        for r in rows(os.path.join(run_dir, name)):
            if r["success"] != "1" or r["nees"] in ("", "nan"):
                continue
            for key in ((group, half), (group.split("_")[0] + "_*", half), ("all", half)):
                groups.setdefault(key, []).append(float(r["nees"]))
    for half in ("select", "report", "shared"):
        keys = sorted(k for k in groups if k[1] == half)
        if not keys:
            continue
        print("## %s" % half)
        for key in keys:
            print("%-18s %s" % (key[0], stats(groups[key])))


def covariance_of(text):
    v = [float(x) for x in text.split()]
    return [v[6 * c:6 * c + 6] for c in range(6)]


def draws(draws_dir):
    per_group = {}
    for name in sorted(os.listdir(draws_dir)):
        if name.endswith(".csv") and "__draw" in name:
            for r in rows(os.path.join(draws_dir, name)):
                if r["success"] == "1":
                    per_group.setdefault(name.split("__")[0], []).append(r)
    print("## repeated noise draws: trace(empirical) / mean trace(reported)")
    for group, rs in sorted(per_group.items()):
        errors = [[float(x) for x in r["error_twist"].split()] for r in rs]
        n = len(errors)
        if n < 2:
            print("%-18s n %3d  (too few successful draws for a spread)" % (group, n))
            continue
        mean = [sum(e[i] for e in errors) / n for i in range(6)]
        empirical = [sum((e[i] - mean[i]) ** 2 for e in errors) / (n - 1) for i in range(6)]
        reported = [0.0] * 6
        for r in rs:
            c = covariance_of(r["covariance"])
            for i in range(6):
                reported[i] += c[i][i] / n
        rot = sum(empirical[:3]) / sum(reported[:3])
        tra = sum(empirical[3:]) / sum(reported[3:])
        whole = sum(empirical) / sum(reported)
        print("%-18s n %3d  rotation %5.2f  translation %5.2f  whole %5.2f  "
              "(reported sqrt(trace) %.3g deg, %.3g)" % (
                  group, n, rot, tra, whole, math.degrees(math.sqrt(sum(reported[:3]))),
                  math.sqrt(sum(reported[3:]))))


def main(argv):
    if len(argv) < 2 or argv[1].startswith("-"):
        sys.exit(__doc__)
    calibration(argv[1])
    if "--draws" in argv:
        draws(argv[argv.index("--draws") + 1])


if __name__ == "__main__":
    main(sys.argv)
