#!/usr/bin/env bash
# Submit a pcsim EVA sweep as a Slurm job array of N shards and a dependent merge job.
#
#   scripts/slurm/submit_eva.sh N OUT_DIR -- pcsim eva arguments (case, --speed, --tension, …)
#
# Prints the merge job's id. The merged sweep lands in OUT_DIR/merged (eva.csv, cases/, the
# manifest); it is byte-identical to the unsharded run. Set PCSIM to the pcsim executable if it
# is not on the compute nodes' PATH.
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
n=$1
out=$2
shift 2
[ "${1:-}" = "--" ] && shift
mkdir -p "$out"
array=$(sbatch --parsable --array=0-$((n - 1)) --chdir="$out" "$here/eva_array.sbatch" "$out" -- "$@")
array=${array%%;*}
merge=$(sbatch --parsable --dependency=afterok:"$array" --chdir="$out" "$here/eva_merge.sbatch" "$out" "$n")
echo "${merge%%;*}"
