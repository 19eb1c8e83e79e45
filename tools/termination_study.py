#!/usr/bin/python3
"""termination_study.py - helper of tools/termination_study.sh (docs/TERMINATION.md).

Sub-commands (all read files written by ppcr_cli / ppcr_bench; nothing is simulated for the
tables):
  initial   write the 4x4 initial guess of a failure case: SOURCE rotated by a further ANGLE
            degrees about the vertical (y) axis through SOURCE's centroid, in the direction that
            increases the misalignment w.r.t. the ground truth.
  report    read the manifest of benchmark runs (one line per run, written by the shell script),
            their --json summaries, --out per-problem CSVs and the fixed-100 --trace-dir traces;
            write the tables (Tables 3-5 layout), the oracle analysis and the offline cross-check
            into docs/TERMINATION.md between <!-- BEGIN GENERATED: name --> / <!-- END ... -->.

Also a small library used by plot_trace.py: read_trace(), settling_mask(), simulate_stop(),
oracle_stop(). The criteria rules are those of src/registration/termination.cpp (termination.hpp documents
them); the oracle is defined in oracle_stop().
"""

import argparse
import csv
import json
import math
import os
import re
import subprocess
import sys

import numpy as np

TRACE_COLUMNS = [
    "iteration", "phase", "successful_steps", "unsuccessful_steps", "initial_cost", "final_cost",
    "cost_drop", "mse_prev", "mse_ground_truth", "benchmark_error", "scale", "correspondences",
    "matched_source_points", "tx", "ty", "tz", "qx", "qy", "qz", "qw", "time_ms",
]
PHASES = {"coarse": 1.0, "fine": 0.0}  # the phase column, as a number (1: the EM coarse phase)
REQUIRED = ["iteration", "successful_steps", "initial_cost", "final_cost", "cost_drop",
            "mse_prev", "scale"]


class StudyError(Exception):
    """An input problem reported as one line (no traceback)."""


# --------------------------------------------------------------------------- traces

def read_trace(path):
    """Reads a ppcr trace CSV into a dict of float arrays (NaN for empty cells)."""
    if not os.path.isfile(path):
        raise StudyError(f"{path}: no such file")
    try:
        with open(path, newline="") as f:
            rows = list(csv.reader(f))
    except (OSError, UnicodeDecodeError) as e:
        raise StudyError(f"{path}: cannot read: {e}")
    if not rows:
        raise StudyError(f"{path}: empty file (expected a ppcr trace CSV header)")
    header = [h.strip() for h in rows[0]]
    missing = [c for c in REQUIRED if c not in header]
    if missing:
        raise StudyError(f"{path}: not a ppcr trace: missing column(s) {', '.join(missing)}")
    data = {h: [] for h in header}
    for n, row in enumerate(rows[1:], start=2):
        if not row:
            continue
        if len(row) != len(header):
            raise StudyError(f"{path}:{n}: {len(row)} fields, expected {len(header)}")
        for h, v in zip(header, row):
            v = v.strip()
            if h == "phase" and v in PHASES:
                data[h].append(PHASES[v])
                continue
            try:
                data[h].append(float(v) if v else math.nan)
            except ValueError:
                raise StudyError(f"{path}:{n}: column {h}: not a number: {v!r}")
    out = {h: np.asarray(v, dtype=float) for h, v in data.items()}
    if len(out["iteration"]) == 0:
        raise StudyError(f"{path}: no iterations (header only)")
    it = out["iteration"]
    if not np.array_equal(it, np.arange(1, len(it) + 1)):
        raise StudyError(f"{path}: iterations are not 1, 2, 3, ...")
    return out


def has_ground_truth(trace):
    g = trace.get("mse_ground_truth")
    return g is not None and np.all(np.isfinite(g)) and np.all(g >= 0)


def settling_mask(trace, scale_mode="auto", shrink=None):
    """Which iterations the monitor saw as scale_settling (src/registration/registration.cpp,
    src/registration/scale_schedule.cpp), reconstructed from the trace's scale column:
      EM: iteration t settles while its scale is still the coarse one (every iteration up to the
          last one run at the initial scale), or when its scale is exactly sqrt(shrink) times the
          previous one (the shrink limit was hit by the EM estimate; shrink = --scale-shrink,
          the library's WeightOptions::em_min_shrink by default).
      raw / fixed scale: never.
    scale_mode 'auto': raw when every scale is exactly 1, else EM (the default mode). A fixed
    scale or a coarse phase that never ends both give a constant scale: pass 'fixed' / 'em'."""
    s = trace["scale"]
    n = len(s)
    if scale_mode == "auto":
        scale_mode = "raw" if np.all(s == 1.0) else "em"
    if scale_mode in ("raw", "fixed"):
        return np.zeros(n, dtype=bool)
    if scale_mode != "em":
        raise StudyError(f"unknown scale mode {scale_mode!r} (expected auto, em, raw, fixed)")
    mask = np.zeros(n, dtype=bool)
    changed = np.nonzero(s != s[0])[0]
    last_coarse = (changed[0] - 1) if len(changed) else n - 1
    mask[: last_coarse + 1] = True
    for i in range(last_coarse + 1, n):
        f = DEFAULT_SCALE_SHRINK if shrink is None else shrink
        if i > 0 and abs(s[i] ** 2 - f * s[i - 1] ** 2) <= 1e-9 * s[i - 1] ** 2:
            mask[i] = True
    return mask


