#!/usr/bin/env bash
# slurm_shards.sh - one ppcr_bench run split over a Slurm cluster: a job array of N shards, then
# a merge job that starts when every shard has succeeded (docs/BENCHMARK.md, "Sharded runs").
#
#   tools/bench/slurm_shards.sh PROBLEMS N OUT_DIR [ppcr_bench flags...]
#
# Run it on the login node. It submits itself twice:
#   sbatch --array=0-$((N-1)) slurm_shards.sh ...     task I runs
#       ppcr_bench PROBLEMS flags --shard I/N --out OUT_DIR/shard_I.csv --quiet
#   sbatch --dependency=afterok:<array> slurm_shards.sh ...   (PPCR_SHARDS_STEP=merge) runs
#       ppcr_bench --merge OUT_DIR/shard_{0..N-1}.csv --out OUT_DIR/merged.csv
#     and writes the unsharded run's summary to OUT_DIR/summary.txt and OUT_DIR/summary.json.
# Logs: OUT_DIR/shard_I.log, OUT_DIR/merge.log. PROBLEMS and OUT_DIR must be on a file system the
# nodes share (the jobs start in the submission folder, so relative paths work). The binary is
# $PPCR_BENCH, else ppcr_bench on PATH; sbatch options (partition, account, ...) go in
# $PPCR_SBATCH_ARGS, e.g. PPCR_SBATCH_ARGS="--partition=short --time=02:00:00".
# Example: tools/bench/slurm_shards.sh data/bunny_local.txt 16 results/bunny \
#            --radius 0.02 --source-voxel 0.002 --target-voxel 0.002
# Checked with bash -n; sbatch --test-only where Slurm is installed.
#SBATCH --job-name=ppcr_bench
#SBATCH --ntasks=1
#SBATCH --cpus-per-task=1
#SBATCH --time=01:00:00
set -euo pipefail

usage() {
  echo "usage: $0 PROBLEMS N OUT_DIR [ppcr_bench flags...]  (N: number of shards, >= 1)" >&2
  exit 2
}
(($# >= 3)) || usage
problems=$1 shards=$2 out=$3
shift 3
[[ $shards =~ ^[1-9][0-9]*$ ]] || {
  echo "slurm_shards.sh: N = '$shards': expected a whole number >= 1" >&2
  usage
}
bench=${PPCR_BENCH:-ppcr_bench}

# A task of the array: one shard.
if [[ -n ${SLURM_ARRAY_TASK_ID:-} ]]; then
  exec "$bench" "$problems" "$@" --shard "$SLURM_ARRAY_TASK_ID/$shards" \
    --out "$out/shard_$SLURM_ARRAY_TASK_ID.csv" --quiet
fi

# The merge job: every shard's CSV, named so that a missing one is an error.
if [[ ${PPCR_SHARDS_STEP:-} == merge ]]; then
  csvs=()
  for ((k = 0; k < shards; ++k)); do csvs+=("$out/shard_$k.csv"); done
  "$bench" --merge "${csvs[@]}" --out "$out/merged.csv" > "$out/summary.txt.partial"
  "$bench" --merge "${csvs[@]}" --json > "$out/summary.json.partial"
  mv "$out/summary.txt.partial" "$out/summary.txt"
  mv "$out/summary.json.partial" "$out/summary.json"
  cat "$out/summary.txt"
  exit 0
fi

# The login node: submit the array, then the merge after it.
command -v sbatch > /dev/null || {
  echo "slurm_shards.sh: sbatch not found: run this on a Slurm login node" >&2
  exit 1
}
[[ -r $problems ]] || {
  echo "slurm_shards.sh: $problems: cannot read the problem file" >&2
  exit 1
}
mkdir -p "$out"
read -r -a extra <<< "${PPCR_SBATCH_ARGS:-}"
array=$(sbatch --parsable "${extra[@]}" --array="0-$((shards - 1))" \
  --output="$out/shard_%a.log" "$0" "$problems" "$shards" "$out" "$@")
array=${array%%;*}  # "<job id>;<cluster>" on multi-cluster setups
merge=$(sbatch --parsable "${extra[@]}" --dependency="afterok:$array" \
  --export=ALL,PPCR_SHARDS_STEP=merge --output="$out/merge.log" \
  "$0" "$problems" "$shards" "$out" "$@")
echo "slurm_shards.sh: shards: job array $array (0-$((shards - 1))), merge: job ${merge%%;*}" \
  "-> $out/summary.txt, $out/merged.csv"
