#!/usr/bin/env python3
"""How well ppcr's verdict separates right from wrong results, on the two halves of a run.

  tools/eval/verdict_report.py RUN_DIR

RUN_DIR holds ppcr_bench --out CSVs (run_wide.sh's output). A problem is wrong when the bench's
success rule failed (column `success`), flagged when its `quality` is weak or failed. The rules'
thresholds were chosen on the choice half (the even rows of each CSV) and are reported on the
held-out half (the odd rows). Standard library only.
"""
import collections
import csv
import glob
import os
import sys


def load(run_dir):
    rows = []
    for path in sorted(glob.glob(os.path.join(run_dir, "*.csv"))):
        group = os.path.basename(path)[:-4].split("__")[0]
        with open(path, newline="") as f:
            for i, row in enumerate(csv.DictReader(f)):
                row["group"], row["half"] = group, i % 2
                rows.append(row)
    return rows


def report(rows, name):
    right = [r for r in rows if r["success"] == "1"]
    wrong = [r for r in rows if r["success"] == "0"]
    caught = sum(r["quality"] != "good" for r in wrong)
    flagged = sum(r["quality"] != "good" for r in right)
    converged = sum(r["converged"] == "1" for r in wrong)
    pct = lambda a, b: 100.0 * a / b if b else float("nan")
    print(f"| {name} | {len(rows)} | {len(wrong)} ({converged} converged) | {caught} "
          f"({pct(caught, len(wrong)):.1f} %) | {len(right)} | {flagged} "
          f"({pct(flagged, len(right)):.1f} %) |")


def main():
    if len(sys.argv) != 2:
        sys.exit(__doc__)
    rows = load(sys.argv[1])
    if not rows:
        sys.exit(f"verdict_report.py: no CSV in {sys.argv[1]}")
    print("| half | problems | wrong | wrong flagged | right | right flagged |")
    print("| ---- | -------: | ----: | ------------: | ----: | ------------: |")
    report([r for r in rows if r["half"] == 0], "choice (even rows)")
    report([r for r in rows if r["half"] == 1], "held out (odd rows)")
    report(rows, "all")
    print()
    counts = collections.Counter(
        ("right" if r["success"] == "1" else "wrong", r["quality"]) for r in rows)
    print("verdicts: " + ", ".join(f"{k[0]} {k[1]} {v}" for k, v in sorted(counts.items())))
    time_ms = sum(float(r["time_ms"]) for r in rows)
    quality_ms = sum(float(r["quality_ms"]) for r in rows)
    worst = max(float(r["quality_ms"]) / float(r["time_ms"]) for r in rows)
    print(f"quality_ms / time_ms: {100 * quality_ms / time_ms:.1f} % in all, "
          f"{100 * worst:.1f} % at most")


if __name__ == "__main__":
    main()