# The library's default --scale-shrink (WeightOptions::em_min_shrink).
DEFAULT_SCALE_SHRINK = 0.25

# The library's default --motion-guard (TerminationCriteria::cost_drop_max_motion).
DEFAULT_MOTION_GUARD = 0.03


def simulate_stop(trace, spec, settling, radius=1.0):
    """The iteration at which a criterion set would have stopped on this trajectory (the monitor
    of src/registration/termination.cpp, replayed), or None if it would not have stopped within the trace.
    spec keys: criteria (set of 'fixed','cost-drop','mse-prev','successful-steps'),
    fixed (iterations), max_iterations, cd_threshold, cd_patience, motion_guard (fraction of
    radius; default DEFAULT_MOTION_GUARD, the library's; 0 = the paper's rule), mse_ratio, mse_patience, steps_threshold, steps_patience.
    Returns (iteration, reason)."""
    c = spec.get("criteria", {"cost-drop"})
    thr = spec.get("cd_threshold", 0.01)
    pat = spec.get("cd_patience", 10)
    guard = spec.get("motion_guard", DEFAULT_MOTION_GUARD)
    ratio = spec.get("mse_ratio", 2.0)
    mpat = spec.get("mse_patience", 3)
    sthr = spec.get("steps_threshold", 1)
    spat = spec.get("steps_patience", 3)
    fixed = spec.get("fixed", 100)
    cap = spec.get("max_iterations", 100)
    cd = ms = st = 0
    prev_mse = 0.0
    n = len(trace["iteration"])
    for i in range(n):
        t = i + 1
        init, fin = trace["initial_cost"][i], trace["final_cost"][i]
        mse = trace["mse_prev"][i]
        if not (math.isfinite(init) and math.isfinite(fin)):
            return t, "numerical_failure"
        if init <= 0.0:
            return t, "zero_cost"
        drop = (init - fin) / init
        counting = not settling[i]
        still = guard <= 0.0 or math.sqrt(mse) < guard * radius
        cd = cd + 1 if (counting and still and drop < thr) else 0
        low = mse == 0.0 or (t >= 2 and mse < prev_mse / ratio)
        ms = ms + 1 if (counting and low) else 0
        prev_mse = mse
        st = st + 1 if (counting and trace["successful_steps"][i] <= sthr) else 0
        if "fixed" in c and t >= fixed:
            return t, "fixed_iterations"
        if "cost-drop" in c and cd > pat:
            return t, "cost_drop"
        if "mse-prev" in c and ms > mpat:
            return t, "mse_prev"
        if "successful-steps" in c and st > spat:
            return t, "successful_steps"
        if t >= cap:
            return t, "max_iterations"
    return None, "none"


def oracle_stop(trace, relative=0.1, absolute=0.0):
    """The oracle 'ideal stop' (paper Sec. 3.2: where the error w.r.t. the ground truth stops
    decreasing by more than a negligible amount), on the trajectory in the trace (a fixed-100
    run: the whole trajectory):
        t* = min { t : rms(t) - m(t) <= max(relative * m(t), absolute) },
        rms(t) = sqrt(MSE w.r.t. the ground truth after iteration t),
        m(t)   = min_{t' >= t} rms(t')  (the best any later iteration reaches).
    In words: the first iteration after which no later iteration brings the source closer to
    its true pose by more than `relative` of the remaining error (10 % by default: the issue's
    'within 10 %' bar, per problem) or `absolute` (RMS, cloud units), whichever is larger.
    Returns None without ground-truth columns."""
    if not has_ground_truth(trace):
        return None
    rms = np.sqrt(trace["mse_ground_truth"])
    suffix_min = np.minimum.accumulate(rms[::-1])[::-1]
    ok = np.nonzero(rms - suffix_min <= np.maximum(relative * suffix_min, absolute))[0]
    return int(ok[0]) + 1


# --------------------------------------------------------------------------- initial guesses

