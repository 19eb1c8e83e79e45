#!/usr/bin/env bash
# termination_study.sh - regenerates docs/TERMINATION.md's tables and docs/images/trace_*.png.
#
#   tools/termination_study.sh [BUILD_DIR]      (default build/study; Release)
#
# Every number and figure of docs/TERMINATION.md comes from this script's real runs of the built
# ppcr_bench (the benchmark protocol, 50 problems per set, for every termination variant, with
# the error models listed per variant) and ppcr_cli (--trace, for the figure cases). Nothing is simulated: the offline
# replay of the criteria on the fixed-100 traces (tools/termination_study.py) is only printed as
# a cross-check next to the real runs.
#
# Environment:
#   JOBS=2          benchmark runs in parallel (each with --threads 1)
#   SETS="bunny lidar"  MODELS="point plane"   subsets (for a quick look)
#   RAW_MODELS="point plane"  error models of the raw family's fixed 100 and authors'-rule runs
#   LIMIT=0         problems per set (0 = all 50; anything else is for testing only)
#   FORCE=0         1 = re-run everything (else a run is reused when its command line, the
#                   binaries and the problem file are unchanged: re-running is cheap)
#   NO_BUILD=0      1 = do not run cmake --build on BUILD_DIR
#   DATA=../shared/data   OUT=BUILD_DIR/termination_study   (raw results, traces, logs)
#   DOC=docs/TERMINATION.md  IMAGES=docs/images
set -euo pipefail

root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
cd "$root"
build=${1:-build/study}
jobs=${JOBS:-2}
sets=${SETS:-bunny lidar}
models=${MODELS:-point plane}
limit=${LIMIT:-0}
force=${FORCE:-0}
data=$(cd "${DATA:-$root/../shared/data}" && pwd)
out=${OUT:-$build/termination_study}
doc=${DOC:-docs/TERMINATION.md}
images=${IMAGES:-docs/images}
py=/usr/bin/python3
helper=$root/tools/termination_study.py
plot=$root/tools/plot_trace.py

say() { printf '[%s] %s\n' "$(date +%H:%M:%S)" "$*" >&2; }
die() { printf 'termination_study.sh: error: %s\n' "$*" >&2; exit 1; }

[[ $jobs =~ ^[1-9][0-9]*$ ]] || die "JOBS=$jobs: expected a positive integer"
[[ $limit =~ ^[0-9]+$ ]] || die "LIMIT=$limit: expected a number >= 0"
[[ -x $py ]] || die "$py not found (Debian: apt-get install python3-matplotlib python3-numpy)"
$py -c 'import numpy, matplotlib' 2>/dev/null ||
  die "$py cannot import numpy/matplotlib (Debian: apt-get install python3-matplotlib)"
[[ -x /usr/bin/time ]] || die "/usr/bin/time not found (Debian: apt-get install time)"
for f in bunny/bun045.ply bunny/bun000.ply bunny/bun045_gt.txt benchmark/bunny_local.txt \
         benchmark/lidar_local.txt; do
  [[ -f $data/$f ]] || die "$data/$f: missing (set DATA=...)"
done
[[ -f $doc ]] || die "$doc: missing (the prose is hand-written; only its GENERATED blocks are rewritten)"

start_s=$(date +%s)

# ------------------------------------------------------------------ build
if [[ ${NO_BUILD:-0} != 1 ]]; then
  if [[ ! -f $build/CMakeCache.txt ]]; then
    say "configuring $build (Release)"
    cmake -S . -B "$build" -DCMAKE_BUILD_TYPE=Release -DPPCR_BUILD_TESTS=OFF \
      -DPPCR_BUILD_BENCHMARKS=OFF -DPPCR_BUILD_PEERS=OFF > /dev/null
  fi
  grep -q 'CMAKE_BUILD_TYPE:STRING=Release' "$build/CMakeCache.txt" ||
    say "warning: $build is not a Release build: times are meaningless"
  say "building ppcr_cli and ppcr_bench in $build (-j2)"
  cmake --build "$build" -j 2 --target ppcr_cli ppcr_bench > "$build/termination_study_build.log" 2>&1 ||
    die "build failed: see $build/termination_study_build.log"
fi
cli=$build/tools/ppcr_cli
bench=$build/tools/bench/ppcr_bench
[[ -x $cli && -x $bench ]] || die "$cli / $bench not built"
stamp_bin=$(sha1sum "$cli" "$bench" | sha1sum | cut -c1-12)

mkdir -p "$out/runs" "$out/figures" "$images"
manifest=$out/manifest.tsv
: > "$manifest.new"
: > "$out/commands.txt"

