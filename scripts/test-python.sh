#!/usr/bin/env bash
# The Python package: builds it from source with pip (maturin, PyO3) into a
# virtualenv of its own, then runs pytest, whose bit-identity tests compare
# it with the Rust crate (the `golden` example, run by the tests).
#
#   scripts/test-python.sh [pytest arguments]
#
# The virtualenv is $CARGO_TARGET_DIR/python-venv (default target/), the
# versions those of python/requirements.txt.
set -euo pipefail
cd "$(dirname "$0")/.."

target=$(realpath -m "${CARGO_TARGET_DIR:-target}")
venv="$target/python-venv"
py="${PYTHON:-python3}"

if ! "$py" -c 'import venv, ensurepip' 2>/dev/null; then
  # Debian's python3 splits venv and ensurepip out.
  apt-get update -qq && apt-get install -y -qq python3-venv >/dev/null
fi
if [[ ! -x "$venv/bin/python" ]]; then
  "$py" -m venv "$venv"
fi
# maturin, run by pip as the build backend, must be found on PATH.
export PATH="$venv/bin:$PATH"
pip() { "$venv/bin/python" -m pip --disable-pip-version-check "$@"; }
pip install --quiet -r python/requirements.txt
# A real build from source, as a user's `pip install ./python` does (without
# build isolation, so that it uses the pinned maturin).
pip install --quiet --no-build-isolation --force-reinstall --no-deps ./python

exec "$venv/bin/python" -m pytest python/tests -q -p no:cacheprovider "$@"