def read_ply_xyz(path):
    """x, y, z of a binary little-endian or ASCII PLY whose vertex element comes first."""
    with open(path, "rb") as f:
        header = []
        while True:
            line = f.readline()
            if not line:
                raise StudyError(f"{path}: truncated PLY header")
            line = line.decode("ascii", "replace").strip()
            header.append(line)
            if line == "end_header":
                break
        fmt = next((h.split()[1] for h in header if h.startswith("format ")), None)
        count, props, in_vertex = 0, [], False
        for h in header:
            p = h.split()
            if p[:1] == ["element"]:
                in_vertex = p[1] == "vertex"
                if in_vertex:
                    count = int(p[2])
            elif p[:1] == ["property"] and in_vertex:
                props.append((p[1], p[2]))
        types = {"float": "f4", "float32": "f4", "double": "f8", "float64": "f8",
                 "uchar": "u1", "uint8": "u1", "char": "i1", "int8": "i1", "short": "i2",
                 "int16": "i2", "ushort": "u2", "uint16": "u2", "int": "i4", "int32": "i4",
                 "uint": "u4", "uint32": "u4"}
        if fmt == "binary_little_endian":
            dt = np.dtype([(n, "<" + types[t]) for t, n in props])
            v = np.frombuffer(f.read(count * dt.itemsize), dtype=dt, count=count)
            return np.stack([v["x"], v["y"], v["z"]], axis=1).astype(float)
        if fmt == "ascii":
            names = [n for _, n in props]
            a = np.loadtxt(f, max_rows=count, ndmin=2)
            return a[:, [names.index("x"), names.index("y"), names.index("z")]]
        raise StudyError(f"{path}: unsupported PLY format {fmt}")


def read_matrix(path):
    m = np.loadtxt(path)
    if m.shape != (4, 4):
        raise StudyError(f"{path}: expected a 4x4 matrix")
    return m


def rotation_angle_deg(R):
    return math.degrees(math.acos(max(-1.0, min(1.0, (np.trace(R) - 1.0) / 2.0))))


def cmd_initial(a):
    P = read_ply_xyz(a.source)
    c = P.mean(axis=0)
    gt = read_matrix(a.ground_truth)
    best = None
    for sign in (1.0, -1.0):
        th = math.radians(sign * a.angle)
        R = np.array([[math.cos(th), 0, math.sin(th)], [0, 1, 0],
                      [-math.sin(th), 0, math.cos(th)]])
        T = np.eye(4)
        T[:3, :3] = R
        T[:3, 3] = c - R @ c
        # misalignment of the initial guess: the rotation taking T_init to T_gt
        mis = rotation_angle_deg(gt[:3, :3] @ R.T)
        if best is None or mis > best[0] + 1e-9:
            best = (mis, T, sign)
    mis, T, sign = best
    with open(a.out, "w") as f:
        for r in range(4):
            f.write(" ".join(f"{T[r, k]:.17g}" for k in range(4)) + "\n")
    print(f"{a.out}: rotation {sign * a.angle:+g} deg about y through the centroid "
          f"({c[0]:.6f}, {c[1]:.6f}, {c[2]:.6f}); misalignment w.r.t. the ground truth "
          f"{mis:.1f} deg (identity: {rotation_angle_deg(gt[:3, :3]):.1f} deg)")


# --------------------------------------------------------------------------- report

SET_ORDER = ["bunny", "lidar"]
MODEL_ORDER = ["point", "plane"]


def quantile(v, q):
    """numpy's linear interpolation (the same as ppcr_bench's summary)."""
    v = np.asarray(v, dtype=float)
    return float(np.quantile(v, q)) if len(v) else math.nan


def read_runs_csv(path):
    with open(path, newline="") as f:
        rows = list(csv.DictReader(f))
    if not rows:
        raise StudyError(f"{path}: no problems")
    return rows


def parse_flags(flags):
    """The criterion spec of a variant's flags (for the offline replay)."""
    tok = flags.split()
    spec = {"criteria": {"cost-drop"}}
    conv = {"--cost-drop-threshold": ("cd_threshold", float), "--patience": ("cd_patience", int),
            "--motion-guard": ("motion_guard", float), "--mse-ratio": ("mse_ratio", float),
            "--mse-patience": ("mse_patience", int), "--steps-threshold": ("steps_threshold", int)}
    for k, v in zip(tok, tok[1:] + [""]):
        if k == "--criterion":
            spec["criteria"] = set(v.split(","))
        elif k == "--max-iterations":
            spec["max_iterations"] = spec["fixed"] = int(v)
        elif k in conv:
            name, f = conv[k]
            spec[name] = f(v)
    return spec


def scale_mode_of(flags):
    tok = flags.split()
    if "--scale" in tok:
        v = tok[tok.index("--scale") + 1]
        return v if v in ("em", "raw") else "fixed"
    return "em"


