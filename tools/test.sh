#!/usr/bin/env bash
# The whole test suite, from a fresh Debian 12 machine: installs what is missing, configures,
# builds and runs every test. `.ci/run` calls exactly this.
#   tools/test.sh            the default stages: release, minimal, sanitize, fuzz, fma
#   PPCR_TEST_STAGES="release" tools/test.sh    only some stages
#   PPCR_TEST_STAGES="nanoflann-next" tools/test.sh   the release build against Debian 13's
#                                                      nanoflann (downloads it; not a default)
# Every test runs in the release stage, the real-scan ones included, and the Python module's
# (pytest, label python) where python/cmake_flags.sh finds what it needs for /usr/bin/python3 (or
# $PPCR_PYTHON). The sanitize stage runs the library's tests that need no real data (the
# real-scan cases exercise the same code on bigger clouds, already run once; the tools' code is
# fuzzed through the readers and parsed in release); the fma stage the core's and readers' tests
# (the exact equalities); the fuzz stage runs each fuzzer for a bounded time. The minimal stage
# builds the core as an embedded build would vendor it (-fno-exceptions -fno-rtti, no OpenMP, no
# I/O) and runs the core's and reliability tests against it, the real-scan ones included.
# Real-scan tests read ../shared/data (or $PPCR_DATA_DIR) and are skipped when it is absent.
# Strict mode (CI=true, as in CI, or PPCR_STRICT=1): nothing may be skipped. Missing real data,
# a Python module or pytest that cannot be had, a fuzzer that does not run and a CPU-flag check
# that cannot read the flags fail the run. After each stage's ctest, tools/check_test_run.py checks
# that every Catch test case has its own ctest entry and that every selected test ran; each stage
# ends with one summary line, and the run with all of them and a total.
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
cd "$root"
"$root/tools/install_deps.sh"
jobs=${PPCR_JOBS:-2}
stages=${PPCR_TEST_STAGES:-release minimal sanitize fuzz fma}
strict=0
if [[ ${CI:-} == true || ${PPCR_STRICT:-} == 1 ]]; then
  strict=1
  export PPCR_STRICT=1  # the tests' own switch (tests/test_data.hpp, python/tests/conftest.py)
fi
summaries=()
totals=(0 0 0 0)  # run, passed, failed, skipped

# fail_strict MESSAGE: in strict mode, MESSAGE is an error; otherwise a warning.
fail_strict() {
  if ((strict)); then
    echo "test.sh: $1 (CI=true or PPCR_STRICT=1: this is a failure, not a skip)" >&2
    exit 1
  fi
  echo "test.sh: warning: $1" >&2
}

# build_and_test STAGE DIR BUILD_TYPE CTEST_ARGS [cmake arguments...]: configures the tests (and
# the tools, unless an argument turns them off) in DIR, builds them, runs the tests ctest selects
# with CTEST_ARGS (a string), then checks the run (tools/check_test_run.py) and records the
# stage's summary line.
build_and_test() {
  local stage=$1 dir=$2 build_type=$3 ctest_args=$4
  shift 4
  local -a required=()
  [[ $stage == release && $strict == 1 ]] && required=(--require-label python)
  cmake -S . -B "$dir" -DCMAKE_BUILD_TYPE="$build_type" -DPPCR_BUILD_TESTS=ON \
    -DPPCR_BUILD_TOOLS=ON "$@"
  cmake --build "$dir" -j "$jobs"
  rm -f "$dir/ctest-junit.xml"
  local rc=0 check=0
  # shellcheck disable=SC2086
  ctest --test-dir "$dir" --output-on-failure -j "$jobs" --output-junit "$root/$dir/ctest-junit.xml" \
    $ctest_args || rc=$?
  local -a strict_flag=()
  ((strict)) && strict_flag=(--strict)
  # shellcheck disable=SC2086
  python3 "$root/tools/check_test_run.py" "$dir" "$root/$dir/ctest-junit.xml" "$stage" \
    "$((SECONDS - start))" "${strict_flag[@]}" "${required[@]}" --counts "$dir/ctest-counts" \
    -- $ctest_args > "$dir/ctest-summary" || check=$?
  cat "$dir/ctest-summary"
  summaries+=("$(cat "$dir/ctest-summary")")
  local run passed failed skipped
  read -r run passed failed skipped < "$dir/ctest-counts"
  totals=($((totals[0] + run)) $((totals[1] + passed)) $((totals[2] + failed)) \
          $((totals[3] + skipped)))
  if ((rc != 0 || check != 0)); then
    echo "test.sh: stage $stage failed (ctest exit $rc, run check exit $check)" >&2
    exit 1
  fi
}

