#!/usr/bin/env bash
# One batch of a pcsim design search as a Slurm job array (pcsim design --evaluate-with):
#
#   pcsim design SPEC.toml --evaluate-with scripts/slurm/design_batch.sh --out OUT
#
# pcsim calls it as `design_batch.sh BATCH_DIR SPEC N` after writing the batch's N designs to
# BATCH_DIR/designs.csv; it submits an array of N single-CPU tasks (each runs `pcsim design SPEC
# --task BATCH_DIR --task-index I`, which writes BATCH_DIR/row-I.csv) and waits for it
# (sbatch --wait): its exit status is the array's. The search itself (the optimiser, the journal)
# stays in the calling pcsim; run that on a login node or in a one-CPU job. Set PCSIM to the
# pcsim executable if it is not on the compute nodes' PATH; SBATCH_* variables (partition,
# account, time) reach sbatch as usual.
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
dir=$1
spec=$2
n=$3
exec sbatch --wait --quiet --array=0-$((n - 1)) --chdir="$dir" "$here/design_task.sbatch" "$dir" "$spec"