def fmt(x, digits=4):
    if x is None or (isinstance(x, float) and not math.isfinite(x)):
        return "-"
    if x == 0:
        return "0"
    return f"{x:.{digits}g}"


def read_time(path):
    """(wall, cpu) seconds of a run from /usr/bin/time -f '%e %U %S'."""
    try:
        with open(path) as f:
            last = [ln for ln in f.read().split("\n") if ln.strip()][-1].split()
        return float(last[0]), float(last[1]) + float(last[2])
    except (OSError, IndexError, ValueError):
        return math.nan, math.nan


MANIFEST_KEYS = ["set", "model", "variant", "family", "flags", "json", "csv", "tracedir",
                 "radius", "time"]


def load_manifest(path):
    runs = []
    with open(path) as f:
        for n, line in enumerate(f, 1):
            line = line.rstrip("\n")
            if not line or line.startswith("#"):
                continue
            p = line.split("\t")
            if len(p) != len(MANIFEST_KEYS):
                raise StudyError(f"{path}:{n}: expected {len(MANIFEST_KEYS)} tab-separated "
                                 "fields")
            r = dict(zip(MANIFEST_KEYS, p))
            r["radius"] = float(r["radius"])
            try:
                with open(r["json"]) as jf:
                    r["summary"] = json.load(jf)
            except (OSError, ValueError) as e:
                raise StudyError(f"{r['json']}: cannot read the run's summary: {e}")
            r["rows"] = read_runs_csv(r["csv"])
            r["wall_s"], r["cpu_s"] = read_time(r["time"])
            r["mode"] = scale_mode_of(r["flags"])
            runs.append(r)
    return runs


class Traces:
    """The fixed-100 traces of each trajectory family, read once."""

    def __init__(self, runs):
        self.runs = runs
        self.cache = {}

    def family_run(self, r):
        return next((x for x in self.runs if x["set"] == r["set"] and x["model"] == r["model"]
                     and x["family"] == r["family"] and x["tracedir"] != "-"), None)

    def get(self, fam, pid):
        path = os.path.join(fam["tracedir"], pid + ".csv")
        if path not in self.cache:
            self.cache[path] = read_trace(path) if os.path.isfile(path) else None
        return self.cache[path]


def hidden(r):
    """The traced fixed-100 run of a family whose table row is a separate untraced run."""
    return r["variant"].endswith("[trace]")


def reference_of(runs, r):
    """The fixed-100 run a variant is compared with: the raw one for raw-mode variants."""
    want = "fixed 100 (raw)" if r["mode"] == "raw" else "fixed 100"
    return next((x for x in runs if x["set"] == r["set"] and x["model"] == r["model"]
                 and x["variant"] == want), None)


def meets_bar(r, ref):
    s, rs = r["summary"], ref["summary"]
    return (s["median"] <= 1.1 * rs["median"] and s["q95"] <= 1.1 * rs["q95"]
            and s["mean_iterations"] <= 0.25 * rs["mean_iterations"])


def table_rows(runs, sel, with_set=False):
    head = ("| " + ("set | model | " if with_set else "") + "variant | median | q0.75 | q0.95 | "
            "success % | mean iter. | max iter. | stopped by the cap | median ms | CPU ms "
            "/ problem | median / fixed | q0.95 / fixed | iter. / fixed |")
    cols = head.count("|") - 1
    out = [head, "|" + "---|" * (2 if with_set else 0) + "---|" + "---:|" * (cols - 1 - (2 if with_set else 0))]
    for r in sel:
        s = r["summary"]
        its = [int(x["iterations"]) for x in r["rows"]]
        capped = sum(1 for x in r["rows"] if x["stop_reason"] == "max_iterations")
        fails = sum(1 for x in r["rows"] if x["ok"] != "1")
        ref = reference_of(runs, r)
        rel = ("-", "-", "-")
        if ref is not None and ref is not r:
            rs = ref["summary"]
            rel = (f"{s['median'] / rs['median']:.2f}", f"{s['q95'] / rs['q95']:.2f}",
                   f"{s['mean_iterations'] / rs['mean_iterations'] * 100:.0f} %")
        name = r["variant"] + (f" ({fails} failed)" if fails else "")
        if r["tracedir"] != "-":
            name += " [traced]"
        cpu = 1000.0 * r["cpu_s"] / max(1, s["problems"])
        pre = f"| {r['set']} | {r['model']} " if with_set else ""
        out.append(f"{pre}| {name} | {fmt(s['median'])} | {fmt(s['q75'])} | {fmt(s['q95'])} | "
                   f"{100 * s['success']:.0f} | {s['mean_iterations']:.1f} | {max(its)} | "
                   f"{capped} | {s['median_ms']:.0f} | {fmt(cpu, 3)} | {rel[0]} | {rel[1]} | "
                   f"{rel[2]} |")
    return "\n".join(out) + "\n"


