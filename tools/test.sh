#!/usr/bin/env bash
# The whole test suite, from a fresh Debian 12 machine: installs what is missing, configures,
# builds and runs every test. `.ci/run` calls exactly this.
#   tools/test.sh            the default stages: release, sanitize, fuzz, fma
#   PPCR_TEST_STAGES="release" tools/test.sh    only some stages (release, sanitize, fuzz, fma)
#   PPCR_TEST_STAGES="nanoflann-next" tools/test.sh   the release build against Debian 13's
#                                                      nanoflann (downloads it; not a default)
# Every test runs in the release stage, the real-scan ones included, and the Python module's
# (pytest, label python) where python/cmake_flags.sh finds what it needs for /usr/bin/python3 (or
# $PPCR_PYTHON). The sanitize stage runs the library's tests that need no real data (the
# real-scan cases exercise the same code on bigger clouds, already run once; the tools' code is
# fuzzed through the readers and parsed in release); the fma stage the core's and readers' tests
# (the exact equalities); the fuzz stage runs each fuzzer for a bounded time.
# Real-scan tests read ../shared/data (or $PPCR_DATA_DIR) and are skipped when it is absent.
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
cd "$root"
"$root/tools/install_deps.sh"
jobs=${PPCR_JOBS:-2}
stages=${PPCR_TEST_STAGES:-release sanitize fuzz fma}

# build_and_test DIR BUILD_TYPE CTEST_ARGS [cmake arguments...]: configures the tests (and the
# tools, unless an argument turns them off) in DIR, builds them and runs the tests ctest selects
# with CTEST_ARGS (a string).
build_and_test() {
  local dir=$1 build_type=$2 ctest_args=$3
  shift 3
  cmake -S . -B "$dir" -DCMAKE_BUILD_TYPE="$build_type" -DPPCR_BUILD_TESTS=ON \
    -DPPCR_BUILD_TOOLS=ON "$@"
  cmake --build "$dir" -j "$jobs"
  # shellcheck disable=SC2086
  ctest --test-dir "$dir" --output-on-failure -j "$jobs" $ctest_args
}

for stage in $stages; do
  start=$SECONDS
  case $stage in
    release)
      echo "== release: build and run all tests"
      # shellcheck disable=SC2046
      build_and_test build/test-release Release "" -DPPCR_BUILD_BENCHMARKS=ON \
        $("$root/python/cmake_flags.sh")
      ;;
    sanitize)
      echo "== sanitize: the tests without real data under AddressSanitizer + UndefinedBehaviorSanitizer"
      ASAN_OPTIONS=detect_leaks=1:abort_on_error=1 UBSAN_OPTIONS=print_stacktrace=1 \
        build_and_test build/test-asan RelWithDebInfo "-LE real_data" -DPPCR_SANITIZE=ON \
          -DPPCR_BUILD_TOOLS=OFF
      ;;
    fuzz)
      echo "== fuzz: bounded libFuzzer runs (clang, ASan + UBSan), ${PPCR_FUZZ_SECONDS:-30} s per target"
      rm -rf build/test-fuzz/fuzz/artifacts
      fuzz/run_fuzzers.sh "${PPCR_FUZZ_SECONDS:-30}" "$root/build/test-fuzz"
      if [[ -n $(find build/test-fuzz/fuzz/artifacts -type f 2>/dev/null) ]]; then
        echo "fuzz: crash inputs found:" >&2
        find build/test-fuzz/fuzz/artifacts -type f >&2
        exit 1
      fi
      ;;
    fma)
      # The release build with fused multiply-adds in the instruction set (-march=haswell), where
      # the CPU runs it: the exact equalities must hold there too (docs/RELIABILITY.md, F7).
      # -march=haswell lets GCC emit these extensions' instructions: all must be there.
      missing=""
      for flag in fma avx2 bmi1 bmi2 movbe f16c abm popcnt; do
        grep -qw "$flag" /proc/cpuinfo 2>/dev/null || missing="$missing $flag"
      done
      if [[ -z $missing ]]; then
        echo "== fma: build with -march=haswell and run the tests without real data"
        build_and_test build/test-fma Release "-LE real_data" -DCMAKE_CXX_FLAGS=-march=haswell \
          -DPPCR_BUILD_TOOLS=OFF -DPPCR_BUILD_SYNTHETIC=OFF
      else
        echo "== fma: skipped, not an x86-64 CPU with Haswell's extensions (missing:$missing)"
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
      build_and_test build/test-nanoflann-next Release "" -Dnanoflann_DIR="$config"
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
      echo "test.sh: unknown stage '$stage' (expected release, sanitize, fuzz, fma, nanoflann-next)" >&2
      exit 2
      ;;
  esac
  echo "== $stage: $((SECONDS - start)) s"
done
echo "== all test stages passed: $stages"
