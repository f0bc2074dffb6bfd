#!/bin/bash
# Workers of one `glintlab tune` study, one per task of a Slurm job array (experiments/README.md, tune):
#   sbatch --array=1-8 experiments/slurm/tune.sh EXPERIMENT --base VARIANT --space KEY=RANGE ... \
#     --objectives M,M --trials N --study /shared/study --cache /shared/cache
# Every task joins the same study through Optuna's journal-file storage on the shared file system and
# stops when the study has N finished trials; a killed task loses only its running trial, which another
# task runs again. GLINTLAB: the CLI (default build/glintlab).
#SBATCH --cpus-per-task=2
set -euo pipefail
G=${GLINTLAB:-build/glintlab}
exec "$G" tune "$@" --storage journal