def em_table(runs, set_name, model):
    sel = [r for r in runs if r["set"] == set_name and r["model"] == model and r["mode"] != "raw"
           and not hidden(r)]
    if not sel:
        return ""
    body = table_rows(runs, sel)
    ok = [r["variant"] for r in sel
          if r["variant"] != "fixed 100" and reference_of(runs, r) is not None
          and meets_bar(r, reference_of(runs, r))]
    body += ("\nMeets the issue's bar (median and q0.95 within 10 % of fixed 100's, at most 25 % "
             "of its iterations): " + (", ".join(ok) if ok else "**none**") + ".\n")
    return body


def raw_table(runs):
    sel = [r for s in SET_ORDER for m in MODEL_ORDER for r in runs
           if r["set"] == s and r["model"] == m and r["mode"] == "raw" and not hidden(r)]
    if not sel:
        return ""
    body = table_rows(runs, sel, with_set=True)
    ok = [f"{r['set']}/{r['model']}: {r['variant']}" for r in sel
          if reference_of(runs, r) is not None and r is not reference_of(runs, r)
          and meets_bar(r, reference_of(runs, r))]
    body += ("\nMeets the bar against raw fixed 100: " + ("; ".join(ok) if ok else "none") +
             ".\n")
    return body


def summary_table(runs):
    """One line per default-trajectory variant: its ratios to fixed 100 on every set/model."""
    combos = [(s, m) for s in SET_ORDER for m in MODEL_ORDER
              if any(r["set"] == s and r["model"] == m for r in runs)]
    labels = []
    for r in runs:
        if (r["mode"] != "raw" and r["variant"] not in labels and r["variant"] != "fixed 100"
                and not hidden(r)):
            labels.append(r["variant"])
    head = "| variant | " + " | ".join(f"{s} {m}" for s, m in combos) + \
        " | worst ratio | mean iter. (all) |"
    out = [head, "|---|" + "---:|" * (len(combos) + 2),
           "| (cell: median ratio / q0.95 ratio / mean iterations) |" + " |" * (len(combos) + 2)]
    for lab in labels:
        cells, worst, its = [], 0.0, []
        complete = True
        for s, m in combos:
            r = next((x for x in runs if x["set"] == s and x["model"] == m
                      and x["variant"] == lab), None)
            ref = next((x for x in runs if x["set"] == s and x["model"] == m
                        and x["variant"] == "fixed 100"), None)
            if r is None or ref is None:
                cells.append("-")
                complete = False
                continue
            a = r["summary"]["median"] / ref["summary"]["median"]
            b = r["summary"]["q95"] / ref["summary"]["q95"]
            worst = max(worst, a, b)
            its.append(r["summary"]["mean_iterations"])
            bold = "**" if max(a, b) > 1.1 else ""
            cells.append(f"{bold}{a:.2f} / {b:.2f}{bold} / {r['summary']['mean_iterations']:.1f}")
        out.append(f"| {lab} | " + " | ".join(cells) +
                   f" | {worst:.2f}{'' if complete else ' (partial)'} | "
                   f"{np.mean(its) if its else math.nan:.1f} |")
    return "\n".join(out) + "\n"


def phases(trace, mode):
    """(first iteration the adaptive criteria count, coarse-phase length, shrink iterations)."""
    m = settling_mask(trace, mode)
    n = len(m)
    free = np.nonzero(~m)[0]
    first = int(free[0]) + 1 if len(free) else n + 1
    s = trace["scale"]
    changed = np.nonzero(s != s[0])[0]
    coarse = int(changed[0]) if len(changed) else n
    if mode != "em":
        coarse = 0
    shrink = int(np.sum(m[coarse:]))
    return first, coarse, shrink


def settling_section(runs, traces):
    out = ["| set | model | trajectory | first counting iteration: mean | median | max | "
           "coarse phase: mean iterations | shrink-limited iterations: mean | runs whose "
           "criteria never count |",
           "|---|---|---|---:|---:|---:|---:|---:|---:|"]
    for r in runs:
        if r["tracedir"] == "-" or r["mode"] != "em":
            continue
        f, c, k, never = [], [], [], 0
        for row in r["rows"]:
            tr = traces.get(r, row["id"])
            if tr is None:
                continue
            a, b, d = phases(tr, "em")
            f.append(a)
            c.append(b)
            k.append(d)
            never += int(a > len(tr["iteration"]))
        if f:
            out.append(f"| {r['set']} | {r['model']} | {r['family']} | {np.mean(f):.1f} | "
                       f"{np.median(f):.0f} | {max(f)} | {np.mean(c):.1f} | {np.mean(k):.1f} | "
                       f"{never} |")
    return "\n".join(out) + "\n"