if ((strict)) && [[ " $stages " == *" release "* ]]; then
  data=${PPCR_DATA_DIR:-$(cd "$root/.." && pwd)/shared/data}
  [[ -d $data ]] || fail_strict "the real-scan data folder $data is missing (set PPCR_DATA_DIR)"
fi

for stage in $stages; do
  start=$SECONDS
  case $stage in
    release)
      echo "== release: build and run all tests"
      python_flags=$("$root/python/cmake_flags.sh")
      [[ -n $python_flags ]] || fail_strict "the Python module cannot be built (python/cmake_flags.sh said why above)"
      "${PPCR_PYTHON:-/usr/bin/python3}" -c "import pytest" 2>/dev/null ||
        fail_strict "${PPCR_PYTHON:-/usr/bin/python3} has no pytest (Debian: python3-pytest)"
      # shellcheck disable=SC2086
      build_and_test release build/test-release Release "" -DPPCR_BUILD_BENCHMARKS=ON \
        $python_flags
      ;;
    minimal)
      echo "== minimal: the core with -fno-exceptions -fno-rtti, without OpenMP and I/O, and its tests"
      build_and_test minimal build/test-minimal Release "" \
        "-DCMAKE_CXX_FLAGS=-fno-exceptions -fno-rtti" -DPPCR_USE_OPENMP=OFF -DPPCR_BUILD_IO=OFF \
        -DPPCR_BUILD_TOOLS=OFF -DPPCR_BUILD_SYNTHETIC=OFF -DPPCR_INSTALL=OFF
      if nm -A build/test-minimal/libppcr.a | grep -E ' U (GOMP_|omp_|pthread_create)'; then
        echo "test.sh: the minimal core links OpenMP or threads (symbols above)" >&2
        exit 1
      fi
      ;;
    sanitize)
      echo "== sanitize: the tests without real data under AddressSanitizer + UndefinedBehaviorSanitizer"
      # -O1 -g1 (line tables only): the sanitizers' recommended level, and the stage's build is
      # most of its time.
      ASAN_OPTIONS=detect_leaks=1:abort_on_error=1 UBSAN_OPTIONS=print_stacktrace=1 \
        build_and_test sanitize build/test-asan RelWithDebInfo "-LE real_data" -DPPCR_SANITIZE=ON \
          -DPPCR_BUILD_TOOLS=OFF "-DCMAKE_CXX_FLAGS_RELWITHDEBINFO=-O1 -g1 -DNDEBUG"
      ;;
    fuzz)
      echo "== fuzz: bounded libFuzzer runs (clang, ASan + UBSan), ${PPCR_FUZZ_SECONDS:-30} s per target"
      rm -rf build/test-fuzz/fuzz/artifacts build/test-fuzz/fuzz/logs
      fuzz/run_fuzzers.sh "${PPCR_FUZZ_SECONDS:-30}" "$root/build/test-fuzz"
      if [[ -n $(find build/test-fuzz/fuzz/artifacts -type f 2>/dev/null) ]]; then
        echo "fuzz: crash inputs found:" >&2
        find build/test-fuzz/fuzz/artifacts -type f >&2
        exit 1
      fi
      fuzzers=$(find build/test-fuzz/fuzz/logs -name '*.log' | wc -l)
      inputs=$(cat build/test-fuzz/fuzz/logs/*.log | sed -n 's/^Done \([0-9]*\) runs.*/\1/p' |
               awk '{ n += $1 } END { print n + 0 }')
      summaries+=("== fuzz: $fuzzers fuzzers ran $inputs inputs, no crash, $((SECONDS - start)) s")
      echo "${summaries[-1]}"
      ;;
    fma)
      # The release build with fused multiply-adds in the instruction set (-march=haswell), where
      # the CPU runs it: the exact equalities must hold there too (docs/RELIABILITY.md, F7).
      # -march=haswell lets GCC emit these extensions' instructions: all must be there.
      missing=""
      if [[ ! -r /proc/cpuinfo ]] || ! grep -q '^flags' /proc/cpuinfo; then
        fail_strict "fma: the CPU's flags cannot be read from /proc/cpuinfo"
        missing=" (unreadable /proc/cpuinfo)"
      else
        for flag in fma avx2 bmi1 bmi2 movbe f16c abm popcnt; do
          grep -qw "$flag" /proc/cpuinfo || missing="$missing $flag"
        done
      fi
      if [[ -z $missing ]]; then
        echo "== fma: build with -march=haswell and run the tests without real data"
        build_and_test fma build/test-fma Release "-LE real_data" -DCMAKE_CXX_FLAGS=-march=haswell \
          -DPPCR_BUILD_TOOLS=OFF -DPPCR_BUILD_SYNTHETIC=OFF
      else
        summaries+=("== fma: skipped, not an x86-64 CPU with Haswell's extensions (missing:$missing)")
        echo "${summaries[-1]}"
      fi
      ;;
    nanoflann-next)
      # Not in the default stages (it downloads): the release build against Debian 13's
      # nanoflann (1.7.1 when written), unpacked under build/, instead of the system's 1.4.3.
      # nanoflann is the k-d tree test's reference (and ppcr_synth's), not the library's.
      echo "== nanoflann-next: build and run all tests against Debian 13's nanoflann"
      "$root/tools/install_deps.sh" curl ca-certificates
      config=$("$root/tools/fetch_nanoflann_debian13.sh" "$root/build/nanoflann-debian13")
      header="$root/build/nanoflann-debian13/root/usr/include/nanoflann.hpp"
      version=$(sed -n '/^#define NANOFLANN_VERSION 0x/{s/.*0x\([0-9a-fA-F]*\).*/\1/p;q}' "$header")
      if [[ -z $version ]] || ((16#$version < 16#150)); then
        echo "test.sh: $header is nanoflann 0x$version, not 1.5 or newer" >&2
        exit 1
      fi
      # Makefiles, here and in the consumer projects ctest builds: their per-object dependency
      # files tell which nanoflann.hpp was compiled in.
      export CMAKE_GENERATOR="Unix Makefiles"
      build_and_test nanoflann-next build/test-nanoflann-next Release "" -Dnanoflann_DIR="$config"
      # After ctest, which also builds the consumer projects (tests/consumer).
      kdtree_test=build/test-nanoflann-next/tests/core/CMakeFiles/ppcr_core_kdtree_test.dir
      if ! grep -qF "$header" "$kdtree_test/test_kdtree.cpp.o.d" ||
         grep -rlE --include='*.d' '(^|[[:space:]])/usr/include/nanoflann\.hpp' \
           build/test-nanoflann-next >&2; then
        echo "test.sh: not every nanoflann user was compiled against $header (files above)" >&2
        exit 1
      fi
      ;;
    *)
      echo "test.sh: unknown stage '$stage' (expected release, minimal, sanitize, fuzz, fma, nanoflann-next)" >&2
      exit 2
      ;;
  esac
done
echo
echo "== summary of the stages: $stages"
printf '%s\n' "${summaries[@]}"
echo "total: ${totals[1]} passed, ${totals[2]} failed, ${totals[3]} skipped"
