#!/usr/bin/env bash
# COCO's noiseless bbob suite (24 functions on [-5, 5]^d, coco-experiment's
# cocoex): hrla against pycma IPOP-CMA-ES, scipy dual_annealing and
# differential_evolution, each called as a scipy user would, every call of
# fun counted (run.py's docstring); then the runtime ECDFs as COCO draws
# them, 51 targets 10^(2 - 0.2k) on f - f_opt, against the "best 2009"
# reference of cocopp (ecdf.py's docstring).
#
#   scripts/test-python.sh -k nothing      # builds hrla from source into $CARGO_TARGET_DIR/python-venv
#   nice -n 10 bench/bbob/run.sh           # everything: d = 2, 5, 10, f1-24, instances 1-5,
#                                          # four solvers, 10^4 d calls a run (about 80 minutes)
#   nice -n 10 bench/bbob/run.sh --solvers hrla            # hrla alone, the same runs (about 3 minutes)
#   bench/bbob/run.sh --dims 2 --functions 15-19 --instances 1 --budget 1000
#   bench/bbob/run.sh --summary            # the tables and plots again, no run
#
# Options (others go to run.py as they are):
#   --dims LIST        dimensions (default 2,5,10)
#   --functions LIST   bbob functions, e.g. 1-24 or 1,8,15 (default 1-24)
#   --instances LIST   instance indices (default 1-5)
#   --solvers LIST     hrla,ipop-cma-es,dual-annealing,differential-evolution (default all)
#   --budget B         calls per run / d (default 10000)
#   --resume           keep the stored runs of the selection at this budget, run the rest
#   --estimate         print the time estimate from the stored runs, run nothing
#   --out FILE         the runs (default target/bbob/runs.jsonl)
#   --summary          run nothing; write the tables and plots from the stored runs
#
# Runs in the virtualenv of scripts/test-python.sh ($CARGO_TARGET_DIR, or
# target/, /python-venv; PYTHON=/path/to/python picks another one that has
# hrla), into which it installs bench/bbob/requirements.txt. The selected
# (solver, d, f, instance) runs replace those stored in target/bbob/runs.jsonl
# (JSON lines, every run's improvements of the best f - f_opt); the others
# stay. ecdf.py then merges them with docs/bbob/runs.csv (the committed
# runtimes to the targets, used for the runs the store lacks: a re-run of
# hrla alone is compared with the peers' committed runs) and writes
# docs/bbob/: runs.csv, ecdf.md (the tables), ecdf-dD.png and
# ecdf-groups-dD.png per dimension.
set -euo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
root="$(cd "$here/../.." && pwd)"
target=$(realpath -m "${CARGO_TARGET_DIR:-$root/target}")
py="${PYTHON:-$target/python-venv/bin/python}"

case "${1:-}" in
    -h|--help) sed -n '2,/^set -euo/p' "$0" | sed '$d; s/^# \{0,1\}//'; exit 0 ;;
esac

out="$root/target/bbob/runs.jsonl"
summary=0
dims="2,5,10" functions="1-24" instances="1-5" solvers="hrla,ipop-cma-es,dual-annealing,differential-evolution"
budget=10000
args=()
while [[ $# -gt 0 ]]; do
    case "$1" in
        --out) out="$2"; shift 2 ;;
        --out=*) out="${1#--out=}"; shift ;;
        --dims) dims="$2"; shift 2 ;;
        --functions) functions="$2"; shift 2 ;;
        --instances) instances="$2"; shift 2 ;;
        --solvers) solvers="$2"; shift 2 ;;
        --budget) budget="$2"; shift 2 ;;
        --summary) summary=1; shift ;;
        *) args+=("$1"); shift ;;
    esac
done

if [[ $summary -eq 0 && ",$solvers," == *",hrla,"* ]] && ! "$py" -c "import hrla" 2>/dev/null; then
    echo "run.sh: $py cannot import hrla; build it first with scripts/test-python.sh -k nothing" >&2
    exit 1
fi
"$py" -m pip install --quiet --disable-pip-version-check -r "$here/requirements.txt"
export OMP_NUM_THREADS=1 OPENBLAS_NUM_THREADS=1 MKL_NUM_THREADS=1 MPLBACKEND=Agg

cd "$root"
mkdir -p "$(dirname "$out")"
if [[ $summary -eq 0 ]]; then
    echo "uptime: $(uptime)" >&2
    "$py" "$here/run.py" --out "$out" --dims "$dims" --functions "$functions" --instances "$instances" \
        --solvers "$solvers" --budget "$budget" ${args[@]+"${args[@]}"}
    for a in ${args[@]+"${args[@]}"}; do [[ "$a" == --estimate ]] && exit 0; done
fi
"$py" "$here/ecdf.py" --store "$out" --docs "$root/docs/bbob"
