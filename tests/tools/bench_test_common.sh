# shellcheck shell=bash
# bench_test_common.sh - sourced by ppcr_bench's script tests: failing, checking a refusal, and
# the small synthetic problem set they run on. Needs $work (the test's folder) set.
# shellcheck disable=SC2154  # $work: set by the test that sources this file

fail() {
  echo "FAIL: $*" >&2
  exit 1
}

# make_problems SYNTH DIR: 10 problems of a small pair rendered by ppcr_synth in DIR (starts up to
# 35 degrees off: most problems succeed, some do not); prints the problem file's path.
make_problems() {
  "$1" "$2" --scene objects --sensor camera --beams 48 --steps 64 --problems 10 --seed 3 \
    --max-problem-rotation 35 --max-problem-translation 0.05 > /dev/null
  echo "$2/problems.txt"
}

# expect_error STATUS MESSAGE_PART COMMAND...: COMMAND exits STATUS, says MESSAGE_PART on stderr
# and prints nothing on stdout.
expect_error() {
  local want=$1 part=$2 status=0
  shift 2
  "$@" > "$work/out.txt" 2> "$work/err.txt" || status=$?
  [[ $status -eq $want ]] || fail "$* exited $status, expected $want: $(cat "$work/err.txt")"
  grep -qF -- "$part" "$work/err.txt" || fail "$*: no '$part' in: $(cat "$work/err.txt")"
  [[ ! -s $work/out.txt ]] || fail "$* printed a summary: $(cat "$work/out.txt")"
}