# ------------------------------------------------------------------ the variants
# Protocol settings (the project's issues), and one inner tolerance for every criterion: the
# plane model's fine phase stops its inner solves at 1e-2 by default with the
# cost-drop criterion alone (--lm-fine-tolerance auto), and at 1e-5 with the others (fixed
# included); the study compares the criteria on the same solves, those of the authors' 1e-5
# (docs/TERMINATION.md has the defaults' figures with auto).
study_lm="--lm-fine-tolerance 0"
proto_bunny="--radius 0.02 --source-voxel 0.002 --target-voxel 0.002 --success-translation 0.002 $study_lm"
proto_lidar="--radius 1 --source-voxel 0.2 --target-voxel 0.2 --success-translation 0.1 $study_lm"
radius_bunny=0.02
radius_lidar=1

# family|label|models|flags. A family is a trajectory: the criterion decides only when to stop,
# but the motion guard (in EM mode it also ends the coarse phase) and the scale mode change the
# trajectory itself. The first line of each family (per set and model) is its fixed-100 run; it is
# run with --trace-dir (the oracle's trajectory, marked [traced] in the tables) and is also the
# table's fixed-100 row (tracing costs a little time: times are indicative only). A label ending
# in [trace] would keep a run out of the tables. models: the error models the variant is run with
# (intersected with MODELS; the list is trimmed to 13 variants to fit 2 shared cores: set a
# variant's models to "plane" to trim further). Library defaults: --error-model plane,
# --motion-guard 0.02, --criterion cost-drop (1 % x 10), --scale em. In raw mode there is no
# coarse phase: the motion guard only acts on the cost drop, and the raw fixed-100 trajectory
# serves every raw variant.
variants=$(cat <<'EOV'
default|fixed 100|point plane|--criterion fixed --max-iterations 100
default|cost drop 1 % x 10 (library default)|point plane|--criterion cost-drop
default|cost drop 1 % x 20 (paper Table 5)|point plane|--criterion cost-drop --patience 20
default|cost drop 1 % x 5|point plane|--criterion cost-drop --patience 5
default|MSE prev. /2 x 3|point plane|--criterion mse-prev
default|successful steps <= 1 x 3|point plane|--criterion successful-steps
default|cost drop 1 % x 10 + MSE prev. /2 x 3|point plane|--criterion cost-drop,mse-prev
paper|fixed 100, motion guard 0 (paper rule)|point plane|--criterion fixed --max-iterations 100 --motion-guard 0
paper|cost drop 1 % x 10, motion guard 0 (paper rule)|point plane|--criterion cost-drop --motion-guard 0
raw|fixed 100 (raw)|RAW_MODELS|--scale raw --criterion fixed --max-iterations 100
raw|cost drop 1 % x 10, motion guard 0 (raw: the authors' rule)|RAW_MODELS|--scale raw --criterion cost-drop --motion-guard 0
raw|cost drop 1 % x 10, motion guard 0.02 (raw)|point plane|--scale raw --criterion cost-drop
raw|MSE prev. /2 x 3 (raw)|point plane|--scale raw --criterion mse-prev
EOV
)
variants=${variants//RAW_MODELS/${RAW_MODELS:-point plane}}

# ------------------------------------------------------------------ run queue
# One job = one ppcr_bench run; a job is skipped when its stamp (command line + binaries +
# problem file) matches the stamp of a finished previous run.
queue=$out/queue.txt
: > "$queue"
declare -A seen_family
n_jobs=0
for set in $sets; do
  case $set in
    bunny) proto=$proto_bunny; radius=$radius_bunny ;;
    lidar) proto=$proto_lidar; radius=$radius_lidar ;;
    *) die "SETS: unknown set $set (bunny, lidar)" ;;
  esac
  problems=$data/benchmark/${set}_local.txt
  for model in $models; do
    [[ $model == point || $model == plane ]] || die "MODELS: unknown model $model (point, plane)"
    while IFS='|' read -r family label vmodels flags; do
      [[ -n $family ]] || continue
      [[ " $vmodels " == *" $model "* ]] || continue
      key=$set-$model-$family
      id=$(printf '%s' "$set $model $label $flags" | sha1sum | cut -c1-10)
      base=$out/runs/$set-$model-$id
      tracedir=-
      extra=""
      if [[ -z ${seen_family[$key]:-} ]]; then  # the family's first line: its traced fixed-100
        seen_family[$key]=1
        tracedir=$base.traces
        extra="--trace-dir $tracedir"
      fi
      lim=""
      [[ $limit != 0 ]] && lim="--limit $limit"
      cmd="$bench $problems $proto --error-model $model $flags --threads 1 --quiet --json --out $base.csv $lim $extra"
      printf '%s\n' "ppcr_bench ../shared/data/benchmark/${set}_local.txt $proto --error-model $model $flags --threads 1 --json${extra:+ --trace-dir DIR}" >> "$out/commands.txt"
      stamp="$cmd $stamp_bin $(sha1sum < "$problems" | cut -c1-12)"
      printf '%s\t%s\t%s\t%s\t%s\t%s\t%s\t%s\t%s\t%s\n' "$set" "$model" "$label" "$family" \
        "$flags" "$base.json" "$base.csv" "$tracedir" "$radius" "$base.time" >> "$manifest.new"
      if [[ $force != 1 && -s $base.json && -f $base.stamp && "$(cat "$base.stamp")" == "$stamp" ]]; then
        continue
      fi
      printf '%s\t%s\t%s\t%s\n' "$base" "$tracedir" "$stamp" "$cmd" >> "$queue"
      n_jobs=$((n_jobs + 1))
    done <<< "$variants"
  done
