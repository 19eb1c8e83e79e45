#!/usr/bin/env bash
# Installs, with apt-get, the Debian 12 packages ppcr needs that are missing.
# Usage: tools/install_deps.sh [demo|all] [extra packages...]
#   demo   what tools/demo.sh builds and runs: the compiler, the libraries, the tools' command-line
#          and JSON parsers, and the Python module's build (pybind11, Python's headers, numpy)
#   all    (the default) the demo's, and what the tests, fuzzers, benchmarks and plotting
#          scripts use: Catch2, pytest, Google Benchmark, clang with its fuzzer runtime, matplotlib,
#          GNU parallel (sharded benchmark runs)
set -euo pipefail
profile=all
if [[ ${1:-} == demo || ${1:-} == all ]]; then
  profile=$1
  shift
fi
packages=(cmake g++ make libeigen3-dev libnanoflann-dev libcli11-dev nlohmann-json3-dev
          liblzf-dev libpng-dev pybind11-dev python3-dev python3-numpy)
if [[ $profile == all ]]; then
  packages+=(catch2 python3-pytest libbenchmark-dev python3-matplotlib clang libclang-rt-14-dev
             python3-venv python3-pip python3-setuptools python3-wheel python3-build time
             parallel)
fi
packages+=("$@")
missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if ((${#missing[@]})); then
  echo "install_deps: installing ${missing[*]}"
  sudo_cmd=()
  [[ $(id -u) -ne 0 ]] && sudo_cmd=(sudo)
  "${sudo_cmd[@]}" apt-get update -qq
  DEBIAN_FRONTEND=noninteractive "${sudo_cmd[@]}" apt-get install -y -qq --no-install-recommends \
    "${missing[@]}"
fi
