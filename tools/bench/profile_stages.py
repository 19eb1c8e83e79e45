#!/usr/bin/env python3
"""Where ppcr's time goes, per stage, from `perf script` output of a call-graph profile.

  perf script -F comm,tid,time,ip,sym,srcline -i perf.data | profile_stages.py [--label NAME]
  profile_stages.py --table A.json B.json ...   (the workloads' shares as one Markdown table)

Each sample's call chain is read from the root toward the leaf: the first frame that names a
stage of its own (the normal fits, the plane pass, the quality measures, ...) decides the
sample's stage, so the stages split ppcr's time and add up to 100 %; a frame that only contains
stages (the association, the LM solver, set_target) gives its stage to the samples that reach no
stage inside it: the pair normals, formed in the plane pass, count as the pass, the k-d queries
of the normal fits as normals, those of the association as search. Inside the plane
pass, which computes the E-step's weights as it goes, a sample is the E-step's when a frame below
the pass is the weight kernel's (the kernel is inlined: perf shows it from the debug information
of a build with -g) or its leaf's source line is in e_step_kernel.hpp. ppcr's time is the
samples under ppcr::align, Registration::set_target or Registration::align; the rest (reading
files, the bench's own filtering and evaluation) is reported as outside. Prints one JSON object:
samples, ppcr_samples, and per stage its share of ppcr's samples, plus the k-d search's share
over all callers (inside the stages); --table puts such objects side by side. Standard library
only.
"""
import argparse
import json
import re
import sys

NS = r"ppcr::(?:\w+::)*"
# (stage, pattern on the frame's name without template arguments and parameters, specific).
# Specific: the first such frame from the root decides. Container: taken when nothing inside
# is specific.
RULES = [
    ("quality measures", r"measure_alignment|degenerate_directions|normal_information"
     r"|detail::judge$", True),
    ("filtering (voxel)", r"voxel_downsample", True),
    ("normals and information matrices", r"compute_normals|fit_normal"
     r"|pack_plane_points|surface_noise", True),
    ("search (k-d tree, neighbour cache, association)", r"Associator::|associate_cached"
     r"|detail::associate$|NeighbourCache::|spread_lists|AssociationTable::", False),
    ("normal equations (plane pass)", r"NormalEquations::(evaluate|pass)", True),
    ("E-step (weights)", r"compute_weights|student_t_weights|gaussian_weights", True),
    ("LM and outer-loop bookkeeping", r"LMSolver::solve", False),
    ("set-up (tree, preparation, spacing)", r"Registration::set_target|prepare_source"
     r"|prepare_cloud|spatial_sort|KdTree::build|median_spacing|Registration::Impl::start", False),
    # Anything else under align (the loop itself) falls back to "LM and outer-loop bookkeeping".
]
STAGES = [r[0] for r in RULES]
COMPILED = [(stage, re.compile(NS + r"(?:\w+::)*(?:" + p + ")"), specific)
            for stage, p, specific in RULES]
ENTRY = re.compile(r"^" + NS + r"(align|Registration::set_target|Registration::align)$")
KD_SEARCH = re.compile(NS + r"detail::KdTree::radius_knn$")  # nanoflann's search runs under it
E_STEP_FILE = "e_step_kernel.hpp"
E_STEP = next(pattern for stage, pattern, _ in COMPILED if stage.startswith("E-step"))


def base_name(symbol):
    """The function's qualified name: no return type, template arguments, parameters, clones."""
    s = re.sub(r"\s*\[clone [^\]]*\]", "", symbol)
    s = re.sub(r"\+0x[0-9a-f]+$", "", s)
    for opening, closing in (("<", ">"), ("(", ")")):
        out, depth = [], 0
        for c in s:
            if c == opening:
                depth += 1
            elif c == closing and depth > 0:
                depth -= 1
            elif depth == 0:
                out.append(c)
        s = "".join(out)
    s = re.sub(r" const$", "", s.strip())
    return s.split(" ")[-1]  # drop a return type


def classify(frames, leaf_srcline):
    """Stage of one sample; frames root first (base names). None: outside ppcr's calls."""
    inside = False
    container = None
    for depth, name in enumerate(frames):
        if not inside:
            inside = bool(ENTRY.match(name))
            if not inside:
                continue
        for stage, pattern, specific in COMPILED:
            if pattern.search(name):
                if specific:
                    if stage.startswith("normal equations") and (
                            E_STEP_FILE in leaf_srcline or
                            any(E_STEP.search(f) for f in frames[depth + 1:])):
                        return "E-step (weights)"
                    return stage
                container = stage
                break
    if not inside:
        return None
    return container or "LM and outer-loop bookkeeping"


def read_samples(stream):
    """Yields (frames root first, srcline of the leaf) per sample of `perf script`."""
    frames, srcline, in_sample = [], "", False
    for line in stream:
        if not line.strip():
            if in_sample:
                yield list(reversed(frames)), srcline
            frames, srcline, in_sample = [], "", False
            continue
        if not line[0].isspace():  # the sample's header
            in_sample = True
            continue
        text = line.strip()
        m = re.match(r"^([0-9a-f]+) (.*)$", text) if line.startswith("\t") else None
        if m:
            frames.append(base_name(re.sub(r" \([^()]*\)$", "", m.group(2))))
        elif len(frames) == 1 and not srcline:
            srcline = text  # the leaf's source line, printed under it (-F srcline)
    if in_sample:
        yield list(reversed(frames)), srcline


def print_table(paths):
    """One Markdown table: a row per stage, a column per workload (its JSON from a run above)."""
    runs = [json.load(open(p)) for p in paths]
    print("| stage | " + " | ".join(r["label"] for r in runs) + " |")
    print("|---|" + "---:|" * len(runs))
    for stage in STAGES:
        print(f"| {stage} | " + " | ".join(f"{r['stages'][stage]:.1f} %" for r in runs) + " |")
    print("| k-d search, every caller (inside the rows above) | " +
          " | ".join(f"{r['kd_search_all_callers']:.1f} %" for r in runs) + " |")
    print("| samples in ppcr's calls (of all) | " +
          " | ".join(f"{r['ppcr_samples']} ({100.0 * r['ppcr_samples'] / r['samples']:.0f} %)"
                     for r in runs) + " |")


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--label", default="", help="the workload's name in the output")
    parser.add_argument("--table", nargs="+", metavar="JSON", help="print these runs' table")
    args = parser.parse_args()
    if args.table:
        print_table(args.table)
        return
    counts = {s: 0 for s in STAGES}
    total = ppcr = kd = 0
    for frames, srcline in read_samples(sys.stdin):
        total += 1
        stage = classify(frames, srcline)
        if stage is None:
            continue
        ppcr += 1
        counts[stage] += 1
        kd += any(KD_SEARCH.search(f) for f in frames)
    if ppcr == 0:
        sys.exit("profile_stages.py: no sample under ppcr::align or Registration (no call "
                 "graph? record with --call-graph dwarf)")
    share = {s: 100.0 * c / ppcr for s, c in counts.items()}
    print(json.dumps({"label": args.label, "samples": total, "ppcr_samples": ppcr,
                      "stages": share, "kd_search_all_callers": 100.0 * kd / ppcr}))


if __name__ == "__main__":
    main()