done
mv "$manifest.new" "$manifest"

run_one() {  # base tracedir stamp cmd
  local base=$1 tracedir=$2 stamp=$3 cmd=$4
  rm -f "$base.json" "$base.stamp"
  if [[ $tracedir != - ]]; then rm -rf "$tracedir"; mkdir -p "$tracedir"; fi
  # shellcheck disable=SC2086
  if ! /usr/bin/time -f '%e %U %S' -o "$base.time" $cmd > "$base.json.tmp" 2> "$base.err"; then
    printf 'FAILED: %s (see %s)\n' "$cmd" "$base.err" >&2
    return 1
  fi
  mv "$base.json.tmp" "$base.json"
  printf '%s' "$stamp" > "$base.stamp"
  printf '  done %s  %s\n' "$(basename "$base")" "$(cut -c1-140 "$base.json")" >&2
}
export -f run_one

total_runs=$(wc -l < "$manifest")
say "$total_runs benchmark runs in the study, $n_jobs to (re)run, $jobs at a time (threads 1 each)"
if [[ $n_jobs -gt 0 ]]; then
  # fixed-100 and traced runs (the longest) first, so that the parallel tail is short
  awk -F'\t' '{ print (($2 != "-" || $4 ~ /--criterion fixed/) ? 0 : 1) "\t" $0 }' "$queue" |
    sort -s -t$'\t' -k1,1n | cut -f2- |
    while IFS=$'\t' read -r base tracedir stamp cmd; do
      printf '%s\0%s\0%s\0%s\0' "$base" "$tracedir" "$stamp" "$cmd"
    done | xargs -0 -n 4 -P "$jobs" bash -c 'run_one "$@"' _ ||
    die "some benchmark runs failed (see the FAILED lines above)"
fi

# ------------------------------------------------------------------ figure cases (ppcr_cli)
say "figure cases: initial guesses and ppcr_cli --trace runs"
bun=$data/bunny
fig_flags="--radius 0.02 --source-voxel 0.002 --target-voxel 0.002 --threads 1"
$py "$helper" initial "$bun/bun045.ply" "$bun/bun045_gt.txt" 0 -o "$out/figures/initial_45.txt" > "$out/figures/initial_45.log"
$py "$helper" initial "$bun/bun045.ply" "$bun/bun045_gt.txt" 45 -o "$out/figures/initial_90.txt" > "$out/figures/initial_90.log"
$py "$helper" initial "$bun/bun045.ply" "$bun/bun045_gt.txt" 135 -o "$out/figures/initial_180.txt" > "$out/figures/initial_180.log"
cat "$out/figures"/initial_*.log >&2
: > "$out/figures/cases.tsv"
: > "$out/figures/commands.txt"
for model in point plane; do
  for case in 45 90 180; do
    for crit in fixed default; do
      name=bunny${case}_${model}_${crit}
      cflags="--error-model $model"
      [[ $crit == fixed ]] && cflags+=" --criterion fixed --max-iterations 100"
      # shellcheck disable=SC2086
      "$cli" "$bun/bun045.ply" "$bun/bun000.ply" $fig_flags $cflags \
        --initial "$out/figures/initial_$case.txt" --ground-truth "$bun/bun045_gt.txt" \
        --trace "$out/figures/$name.csv" --json --quiet > "$out/figures/$name.json" ||
        die "ppcr_cli failed on $name"
      printf 'ppcr_cli ../shared/data/bunny/bun045.ply ../shared/data/bunny/bun000.ply %s %s --initial initial_%s.txt --ground-truth ../shared/data/bunny/bun045_gt.txt --trace %s.csv\n' \
        "$fig_flags" "$cflags" "$case" "$name" >> "$out/figures/commands.txt"
      printf '%s\t%s\t%s\t%s\t%s\n' "$case" "$model" "$crit" "$out/figures/$name.csv" \
        "$out/figures/$name.json" >> "$out/figures/cases.tsv"
    done
  done
done

# ------------------------------------------------------------------ tables and figures
say "tables, oracle analysis and cross-check -> $doc"
$py "$helper" report "$manifest" --doc "$doc" --figures "$out/figures" \
  --commands "$out/commands.txt"
say "figures -> $images"
$py "$helper" figures "$manifest" --figures "$out/figures" --images "$images" --plot "$plot" >&2

elapsed=$(( $(date +%s) - start_s ))
$py "$helper" runtime "$doc" --seconds "$elapsed" --jobs "$jobs" --runs "$total_runs" \
  --reran "$n_jobs" --binary-stamp "$stamp_bin"
say "done in $((elapsed / 60)) min $((elapsed % 60)) s ($n_jobs of $total_runs benchmark runs executed)"
