#!/usr/bin/env bash
# A sharded `persp accuracy` sweep as a Slurm array job (docs/SWEEPS.md):
# task K of N measures every N-th row; the last step merges the slices into
# the JSON the unsharded run writes, and can build the page from it.
#
#   sbatch --array=1-16 scripts/slurm_sweep.sh            # the slices
#   sbatch --dependency=afterok:JOBID scripts/slurm_sweep.sh merge
#
# PERSP (the binary), SWEEP_DIR (shared folder) and SWEEP_ARGS may be set in
# the environment; SWEEP_ARGS must be the same for every task.
#SBATCH --job-name=persp-sweep
#SBATCH --cpus-per-task=1
#SBATCH --time=01:00:00
#SBATCH --output=persp-sweep-%A_%a.log
set -eu
persp="${PERSP:-persp}"
dir="${SWEEP_DIR:-sweep}"
args="${SWEEP_ARGS:---case paper-quad,random-triangles,corridor,floor --triangles 400}"
mkdir -p "$dir"

if [ "${1:-}" = "merge" ]; then
    # shellcheck disable=SC2086
    "$persp" merge -o "$dir/accuracy.json" "$dir"/shard-*.json
    "$persp" report --from "$dir" -o "$dir/page"
    exit 0
fi

k="${SLURM_ARRAY_TASK_ID:?run as an array job: sbatch --array=1-N}"
n="${SLURM_ARRAY_TASK_COUNT:?run as an array job: sbatch --array=1-N}"
# Slurm's array ids are those of --array; the shard numbers are 1..N.
k=$((k - ${SLURM_ARRAY_TASK_MIN:-1} + 1))
# shellcheck disable=SC2086
# -o puts the file in place only once it is complete.
"$persp" accuracy $args --json --shard "$k/$n" -o "$dir/shard-$k-of-$n.json"