def oracle_section(runs, traces, rel):
    """Per run: stop - ideal (iterations), the ideal from the fixed-100 trace of the variant's
    trajectory family; and the offline replay of the variant's criteria on that trace."""
    out = ["| set | model | variant | stop - ideal: median | q0.05 | q0.25 | q0.75 | q0.95 | "
           "early (< ideal) | early by > 5 | late by > 20 | replay = run |",
           "|---|---|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|"]
    for r in runs:
        fam = traces.family_run(r)
        if fam is None or hidden(r):
            continue
        diffs, replay_ok, replay_n = [], 0, 0
        for row in r["rows"]:
            tr = traces.get(fam, row["id"])
            if tr is None:
                continue
            ideal = oracle_stop(tr, rel)
            if ideal is None:
                continue
            stop = int(row["iterations"])
            diffs.append(stop - ideal)
            sim, _ = simulate_stop(tr, parse_flags(r["flags"]), settling_mask(tr, r["mode"]),
                                   r["radius"])
            replay_n += 1
            replay_ok += int(sim == stop)
        if not diffs:
            continue
        d = np.asarray(diffs)
        out.append(
            f"| {r['set']} | {r['model']} | {r['variant']} | {np.median(d):+.0f} | "
            f"{quantile(d, 0.05):+.0f} | {quantile(d, 0.25):+.0f} | {quantile(d, 0.75):+.0f} | "
            f"{quantile(d, 0.95):+.0f} | {int(np.sum(d < 0))} | {int(np.sum(d < -5))} | "
            f"{int(np.sum(d > 20))} | {replay_ok}/{replay_n} |")
    return "\n".join(out) + "\n"


def frozen_section(runs, traces, rel):
    """The oracle's ideal stop on each trajectory, and what fixed 100 spends after it."""
    out = ["| set | model | trajectory | ideal stop: mean | median | q0.05 | q0.95 | fixed 100 "
           "runs after it: mean | ideal > 25 | ideal > 50 | benchmark error at the ideal stop "
           "/ at 100: median | q0.95 |",
           "|---|---|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|"]
    for r in runs:
        if r["tracedir"] == "-":
            continue
        ideals, ratio = [], []
        for row in r["rows"]:
            tr = traces.get(r, row["id"])
            if tr is None:
                continue
            ideal = oracle_stop(tr, rel)
            if ideal is None:
                continue
            ideals.append(ideal)
            be = tr["benchmark_error"]
            ratio.append(be[ideal - 1] / be[-1] if be[-1] > 0 else math.nan)
        if not ideals:
            continue
        n = int(r["rows"][0]["iterations"])
        i = np.asarray(ideals)
        out.append(f"| {r['set']} | {r['model']} | {r['family']} | {i.mean():.1f} | "
                   f"{np.median(i):.0f} | {quantile(i, 0.05):.0f} | {quantile(i, 0.95):.0f} | "
                   f"{np.mean(n - i):.1f} | {int(np.sum(i > 25))} | {int(np.sum(i > 50))} | "
                   f"{np.nanmedian(ratio):.2f} | {quantile(ratio, 0.95):.2f} |")
    return "\n".join(out) + "\n"


# Figure cases (ppcr_cli): cases.tsv lines "case model crit trace json".
FIGURE_CRITERIA = [
    ("cost drop 1 % x 10", {"criteria": {"cost-drop"}}),
    ("cost drop 1 % x 20", {"criteria": {"cost-drop"}, "cd_patience": 20}),
    ("cost drop 0.3 % x 10", {"criteria": {"cost-drop"}, "cd_threshold": 0.003}),
    ("MSE prev. /2 x 3", {"criteria": {"mse-prev"}}),
    ("successful steps <= 1 x 3", {"criteria": {"successful-steps"}}),
]


def load_cases(figdir):
    path = os.path.join(figdir, "cases.tsv")
    cases = []
    with open(path) as f:
        for line in f:
            p = line.rstrip("\n").split("\t")
            if len(p) == 5:
                with open(p[4]) as jf:
                    j = json.load(jf)
                cases.append({"case": p[0], "model": p[1], "crit": p[2], "trace": p[3],
                              "json": j})
    return cases


