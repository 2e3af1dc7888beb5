#!/usr/bin/env bash
# Peer harness: the HRLA step in numpy, numba and JAX beside this crate.
#
#   bench/peers/run.sh [--hrla-ns NS] [--hrla-ns-novalue NS] [-K STEPS] [--repeats N] [--only numpy,numba,jax]
#
# Without --hrla-ns the crate's figure is read from criterion's output under
# $CARGO_TARGET_DIR (default: <repo>/target), criterion/f64_d10/hrla_best/1000/new/estimates.json;
# produce it with `cargo bench -p hrla-bench -- 'f64/d10/hrla/'`.
set -euo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
venv="$here/.venv"
py="${PYTHON:-python3}"

if [[ ! -x "$venv/bin/python" ]]; then
    "$py" -m venv "$venv"
fi
# Quiet when everything is already installed at the pinned versions.
"$venv/bin/python" -m pip install --quiet --disable-pip-version-check -r "$here/requirements.txt"

# One thread per tool wherever the tool lets us say so.
export OMP_NUM_THREADS=1 OPENBLAS_NUM_THREADS=1 MKL_NUM_THREADS=1 NUMBA_NUM_THREADS=1
# intra_op_parallelism_threads is a TensorFlow option, not an XLA flag: XLA rejects it
# alone ("--intra_op_parallelism_threads" is an unknown flag), so only the Eigen switch is set.
export XLA_FLAGS="--xla_cpu_multi_thread_eigen=false"

echo "uptime: $(uptime)"
exec "$venv/bin/python" "$here/peers.py" "$@"
