#!/usr/bin/env python3
"""tools/bench/profile_stages.py on a `perf script` text made by hand: every sample's stage is
known from its call chain, so the shares are exact fractions.

Usage: test_profile_stages.py PROFILE_STAGES_PY. Exit 0 passed, 1 failed.
"""
import json
import subprocess
import sys

NS = "ppcr::eigen_align16_heap16::"
CLOUD = "std::vector<Eigen::Matrix<double, 3, 1, 0, 3, 1>, std::allocator<Eigen::Matrix<double, " \
        "3, 1, 0, 3, 1> > > const&"
ALIGN = f"{NS}align({CLOUD}, {CLOUD}, {NS}RegistrationOptions const&, Eigen::Transform<double, " \
        "3, 1, 0> const&)"
SET_TARGET = f"{NS}Registration::set_target({CLOUD})"
REG_ALIGN = f"{NS}Registration::align({CLOUD}, Eigen::Transform<double, 3, 1, 0> const&)"
KD = [f"{NS}detail::KdTree::radius_knn(Eigen::Matrix<double, 3, 1, 0, 3, 1> const&, int, "
      "double, unsigned int*, double*) const",
      "bool nanoflann::KDTreeSingleIndexAdaptor<nanoflann::L2_Simple_Adaptor<double, "
      f"{NS}detail::(anonymous namespace)::CloudAdaptor, double, unsigned int>, "
      f"{NS}detail::(anonymous namespace)::CloudAdaptor, 3, unsigned int>::searchLevel<"
      f"{NS}detail::RadiusKnnResultSet>({NS}detail::RadiusKnnResultSet&, double const*, "
      "nanoflann::KDTreeBaseClass<...>::Node*, double, std::array<double, 3ul>&, float) const"]
FIND = f"{NS}detail::Associator::find(bool, Eigen::Transform<double, 3, 1, 0> const&)"
SOLVE = f"{NS}detail::LMSolver::solve({NS}LMOptions const&, {NS}detail::LMProblem const&, " \
        "Eigen::Transform<double, 3, 1, 0>*)"
PASS = f"void {NS}detail::NormalEquations::pass<true, false, {NS}detail::with_weight_kernel<" \
       f"false, {NS}detail::NormalEquations::evaluate(int)::{{lambda(auto:1 const&)#2}}>>(" \
       "int)::{lambda(long)#1}::operator()(long) const [clone ._omp_fn.0]"
ROOT = ["_start", "__libc_start_main_impl", "main"]

