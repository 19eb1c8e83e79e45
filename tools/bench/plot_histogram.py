#!/usr/bin/python3
"""Histogram of the benchmark error per method, one panel per set (like the paper's Figure 7).

Reads the per-problem CSVs that tools/bench/run_all.sh writes (<set>_<method>.csv, column
`error`) and writes a PNG. Needs matplotlib (Debian: python3-matplotlib).

  tools/bench/plot_histogram.py build/bench-results               -> .../error_histogram.png
  tools/bench/plot_histogram.py RESULTS -o fig.png --methods ppcr,pcl-gicp,o3d-gicp
"""
import argparse
import csv
import math
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def read_errors(path):
    with open(path, newline="") as f:
        return [float(row["error"]) for row in csv.DictReader(f)]


def find_runs(folder):
    """{set: {method: path}} for every <set>_<method>.csv in folder."""
    runs = {}
    for name in sorted(os.listdir(folder)):
        if not name.endswith(".csv") or "_" not in name:
            continue
        stem = name[: -len(".csv")]
        set_name, method = stem.split("_", 1)
        runs.setdefault(set_name, {})[method] = os.path.join(folder, name)
    return runs


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("results", help="folder with <set>_<method>.csv files")
    parser.add_argument("-o", "--output", help="PNG path (default RESULTS/error_histogram.png)")
    parser.add_argument("--methods", help="comma-separated methods to plot, in order (default all)")
    parser.add_argument("--sets", help="comma-separated sets, in order (default all found)")
    parser.add_argument("--bins", type=int, default=30, help="log-spaced bins per panel")
    args = parser.parse_args()

    runs = find_runs(args.results)
    if not runs:
        sys.exit(f"plot_histogram.py: no <set>_<method>.csv in {args.results}")
    sets = args.sets.split(",") if args.sets else sorted(runs)
    missing = [s for s in sets if s not in runs]
    if missing:
        sys.exit(f"plot_histogram.py: no CSV for set(s) {', '.join(missing)}")

    fig, axes = plt.subplots(1, len(sets), figsize=(6.5 * len(sets), 4.5), squeeze=False)
    for ax, set_name in zip(axes[0], sets):
        methods = (args.methods.split(",") if args.methods else
                   sorted(runs[set_name], key=lambda m: (not m.startswith("ppcr"), m)))
        errors = {m: read_errors(runs[set_name][m]) for m in methods if m in runs[set_name]}
        positive = [e for es in errors.values() for e in es if e > 0 and math.isfinite(e)]
        if not positive:
            ax.set_title(f"{set_name}: no errors to plot")
            continue
        lo, hi = math.log10(min(positive)), math.log10(max(positive))
        if hi - lo < 1e-9:
            lo, hi = lo - 0.5, hi + 0.5
        bins = [10 ** (lo + (hi - lo) * i / args.bins) for i in range(args.bins + 1)]
        for method, es in errors.items():
            # Clamp zero / non-finite errors into the outermost bins so every problem counts.
            shown = [min(max(e, bins[0]), bins[-1]) if math.isfinite(e) else bins[-1] for e in es]
            ax.hist(shown, bins=bins, histtype="step", linewidth=1.6, label=f"{method} ({len(es)})")
        ax.set_xscale("log")
        ax.set_xlabel("benchmark error e (mean relative point displacement)")
        ax.set_ylabel("problems")
        ax.set_title(set_name)
        ax.grid(True, which="major", alpha=0.3)
        ax.legend(fontsize="small")
    fig.tight_layout()
    output = args.output or os.path.join(args.results, "error_histogram.png")
    fig.savefig(output, dpi=120)
    print(output)


if __name__ == "__main__":
    main()
