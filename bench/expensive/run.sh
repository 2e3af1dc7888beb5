#!/usr/bin/env bash
# Evaluations to a target on expensive functions (problems.py: an ODE fit
# with solve_ivp, a 10-parameter fit of three peaks, an 8-atom Lennard-Jones
# cluster): hrla against scipy dual_annealing, differential_evolution and
# pycma IPOP-CMA-ES, every call of fun counted (run.py's docstring).
#
#   scripts/test-python.sh -k nothing      # builds hrla from source into $CARGO_TARGET_DIR/python-venv
#   nice -n 10 bench/expensive/run.sh      # everything: peaks and lj8 with seeds 0-19; ode with
#                                          # seeds 0-19, CMA-ES 0-9 only; cap 20 000 calls, 2 jobs
#   bench/expensive/run.sh --problems lj8 --seeds 0-4 --methods hrla,dual-annealing
#
# Runs in the virtualenv of scripts/test-python.sh ($CARGO_TARGET_DIR, or
# target/, /python-venv; PYTHON=/path/to/python picks another one that has
# hrla), into which it installs numpy, scipy and cma at the versions of
# bench/quality/requirements.txt. Writes target/expensive/runs.csv (or
# --out FILE; further arguments go to run.py), then prints the summary
# (summarize.py). The ODE takes about 7 ms a call, and CMA-ES runs to the
# cap there (3 to 6 minutes a run): the full run takes about 80 minutes on
# two busy cores.
set -euo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
root="$(cd "$here/../.." && pwd)"
target=$(realpath -m "${CARGO_TARGET_DIR:-$root/target}")
py="${PYTHON:-$target/python-venv/bin/python}"
if ! "$py" -c "import hrla" 2>/dev/null; then
    echo "run.sh: $py cannot import hrla; build it first with scripts/test-python.sh -k nothing" >&2
    exit 1
fi
"$py" -m pip install --quiet --disable-pip-version-check -r "$root/bench/quality/requirements.txt"
export OMP_NUM_THREADS=1 OPENBLAS_NUM_THREADS=1 MKL_NUM_THREADS=1

out="$root/target/expensive/runs.csv"
args=()
while [[ $# -gt 0 ]]; do
    case "$1" in
        --out) out="$2"; shift 2 ;;
        --out=*) out="${1#--out=}"; shift ;;
        *) args+=("$1"); shift ;;
    esac
done
mkdir -p "$(dirname "$out")"
echo "uptime: $(uptime)" >&2
if [[ ${#args[@]} -eq 0 ]]; then
    "$py" "$here/run.py" --out "$out" --problems peaks,lj8 --seeds 0-19 --jobs 2
    "$py" "$here/run.py" --out "$out" --append --problems ode --seeds 0-9 --jobs 2
    "$py" "$here/run.py" --out "$out" --append --problems ode --seeds 10-19 \
        --methods hrla,dual-annealing,differential-evolution --jobs 2
else
    "$py" "$here/run.py" --out "$out" "${args[@]}"
fi
"$py" "$here/summarize.py" "$out"
