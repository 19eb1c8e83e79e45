#!/usr/bin/env bash
# Builds the fuzzers (ppcr_io readers, ppcr::align) with clang, writes the seed corpus, and runs
# each target for a fixed time. The numbers in fuzz/README.md come from this script.
#   usage: fuzz/run_fuzzers.sh [seconds per target, default 120] [build folder, default build-fuzz]
#   PPCR_FUZZ_TARGETS="registration" limits the run to some targets (default: all five).
#   PPCR_FUZZ_FLAGS="-flag=value ..." adds libFuzzer flags to every run.
# Exits non-zero when a fuzzer is missing, fails (a crash: its input is in artifacts/), or runs no
# input; each fuzzer's whole output is in <build>/fuzz/logs/<target>.log.
# Crash inputs land in <build>/fuzz/artifacts/<target>/; the growing corpus in corpus/<target>/.
set -euo pipefail
here="$(cd "$(dirname "$0")" && pwd)"
root="$(dirname "$here")"
seconds="${1:-120}"
build="${2:-$root/build-fuzz}"

cmake -S "$root" -B "$build" -DCMAKE_CXX_COMPILER=clang++ -DCMAKE_BUILD_TYPE=RelWithDebInfo \
      -DPPCR_BUILD_FUZZERS=ON -DPPCR_BUILD_TESTS=OFF -DPPCR_BUILD_TOOLS=OFF
cmake --build "$build" -j2 --target ppcr_fuzzers fuzz_seed_corpus

cd "$build/fuzz"
for target in ${PPCR_FUZZ_TARGETS:-ply pcd xyz transform registration}; do
  mkdir -p "corpus/$target" "artifacts/$target" logs
  cp -n "seeds/$target/"* "corpus/$target/" || true  # keep what earlier runs found
  echo "== fuzz_$target for ${seconds}s"
  # -malloc_limit_mb: no input of at most 16 KiB may make the readers allocate 64 MB at once.
  # fuzz_registration: its input is a parameter block and at most 2 x 64 points (51 + 768
  # bytes); -timeout=10 s: a run is bounded by its caps (12 outer x 12 LM iterations).
  if [[ $target == registration ]]; then
    options=(-max_len=1024)
  else
    options=(-dict="$here/$target.dict" -max_len=16384)
  fi
  # The whole log is kept; the run fails when the fuzzer exits non-zero (a crash, a timeout, an
  # out-of-memory, a flag it cannot use), when it does not exist, or when it ends without running
  # any input (no "Done N runs" with N > 0).
  log="logs/$target.log"
  status=0
  [[ -x ./fuzz_$target ]] || { echo "fuzz: no fuzzer fuzz_$target in $build/fuzz" >&2; exit 1; }
  "./fuzz_$target" -max_total_time="$seconds" "${options[@]}" ${PPCR_FUZZ_FLAGS:-} \
      -artifact_prefix="artifacts/$target/" -print_final_stats=1 -rss_limit_mb=2048 \
      -malloc_limit_mb=64 -timeout=10 "corpus/$target" > "$log" 2>&1 || status=$?
  grep -E '^(Done|stat::number_of_executed_units|stat::peak_rss_mb)|ERROR|SUMMARY|invariant' "$log" || true
  runs=$(sed -n 's/^Done \([0-9][0-9]*\) runs.*/\1/p' "$log" | tail -1)
  # libFuzzer only warns about a flag it does not know: here that is a failure too.
  if grep -q "unrecognized flag" "$log"; then
    echo "fuzz: fuzz_$target was given a flag it does not know:" >&2
    grep "unrecognized flag" "$log" >&2
    exit 1
  fi
  if ((status != 0)) || [[ -z $runs ]] || ((runs == 0)); then
    echo "fuzz: fuzz_$target failed (exit $status, ${runs:-no} runs); the last lines of $build/fuzz/$log:" >&2
    tail -n 20 "$log" >&2
    exit 1
  fi
  echo "fuzz: fuzz_$target ran $runs inputs in ${seconds}s"
done