def figures_section(figdir, rel):
    cases = load_cases(figdir)
    out = ["| case | model | fixed 100: benchmark error, rotation error (deg) | default run "
           "(cost drop 1 % x 10): stopped at, benchmark error | replayed on the fixed-100 "
           "trajectory: " + ", ".join(n for n, _ in FIGURE_CRITERIA) + " | oracle ideal stop |",
           "|---|---|---|---|---|---:|"]
    for c in cases:
        if c["crit"] != "fixed":
            continue
        d = next((x for x in cases if x["case"] == c["case"] and x["model"] == c["model"]
                  and x["crit"] == "default"), None)
        tr = read_trace(c["trace"])
        m = settling_mask(tr, "em")
        reps = []
        for _, spec in FIGURE_CRITERIA:
            t, _ = simulate_stop(tr, spec, m, 0.02)
            reps.append(str(t) if t is not None and t < len(m) else "never (cap)")
        ideal = oracle_stop(tr, rel)
        j = c["json"]
        dj = d["json"] if d else None
        dtxt = (f"{dj['iterations']} ({dj['stop_reason']}), {dj['benchmark_error']:.4g}"
                if dj else "-")
        out.append(f"| {c['case']} deg | {c['model']} | {j['benchmark_error']:.4g}, "
                   f"{j['rotation_error_deg']:.1f} | {dtxt} | {', '.join(reps)} | {ideal} |")
    return "\n".join(out) + "\n"


def initial_section(figdir):
    out = []
    for case in ("45", "90", "180"):
        log = os.path.join(figdir, f"initial_{case}.log")
        txt = os.path.join(figdir, f"initial_{case}.txt")
        if not os.path.isfile(txt):
            continue
        with open(log) as f:
            note = f.read().strip().split(": ", 1)[-1]
        with open(txt) as f:
            mat = f.read().rstrip("\n")
        out.append(f"`initial_{case}.txt` ({note}):\n\n```\n{mat}\n```\n")
    return "\n".join(out)


def commands_section(path, figdir):
    with open(path) as f:
        lines = [ln.rstrip("\n") for ln in f if ln.strip()]
    with open(os.path.join(figdir, "commands.txt")) as f:
        lines += [ln.rstrip("\n") for ln in f if ln.strip()]
    return "```\n" + "\n".join(lines) + "\n```\n"


def pick_examples(runs, traces, rel):
    """Lidar traces for the figures: (a) the raw-mode problem where the paper's cost drop hurt
    most (real runs: its error over raw fixed 100's), (b) the default-trajectory problem the
    oracle needs longest for. Returns [(trace path, png name, title, radius, scale mode,
    motion guard of the run)]."""
    picks = []
    cd = next((r for m in ("point", "plane") for r in runs if r["set"] == "lidar"
               and r["model"] == m and r["mode"] == "raw" and "authors' rule" in r["variant"]),
              None)
    if cd is not None:
        ref = reference_of(runs, cd)
        fam = traces.family_run(cd)
        if ref is not None and fam is not None:
            fixed = {x["id"]: float(x["error"]) for x in ref["rows"]}
            worst = max(cd["rows"], key=lambda x: float(x["error"]) / fixed[x["id"]])
            picks.append((os.path.join(fam["tracedir"], worst["id"] + ".csv"),
                          "trace_lidar_raw_early_stop.png",
                          f"lidar problem {worst['id']}, raw mode (the authors'), "
                          f"{cd['model']}, 100 "
                          f"iterations: the paper's cost drop stopped at {worst['iterations']} "
                          f"(error {float(worst['error']):.3g} vs {fixed[worst['id']]:.3g})",
                          1.0, "raw", 0.0))
    fam = next((r for m in ("point", "plane") for r in runs if r["set"] == "lidar"
                and r["model"] == m and r["family"] == "default" and r["tracedir"] != "-"),
               None)
    if fam is not None:
        best = None
        for row in fam["rows"]:
            tr = traces.get(fam, row["id"])
            if tr is None:
                continue
            i = oracle_stop(tr, rel)
            if i is not None and (best is None or i > best[0]):
                best = (i, row["id"])
        if best is not None:
            picks.append((os.path.join(fam["tracedir"], best[1] + ".csv"),
                          "trace_lidar_point_slowest.png",
                          f"lidar problem {best[1]}, default (EM) mode, {fam['model']}, 100 "
                          f"iterations: the latest oracle ideal stop of the set ({best[0]})",
                          1.0, "em", DEFAULT_MOTION_GUARD))
    return picks


def replace_generated(doc_path, sections):
    with open(doc_path) as f:
        text = f.read()
    for name, body in sections.items():
        pat = re.compile(r"(<!-- BEGIN GENERATED: " + re.escape(name) + r" -->\n)(.*?)"
                         r"(<!-- END GENERATED: " + re.escape(name) + r" -->)", re.S)
        if not pat.search(text):
            print(f"termination_study.py: warning: {doc_path}: no GENERATED block named "
                  f"{name!r} (skipped)", file=sys.stderr)
            continue
        text = pat.sub(lambda m: m.group(1) + body + m.group(3), text)
    tmp = doc_path + ".tmp"
    with open(tmp, "w") as f:
        f.write(text)
    os.replace(tmp, doc_path)


