#!/bin/bash
# Builds the reproduction tool, submits the job array (repro.sbatch) and
# queues the merge to run once every task has succeeded. Run from a login
# node, in the repository:
#   OUT=$SCRATCH/repro ARGS="all" tools/repro/slurm/submit.sh [sbatch options]
# e.g. `--array=0-63 --partition=short` to override the script's defaults.
set -euo pipefail
cd "$(dirname "$0")/../../.."
cargo build --release -p hrla-repro
export REPRO=${REPRO:-$PWD/target/release/repro} OUT=${OUT:-$PWD/repro-out} ARGS=${ARGS:-all}
array=$(sbatch --parsable --export=ALL "$@" tools/repro/slurm/repro.sbatch)
merge=$(sbatch --parsable --export=ALL --dependency="afterok:${array%%;*}" \
  --job-name=hrla-repro-merge --output=hrla-repro-merge-%j.log \
  --wrap "\"$REPRO\" $ARGS --out \"$OUT\" --merge")
echo "job array $array, merge $merge: tables in $OUT once both finish"
