#!/usr/bin/env python3
"""summarise.py RUN_DIR [RUN_DIR...] [--out PREFIX] - the wide evaluation's table.

Each RUN_DIR is OUT_DIR/LABEL written by run_wide.sh (one ppcr_bench CSV per problem file:
bunny.csv, lidar.csv, <group>__<seed>.csv). Per group (bunny, lidar, each synthetic
<scene>_<noise>), per scene (room, street, objects: all noise models), "wide" (every synthetic
problem) and "all" (wide + both shared sets), for each run:
  ok          successes: rotation error < 1 degree and translation error < the group's
              --success-translation (tools/eval/protocol.txt), ppcr_bench's rule
  wrongconv   failures whose stop reason is a criterion stop (fixed_iterations, cost_drop,
              mse_prev, successful_steps, zero_cost: the registration reported it converged)
  err_med, err_q95   benchmark error (numpy's linear-interpolation quantiles, as ppcr_bench)
  rot_med, rot_q95   rotation error, degrees
  ms_med      median registration time, ms;  it_mean  mean outer iterations
  lost/won    problems this run fails that the first run solves / solves that the first fails
Prints a plain-text table; with --out PREFIX also writes PREFIX.csv and PREFIX.md. With
--starts WIDE_SET_DIR (make_wide_set.sh's OUT_DIR) it also counts successes and wrong converged
results by the start's rotation angle (0-10, 10-20, 20-30 degrees) over the wide set.
Python 3 standard library only.
"""
import csv
import math
import os
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
CRITERION_STOPS = {"fixed_iterations", "cost_drop", "mse_prev", "successful_steps", "zero_cost"}
SUCCESS_ROTATION_DEG = 1.0
SCENES = ["room", "street", "objects"]
NOISES = ["gauss", "range", "depthcam"]


def protocol():
    """group or scene -> success translation bound."""
    bounds = {}
    with open(os.path.join(HERE, "protocol.txt")) as f:
        for line in f:
            words = line.split()
            if not words or words[0].startswith("#"):
                continue
            bounds[words[0]] = float(words[words.index("--success-translation") + 1])
    return bounds


def quantile(values, q):
    v = sorted(values)
    if not v:
        return float("nan")
    position = q * (len(v) - 1)
    lo = int(position)
    hi = min(lo + 1, len(v) - 1)
    return v[lo] + (position - lo) * (v[hi] - v[lo])


def load(run_dir, bounds):
    """[(key, group, row)] with key = (group, file stem, problem id)."""
    rows = []
    for name in sorted(os.listdir(run_dir)):
        if not name.endswith(".csv"):
            continue
        stem = name[:-4]
        group = stem.split("__")[0]
        bound = bounds.get(group, bounds.get(group.split("_")[0]))
        with open(os.path.join(run_dir, name)) as f:
            for r in csv.DictReader(f):
                rot = float(r["rotation_error_deg"])
                tra = float(r["translation_error"])
                ok = rot < SUCCESS_ROTATION_DEG and tra < bound
                rows.append(((group, stem, r["id"]), group, {
                    "ok": ok,
                    "wrongconv": (not ok) and r["stop_reason"] in CRITERION_STOPS,
                    "error": float(r["error"]),
                    "rot": rot,
                    "ms": float(r["time_ms"]),
                    "it": int(r["iterations"]),
                }))
    return rows


def members(group):
    """The aggregates a group belongs to."""
    out = [group]
    scene = group.split("_")[0]
    if group not in ("bunny", "lidar"):
        out += [scene, "wide"]
    out.append("all")
    return out


def order():
    groups = ["bunny", "lidar"] + [f"{s}_{n}" for s in SCENES for n in NOISES]
    return groups + SCENES + ["wide", "all"]


def start_angles(starts_dir):
    """(group, stem, id) -> start rotation angle, degrees, for the wide set's problems."""
    angles = {}
    for group in os.listdir(starts_dir):
        gdir = os.path.join(starts_dir, group)
        if not os.path.isdir(gdir):
            continue
        for seed in os.listdir(gdir):
            path = os.path.join(gdir, seed, "problems.txt")
            if not os.path.exists(path):
                continue
            with open(path) as f:
                next(f)
                for line in f:
                    w = line.split()
                    t = [float(x) for x in w[4:16]]
                    cosine = max(-1.0, min(1.0, (t[0] + t[5] + t[10] - 1.0) / 2.0))
                    angles[(group, f"{group}__{seed}", w[0])] = math.degrees(math.acos(cosine))
    return angles


