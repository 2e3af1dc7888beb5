#!/usr/bin/env bash
# Quality benchmark of the peers (scipy dual_annealing, scipy basinhopping,
# scipy differential_evolution, pycma IPOP-CMA-ES) on the problems of
# functions.py.
#
#   bench/quality/run_peers.sh                 # everything: all problems, d = 2 and 10
#                                              # (the problems of one dimension in theirs:
#                                              # rot_*, plateau, schwefel 10, lj7 21, lj13 39,
#                                              # gauss_fit 6), seeds 0-19, B = 10_000 and 125_000
#   bench/quality/run_peers.sh --seeds 0-4 --budgets 10000 --problems rastrigin,lj7
#
# Creates the virtualenv target/quality-venv (python3 -m venv; numpy, scipy
# and cma at the versions pinned in requirements.txt, from PyPI), checks the
# gradients (functions.py --check), runs peers.py into target/quality/peers.csv
# (or --out FILE) with any further arguments passed on, then prints the
# summary (summarize.py). Needs only python3 (>= 3.11) with pip, and PyPI.
# PYTHON=/path/to/python3 picks the interpreter.
set -euo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
root="$(cd "$here/../.." && pwd)"
venv="$root/target/quality-venv"
py="${PYTHON:-python3}"

"$py" -c 'import sys; sys.exit(0 if sys.version_info >= (3, 11) else "run_peers.sh: Python >= 3.11 is needed (the pinned numpy and scipy need it)")'

if [[ ! -x "$venv/bin/python" ]]; then
    mkdir -p "$root/target"
    if ! "$py" -m venv "$venv"; then
        # Debian's python3 without python3-venv has no ensurepip: make the
        # venv without pip and install into it with this interpreter's pip.
        rm -rf "$venv"
        "$py" -m venv --without-pip "$venv"
    fi
fi
if [[ -x "$venv/bin/pip" ]] || "$venv/bin/python" -m pip --version >/dev/null 2>&1; then
    "$venv/bin/python" -m pip install --quiet --disable-pip-version-check -r "$here/requirements.txt"
else
    "$py" -m pip --python "$venv/bin/python" install --quiet --disable-pip-version-check -r "$here/requirements.txt"
fi

# One thread for numpy's BLAS (the problems are tiny; more threads only add noise).
export OMP_NUM_THREADS=1 OPENBLAS_NUM_THREADS=1 MKL_NUM_THREADS=1

out="$root/target/quality/peers.csv"
args=()
while [[ $# -gt 0 ]]; do
    case "$1" in
        --out) out="$2"; shift 2 ;;
        --out=*) out="${1#--out=}"; shift ;;
        *) args+=("$1"); shift ;;
    esac
done
mkdir -p "$(dirname "$out")"

"$venv/bin/python" "$here/functions.py" --check > /dev/null || {
    "$venv/bin/python" "$here/functions.py" --check
    echo "run_peers.sh: the problems' self-test failed" >&2
    exit 1
}
echo "uptime: $(uptime)" >&2
start=$(date +%s)
"$venv/bin/python" "$here/peers.py" --out "$out" ${args[@]+"${args[@]}"}
echo "run_peers.sh: $(( $(date +%s) - start )) s for peers.py; CSV: $out" >&2
"$venv/bin/python" "$here/summarize.py" "$out"