def cmd_report(a):
    runs = load_manifest(a.manifest)
    traces = Traces(runs)
    rel = a.oracle_relative
    sections = {}
    for s in SET_ORDER:
        for m in MODEL_ORDER:
            body = em_table(runs, s, m)
            if body:
                sections[f"table-{s}-{m}"] = body
    sections["table-raw"] = raw_table(runs)
    sections["summary"] = summary_table(runs)
    sections["settling"] = settling_section(runs, traces)
    sections["oracle"] = oracle_section(runs, traces, rel)
    sections["frozen"] = frozen_section(runs, traces, rel)
    sections["commands"] = commands_section(a.commands, a.figures)
    sections["initial"] = initial_section(a.figures)
    sections["figures"] = figures_section(a.figures, rel)
    if a.doc:
        replace_generated(a.doc, sections)
        print(f"{a.doc}: {len(sections)} generated block(s) updated")
    else:
        for k, v in sections.items():
            print(f"<!-- {k} -->\n{v}")


def cmd_figures(a):
    runs = load_manifest(a.manifest)
    traces = Traces(runs)
    jobs = []
    for c in load_cases(a.figures):
        if c["crit"] != "fixed":
            continue
        mis = {"45": "the paper's 45 degree case (Figure 2)",
               "90": "a further 45 degrees (Figure 6a)",
               "180": "a further 135 degrees (Figure 6b)"}[c["case"]]
        jobs.append((c["trace"], f"trace_bunny{c['case']}_{c['model']}.png",
                     f"bun045 onto bun000, {mis}, {c['model']} model, 100 iterations",
                     0.02, "em", DEFAULT_MOTION_GUARD))
    jobs += pick_examples(runs, traces, a.oracle_relative)
    os.makedirs(a.images, exist_ok=True)
    for trace, png, title, radius, mode, guard in jobs:
        r = subprocess.run([sys.executable, a.plot, trace, "-o", os.path.join(a.images, png),
                            "--title", title, "--oracle-relative", str(a.oracle_relative),
                            "--radius", str(radius), "--scale-mode", mode,
                            "--motion-guard", str(guard)],
                           capture_output=True, text=True)
        if r.returncode != 0:
            raise StudyError(f"plot_trace.py {trace}: {r.stderr.strip()}")
        size = os.path.getsize(os.path.join(a.images, png))
        print(f"{os.path.join(a.images, png)} ({size // 1024} KB)")


def cmd_runtime(a):
    text = (f"Last full run: {a.seconds // 60} min {a.seconds % 60} s wall for {a.runs} "
            f"benchmark runs ({a.reran} executed, the rest reused: unchanged command, binaries "
            f"and problems), {a.jobs} at a time with --threads 1 each, on "
            f"{os.cpu_count()} shared cores; binaries {a.binary_stamp}.\n")
    replace_generated(a.doc, {"runtime": text})


def main(argv):
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    sub = p.add_subparsers(dest="cmd", required=True)
    q = sub.add_parser("initial", help="initial guess of a failure case (4x4 file)")
    q.add_argument("source")
    q.add_argument("ground_truth")
    q.add_argument("angle", type=float)
    q.add_argument("-o", "--out", required=True)
    for name in ("report", "figures"):
        q = sub.add_parser(name)
        q.add_argument("manifest")
        q.add_argument("--figures", required=True, help="folder of the ppcr_cli figure runs")
        q.add_argument("--oracle-relative", type=float, default=0.1)
        if name == "report":
            q.add_argument("--doc", help="document whose GENERATED blocks to update")
            q.add_argument("--commands", required=True)
        else:
            q.add_argument("--images", required=True)
            q.add_argument("--plot", required=True)
    q = sub.add_parser("runtime")
    q.add_argument("doc")
    q.add_argument("--seconds", type=int, required=True)
    q.add_argument("--jobs", type=int, required=True)
    q.add_argument("--runs", type=int, required=True)
    q.add_argument("--reran", type=int, required=True)
    q.add_argument("--binary-stamp", required=True)
    a = p.parse_args(argv)
    try:
        {"initial": cmd_initial, "report": cmd_report, "figures": cmd_figures,
         "runtime": cmd_runtime}[a.cmd](a)
    except StudyError as e:
        print(f"termination_study.py: error: {e}", file=sys.stderr)
        return 1
    except (OSError, ValueError, KeyError) as e:
        print(f"termination_study.py: error: {type(e).__name__}: {e}", file=sys.stderr)
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
