#!/usr/bin/python3
"""plot_trace.py - a ppcr trace (ppcr_cli --trace, ppcr_bench --trace-dir) as a PNG in the
manner of the paper's Figure 2: per outer iteration, the successful LM steps, the initial and
final cost, the relative cost drop, the MSE w.r.t. the previous iteration, the MSE w.r.t. the
ground truth (when the trace has it), and the discrete derivatives of the last three.

Vertical lines mark where the run stopped (its last row) and where each criterion, with the
default settings, would have stopped on this trajectory (the monitor of src/registration/termination.cpp
replayed on the trace; a criterion that would fire after the last row is not drawn), and the
oracle's ideal stop (tools/termination_study.py: oracle_stop). Grey bands: iterations in which
the E-step scale was still settling (coarse phase or shrinking at its limit), when the
adaptive criteria do not count.

Usage: plot_trace.py TRACE.csv [-o OUT.png] [--title T] [--radius R] [--motion-guard F]
Exit status 0, or 1 with a one-line error on stderr.
"""

import argparse
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))


def fail(message):
    print(f"plot_trace.py: error: {message}", file=sys.stderr)
    sys.exit(1)


try:
    import numpy as np
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
except ImportError as e:  # pragma: no cover
    fail(f"{e} (Debian: apt-get install python3-matplotlib; run with /usr/bin/python3)")

import termination_study as ts  # noqa: E402  (same folder)

# The criteria drawn: label -> (spec for ts.simulate_stop, colour, line style).
CRITERIA = [
    ("cost drop 1 % x 10", {"criteria": {"cost-drop"}}, "tab:red", "-"),
    ("cost drop 1 % x 20", {"criteria": {"cost-drop"}, "cd_patience": 20}, "tab:orange", "-"),
    ("MSE prev. /2 x 3", {"criteria": {"mse-prev"}}, "tab:blue", "-"),
    ("successful steps <= 1 x 3", {"criteria": {"successful-steps"}}, "tab:purple", "-"),
]


def signed_log(ax, x, values, colour):
    """|values| on a log axis: filled markers where the value is positive, hollow where it is
    negative (the magnitude is what tells when a quantity has stopped changing)."""
    v = np.asarray(values, dtype=float)
    mag = np.abs(v)
    mag[~(mag > 0)] = np.nan
    ax.plot(x, mag, "-", color=colour, lw=0.8, alpha=0.6)
    pos, neg = v > 0, v < 0
    ax.plot(x[pos], mag[pos], "o", color=colour, ms=2.5, lw=0)
    ax.plot(x[neg], mag[neg], "o", mfc="white", mec=colour, ms=3, mew=0.8, lw=0)
    ax.set_yscale("log")


def positive(values):
    v = np.asarray(values, dtype=float).copy()
    v[~(v > 0)] = np.nan  # log axes: drop zeros/negatives (drawn as gaps)
    return v


