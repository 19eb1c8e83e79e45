#!/usr/bin/env bash
# Installs, with apt-get, the Debian 12 packages ppcr needs that are missing (build, tests,
# tools, benchmarks). Usage: tools/install_deps.sh [extra packages...]
set -euo pipefail
packages=(cmake g++ make libeigen3-dev libnanoflann-dev catch2 libcli11-dev nlohmann-json3-dev
          liblzf-dev libbenchmark-dev python3-matplotlib python3-numpy clang libclang-rt-14-dev
          "$@")
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
