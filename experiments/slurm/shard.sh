#!/bin/bash
# One shard of a run per task of a Slurm job array, then `merge` (experiments/README.md, resume and shards):
#   jid=$(sbatch --parsable --array=1-8 experiments/slurm/shard.sh EXPERIMENT OUT CACHE)
#   sbatch --dependency=afterok:$jid --wrap "build/glintlab merge OUT-* --out OUT"
# Task k runs `run --shard k/n` into OUT-k (n = the array's size); CACHE is the shared reference cache
# on the cluster's file system. --resume: a requeued task continues where it was killed.
# GLINTLAB: the CLI (default build/glintlab, from the folder sbatch was called in).
#SBATCH --cpus-per-task=2
set -euo pipefail
G=${GLINTLAB:-build/glintlab}
exec "$G" run "$1" --shard "${SLURM_ARRAY_TASK_ID}/${SLURM_ARRAY_TASK_COUNT}" --out "$2-${SLURM_ARRAY_TASK_ID}" \
  --cache "$3" --resume --no-report