def main(argv):
    p = argparse.ArgumentParser(description="Plots a ppcr trace CSV like the paper's Figure 2.")
    p.add_argument("trace", metavar="TRACE.csv")
    p.add_argument("-o", "--out", help="output PNG (default: TRACE with .png)")
    p.add_argument("--title", help="figure title (default: the file name)")
    p.add_argument("--scale-mode", default="auto", choices=["auto", "em", "raw", "fixed"],
                   help="E-step scale mode of the run, for the settling bands and the replayed "
                        "criteria (auto: raw if every scale is 1, else em)")
    p.add_argument("--oracle-relative", type=float, default=0.1,
                   help="oracle ideal stop: relative tolerance on the ground-truth RMS "
                        "(default 0.1)")
    p.add_argument("--oracle-absolute", type=float, default=0.0,
                   help="oracle ideal stop: absolute tolerance, RMS in cloud units "
                        "(default 0)")
    p.add_argument("--radius", type=float, default=1.0,
                   help="the run's --radius (the motion guard is relative to it; default 1)")
    p.add_argument("--motion-guard", type=float, default=ts.DEFAULT_MOTION_GUARD,
                   help="the --motion-guard of the replayed cost-drop criteria (default "
                        f"{ts.DEFAULT_MOTION_GUARD}, the library's; 0 = the paper's rule)")
    p.add_argument("--dpi", type=int, default=72)
    a = p.parse_args(argv)
    out = a.out or (os.path.splitext(a.trace)[0] + ".png")
    if not out.lower().endswith(".png"):
        fail(f"{out}: the output must be a .png file")
    try:
        tr = ts.read_trace(a.trace)
        settling = ts.settling_mask(tr, a.scale_mode)
    except ts.StudyError as e:
        fail(str(e))

    it = tr["iteration"]
    n = len(it)
    gt = ts.has_ground_truth(tr)
    stops = []
    for label, spec, colour, style in CRITERIA:
        t, _ = ts.simulate_stop(tr, dict(spec, motion_guard=a.motion_guard), settling,
                                a.radius)
        if t is not None and t < n:
            stops.append((t, label, colour, style))
    stops.append((n, f"run stopped ({n})", "black", "-"))
    ideal = ts.oracle_stop(tr, a.oracle_relative, a.oracle_absolute) if gt else None
    if ideal is not None:
        stops.append((ideal, f"oracle ideal stop ({ideal})", "tab:green", "--"))

    fig, axes = plt.subplots(3, 3, figsize=(13, 9.5), sharex=True)
    ax = axes.ravel()

    def derivative(v):
        d = np.full(n, np.nan)
        d[1:] = np.diff(v)
        return d

    drop = tr["cost_drop"]
    mse = tr["mse_prev"]
    ax[0].plot(it, tr["successful_steps"], ".-", color="tab:gray", lw=1, ms=3)
    ax[0].set_title("successful LM steps")
    ax[1].plot(it, positive(tr["initial_cost"]), "-", lw=1.2, label="initial")
    ax[1].plot(it, positive(tr["final_cost"]), "--", lw=1.2, label="final")
    ax[1].set_yscale("log")
    ax[1].legend(fontsize=8, loc="upper right")
    ax[1].set_title("inner problem's cost")
    ax[2].plot(it, positive(tr["scale"]), "-", color="tab:brown", lw=1.2)
    ax[2].set_yscale("log")
    ax[2].set_title("E-step scale s (cloud units)")
    signed_log(ax[3], it, drop, "tab:red")
    ax[3].axhline(0.01, color="tab:red", lw=0.8, ls=":")
    ax[3].set_title("relative cost drop (initial - final) / initial")
    ax[4].plot(it, positive(mse), ".-", color="tab:blue", lw=1, ms=3)
    ax[4].text(0.98, 0.95, "0 not drawn", transform=ax[4].transAxes, ha="right", va="top",
               fontsize=7, color="gray") if np.any(mse == 0) else None
    ax[4].set_yscale("log")
    ax[4].set_title("MSE w.r.t. the previous iteration")
    signed_log(ax[6], it, derivative(drop), "tab:red")
    ax[6].set_title("|discrete derivative| of the cost drop")
    signed_log(ax[7], it, derivative(mse), "tab:blue")
    ax[7].set_title("|discrete derivative| of the MSE w.r.t. previous")
    if gt:
        g = tr["mse_ground_truth"]
        ax[5].plot(it, positive(g), ".-", color="tab:green", lw=1, ms=3)
        ax[5].set_yscale("log")
        ax[5].set_title("MSE w.r.t. the ground truth")
        be = tr.get("benchmark_error")
        if be is not None and np.all(np.isfinite(be)):
            ax[5].text(0.98, 0.95, f"benchmark error: first {be[0]:.3g}, last {be[-1]:.3g}",
                       transform=ax[5].transAxes, ha="right", va="top", fontsize=8)
        signed_log(ax[8], it, derivative(g), "tab:green")
        ax[8].set_title("|discrete derivative| of the MSE w.r.t. ground truth")
    else:
        for k in (5, 8):
            ax[k].text(0.5, 0.5, "no ground truth in this trace", ha="center", va="center",
                       transform=ax[k].transAxes, color="gray")
            ax[k].set_yticks([])
        ax[5].set_title("MSE w.r.t. the ground truth")
        ax[8].set_title("|discrete derivative| of the MSE w.r.t. ground truth")

    # settling bands and stop markers on every panel
    runs, start = [], None
    for i in range(n):
        if settling[i] and start is None:
            start = i
        if (not settling[i] or i == n - 1) and start is not None:
            runs.append((it[start] - 0.5, it[i if settling[i] else i - 1] + 0.5))
            start = None
    for a_ in ax:
        for lo, hi in runs:
            a_.axvspan(lo, hi, color="0.88", lw=0, zorder=0)
        for t, label, colour, style in stops:
            a_.axvline(t, color=colour, ls=style, lw=1.1, alpha=0.85)
        a_.grid(True, which="major", lw=0.3, alpha=0.5)
        a_.tick_params(labelsize=8)
        a_.title.set_fontsize(10)
    for k in (6, 7, 8):
        ax[k].set_xlabel("outer iteration")
    handles = [plt.Line2D([], [], color=c, ls=s, lw=1.5) for _, _, c, s in stops]
    labels = [f"{lab} ({t})" if not lab.endswith(")") else lab for t, lab, _, _ in stops]
    handles.append(plt.Rectangle((0, 0), 1, 1, color="0.88"))
    labels.append("scale settling (criteria not counting)")
    handles.append(plt.Line2D([], [], marker="o", mfc="white", mec="0.3", lw=0))
    labels.append("hollow marker: negative value (magnitude shown)")
    fig.legend(handles, labels, loc="lower center", ncol=min(len(labels), 4), fontsize=9,
               frameon=False)
    fig.suptitle(a.title or os.path.basename(a.trace), fontsize=12)
    fig.tight_layout(rect=(0, 0.06, 1, 0.97))
    try:
        fig.savefig(out, dpi=a.dpi)
    except OSError as e:
        fail(f"{out}: cannot write: {e.strerror or e}")
    print(out)
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
