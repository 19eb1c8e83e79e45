# protocol.sh - sourced by run_all.sh and perf.sh: bench_protocol SET prints the ppcr_bench
# options of SET from tools/bench/protocol.txt (the one definition of the benchmark protocol),
# or fails with a message naming the set.
bench_protocol() {
  local file line
  file="$(dirname "${BASH_SOURCE[0]}")/protocol.txt"
  line=$(grep -m1 "^$1 " "$file") ||
    { echo "no benchmark protocol for set '$1' in $file" >&2; return 1; }
  echo "${line#"$1" }"
}
