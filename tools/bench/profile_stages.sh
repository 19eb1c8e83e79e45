#!/usr/bin/env bash
# Where ppcr's time goes, per stage (docs/PERFORMANCE.md, "Where the time goes"): profiles three
# workloads at one thread with perf (cpu-clock, DWARF call graphs) and prints the stages' shares
# of ppcr's time as one Markdown table, a column per workload:
#   bunny       ppcr_bench on the first 10 bunny problems, the protocol of protocol.txt
#   lidar       the same on the first 10 lidar problems
#   lidar-full  ppcr_cli on the full-resolution LiDAR pair, radius 1
# The stages and how samples are assigned to them: profile_stages.py.
#
#   tools/bench/profile_stages.sh [BUILD_DIR] [OUT_DIR]   (defaults: build/release, build/profile)
#
# BUILD_DIR: a Release build with tools; configured with -DCMAKE_CXX_FLAGS=-g (debug information,
# the same code) the E-step is told apart inside the plane pass, else it counts there. Needs perf,
# python3 and ../shared/data (or $PPCR_DATA_DIR). OUT_DIR keeps perf's data and each workload's
# JSON; the table goes to stdout. PROFILE_LIMIT=10 sets the problems per set.
set -euo pipefail
root=$(cd "$(dirname "$0")/../.." && pwd)
# shellcheck source=protocol.sh
source "$root/tools/bench/protocol.sh"
build=${1:-$root/build/release}
out=${2:-$root/build/profile}
data=${PPCR_DATA_DIR:-$root/../shared/data}
limit=${PROFILE_LIMIT:-10}
bench=$build/tools/bench/ppcr_bench
cli=$build/tools/ppcr_cli
for exe in "$bench" "$cli"; do
  [[ -x $exe ]] || { echo "profile_stages.sh: $exe not found (build $build with tools)" >&2; exit 1; }
done
command -v perf > /dev/null || { echo "profile_stages.sh: perf not found" >&2; exit 1; }
[[ -d $data/benchmark ]] || { echo "profile_stages.sh: $data/benchmark not found" >&2; exit 1; }
mkdir -p "$out"

# profile NAME COMMAND...: records COMMAND, then writes OUT/NAME.json (profile_stages.py). The
# stack copy is perf's largest: with its default 8 KiB most of the plane pass's samples lose
# their chain and would count as outside ppcr.
profile() {
  local name=$1
  shift
  echo "== $name: $*" >&2
  local status=0
  perf record -q -e cpu-clock -F 2000 --call-graph dwarf,65528 -o "$out/$name.data" -- "$@" \
    > /dev/null || status=$?
  # 3: ppcr_cli's registration ran to its end and its verdict was "failed"; the time is spent.
  if [[ $status -ne 0 && $status -ne 3 ]]; then
    echo "profile_stages.sh: $name: exit status $status" >&2
    exit 1
  fi
  perf script -F comm,tid,time,ip,sym,srcline -i "$out/$name.data" 2> /dev/null |
    python3 "$root/tools/bench/profile_stages.py" --label "$name" > "$out/$name.json"
}

for set in bunny lidar; do
  # shellcheck disable=SC2046  # the protocol's options are words
  profile "$set" "$bench" "$data/benchmark/${set}_local.txt" $(bench_protocol "$set") \
    --threads 1 --limit "$limit" --quiet
done
profile lidar-full "$cli" "$data/lidar/source.ply" "$data/lidar/target.ply" --radius 1 \
  --threads 1 --json --quiet
python3 "$root/tools/bench/profile_stages.py" --table "$out"/{bunny,lidar,lidar-full}.json