# (call chain from the root, the leaf's source line, its stage or None for outside ppcr).
SAMPLES = [
    (ROOT + [ALIGN, SET_TARGET, f"{NS}detail::compute_normals({CLOUD})"] + KD, "nanoflann.hpp:1745",
     "normals and information matrices"),
    (ROOT + [ALIGN, REG_ALIGN, FIND, f"{NS}detail::associate_cached({CLOUD})"] + KD,
     "nanoflann.hpp:1745", "search (k-d tree, neighbour cache, association)"),
    # The pair normals, formed in the plane pass with source normals, count as the pass.
    (ROOT + [ALIGN, REG_ALIGN, SOLVE, PASS.replace("pass<true, false,", "pass<true, true,"),
             f"{NS}detail::pair_normals_of_point(Eigen::Matrix<double, 3, 1, 0, 3, 1> const&, "
             f"unsigned int const*, unsigned long, {NS}detail::PlanePoint const*, "
             f"{NS}detail::PairNormal*)"],
     "pair_normals.cpp:40", "normal equations (plane pass)"),
    (ROOT + [ALIGN, REG_ALIGN, SOLVE, PASS], "e_step_kernel.hpp:40", "E-step (weights)"),
    # The weight kernel inlined into the pass (perf names inlined frames without their
    # parameters), its leaf an intrinsic's header.
    (ROOT + [ALIGN, REG_ALIGN, SOLVE, PASS,
             f"{NS}detail::student_t_weights<false, {NS}detail::PowerDyadic>", "_mm_sqrt_pd"],
     "emmintrin.h:800 (inlined)", "E-step (weights)"),
    (ROOT + [ALIGN, REG_ALIGN, SOLVE, PASS], "normal_equations.cpp:150",
     "normal equations (plane pass)"),
    (ROOT + [ALIGN, REG_ALIGN, SOLVE], "lm_solver.cpp:80", "LM and outer-loop bookkeeping"),
    (ROOT + [f"{NS}voxel_downsample({CLOUD}, double, {CLOUD}*)"], "voxel.cpp:20", None),
    (ROOT + [ALIGN, REG_ALIGN, f"{NS}detail::measure_alignment(int)"] + KD, "nanoflann.hpp:1745",
     "quality measures"),
    (ROOT + [ALIGN, SET_TARGET, f"{NS}detail::median_spacing({CLOUD})"] + KD, "nanoflann.hpp:1745",
     "set-up (tree, preparation, spacing)"),
    # The spacing is set-up in set_target, but a quality measure inside measure_alignment.
    (ROOT + [ALIGN, REG_ALIGN, f"{NS}detail::measure_alignment(int)",
             f"{NS}detail::median_spacing({CLOUD})"] + KD, "nanoflann.hpp:1745", "quality measures"),
    (ROOT + [ALIGN, REG_ALIGN, f"{NS}Registration::Impl::start(int)",
             f"{NS}detail::LMSolver::resize(unsigned long, int)", "__memset_avx2_unaligned"],
     "memset.S:10", "set-up (tree, preparation, spacing)"),
    (ROOT + [ALIGN, REG_ALIGN], "registration.cpp:320", "LM and outer-loop bookkeeping"),
]


def perf_script_text():
    """The samples as `perf script -F comm,tid,time,ip,sym,srcline` prints them."""
    out = []
    for k, (chain, srcline, _) in enumerate(SAMPLES):
        out.append(f"ppcr_bench 100 {k}.000000: ")
        for depth, frame in enumerate(reversed(chain)):  # the leaf first
            offset = f"+0x1{'f' * (depth % 2)}" if frame.endswith((")", "const")) else ""
            out.append(f"\t    {0x1000 + depth:x} {frame}{offset}")
            out.append(f"  {srcline if depth == 0 else 'registration.cpp:1'}")
        out.append("")
    return "\n".join(out) + "\n"


def main():
    result = subprocess.run([sys.executable, sys.argv[1], "--label", "hand"],
                            input=perf_script_text(), capture_output=True, text=True, check=True)
    got = json.loads(result.stdout)
    inside = [s for s in SAMPLES if s[2] is not None]
    errors = []
    if got["samples"] != len(SAMPLES) or got["ppcr_samples"] != len(inside):
        errors.append(f"samples {got['samples']} / {got['ppcr_samples']}, expected "
                      f"{len(SAMPLES)} / {len(inside)}")
    for stage, share in got["stages"].items():
        want = 100.0 * sum(s[2] == stage for s in inside) / len(inside)
        if abs(share - want) > 1e-9:
            errors.append(f"{stage}: {share} %, expected {want} %")
    kd = 100.0 * sum(KD[1] in s[0] for s in inside) / len(inside)
    if abs(got["kd_search_all_callers"] - kd) > 1e-9:
        errors.append(f"k-d search {got['kd_search_all_callers']} %, expected {kd} %")
    if abs(sum(got["stages"].values()) - 100.0) > 1e-9:
        errors.append(f"the stages add up to {sum(got['stages'].values())} %")
    for e in errors:
        print("FAIL: " + e, file=sys.stderr)
    if not errors:
        print(f"PASS: {len(SAMPLES)} hand-made samples, every stage's share exact")
    return 1 if errors else 0


if __name__ == "__main__":
    sys.exit(main())
