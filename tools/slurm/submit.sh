#!/usr/bin/env bash
# Submits a sweep to Slurm: an array of N shards, and a merge job that runs when they have ended.
#   tools/slurm/submit.sh STUDY.yaml RESULTS N [extra sbatch options, e.g. --partition=cpu --cpus-per-task=8]
# Prints the two job ids; the table is RESULTS/merged/results.csv when the merge job has ended.
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
study=${1:?usage: submit.sh STUDY.yaml RESULTS N [sbatch options]}
results=${2:?usage: submit.sh STUDY.yaml RESULTS N [sbatch options]}
n=${3:?usage: submit.sh STUDY.yaml RESULTS N [sbatch options]}
shift 3
array=$(sbatch --parsable --array="0-$((n - 1))" "$@" "$here/sweep.sbatch" "$study" "$results")
array=${array%%;*}
merge=$(sbatch --parsable --dependency="afterany:$array" "$@" "$here/merge.sbatch" "$results")
echo "array job $array ($n shards), merge job ${merge%%;*}: $results/merged/results.csv"