def start_table(runs, starts_dir):
    angles = start_angles(starts_dir)
    bins = [(0, 10), (10, 20), (20, 30.001)]
    head = "wide set by start rotation: ok/n (wrong converged)"
    lines = [head, "run " + " ".join(f"{lo:>5.0f}-{min(hi, 30):<2.0f} deg".rjust(16) for lo, hi in bins)]
    for label, _, rows in runs:
        cells = []
        for lo, hi in bins:
            sel = [r for k, _, r in rows if k in angles and lo <= angles[k] < hi]
            cells.append(f"{sum(r['ok'] for r in sel)}/{len(sel)} ({sum(r['wrongconv'] for r in sel)})".rjust(16))
        lines.append(label.ljust(3) + " " + " ".join(cells))
    return lines


def main(argv):
    out_prefix = None
    if "--out" in argv:
        i = argv.index("--out")
        out_prefix = argv[i + 1]
        argv = argv[:i] + argv[i + 2:]
    starts_dir = None
    if "--starts" in argv:
        i = argv.index("--starts")
        starts_dir = argv[i + 1]
        argv = argv[:i] + argv[i + 2:]
    if not argv:
        print(__doc__)
        return 2
    bounds = protocol()
    runs = []
    for run_dir in argv:
        label = os.path.basename(os.path.normpath(run_dir))
        flags = ""
        if os.path.exists(os.path.join(run_dir, "flags.txt")):
            flags = open(os.path.join(run_dir, "flags.txt")).read().strip()
        runs.append((label, flags, load(run_dir, bounds)))
    base_ok = {key: row["ok"] for key, _, row in runs[0][2]}

    table = []
    for label, flags, rows in runs:
        by = {}
        for key, group, row in rows:
            for g in members(group):
                by.setdefault(g, []).append((key, row))
        for g in order():
            if g not in by:
                continue
            rs = [r for _, r in by[g]]
            lost = sum(1 for k, r in by[g] if k in base_ok and base_ok[k] and not r["ok"])
            won = sum(1 for k, r in by[g] if k in base_ok and not base_ok[k] and r["ok"])
            table.append({
                "run": label, "group": g, "n": len(rs),
                "ok": sum(r["ok"] for r in rs),
                "wrongconv": sum(r["wrongconv"] for r in rs),
                "err_med": quantile([r["error"] for r in rs], 0.5),
                "err_q95": quantile([r["error"] for r in rs], 0.95),
                "rot_med": quantile([r["rot"] for r in rs], 0.5),
                "rot_q95": quantile([r["rot"] for r in rs], 0.95),
                "ms_med": quantile([r["ms"] for r in rs], 0.5),
                "it_mean": sum(r["it"] for r in rs) / len(rs),
                "lost": lost, "won": won,
            })

    cols = ["group", "run", "n", "ok", "wrongconv", "err_med", "err_q95", "rot_med", "rot_q95",
            "ms_med", "it_mean", "lost", "won"]

    def fmt(row, c):
        v = row[c]
        if c in ("err_med", "err_q95", "rot_med", "rot_q95"):
            return f"{v:.4g}"
        if c in ("ms_med", "it_mean"):
            return f"{v:.1f}"
        return str(v)

    table.sort(key=lambda r: (order().index(r["group"]), [x[0] for x in runs].index(r["run"])))
    widths = {c: max(len(c), *(len(fmt(r, c)) for r in table)) for c in cols}
    lines = [" ".join(c.rjust(widths[c]) for c in cols)]
    for r in table:
        lines.append(" ".join(fmt(r, c).rjust(widths[c]) for c in cols))
    legend = [f"{label}: {flags or '(protocol options only)'}" for label, flags, _ in runs]
    if starts_dir:
        lines += [""] + start_table(runs, starts_dir)
    print("\n".join(legend + [""] + lines))
    if out_prefix:
        with open(out_prefix + ".csv", "w", newline="") as f:
            w = csv.writer(f)
            w.writerow(cols)
            for r in table:
                w.writerow([fmt(r, c) for c in cols])
        with open(out_prefix + ".md", "w") as f:
            f.write("\n".join("- " + x for x in legend) + "\n\n")
            f.write("| " + " | ".join(cols) + " |\n|" + "---|" * len(cols) + "\n")
            for r in table:
                f.write("| " + " | ".join(fmt(r, c) for c in cols) + " |\n")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
