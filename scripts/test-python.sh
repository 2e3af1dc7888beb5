#!/usr/bin/env bash
# The Python package: builds its abi3 wheel (maturin, PyO3, release) into
# $CARGO_TARGET_DIR/wheels, installs it into a virtualenv of its own and
# runs pytest, whose bit-identity tests compare it with the Rust crate
# (the `golden` example, run by the tests); checks the stubs with
# `mypy --strict` on an example; then installs the same wheel into a
# fresh virtualenv with no Rust toolchain on PATH and runs one
# minimisation there.
#
#   scripts/test-python.sh [pytest arguments]
#
# The virtualenvs are $CARGO_TARGET_DIR/python-venv (default target/) and
# $CARGO_TARGET_DIR/wheel-venv (made anew each time), the versions those of
# python/requirements.txt.
set -euo pipefail
cd "$(dirname "$0")/.."

target=$(realpath -m "${CARGO_TARGET_DIR:-target}")
venv="$target/python-venv"
wheels="$target/wheels"
py="${PYTHON:-python3}"

if ! "$py" -c 'import venv, ensurepip' 2>/dev/null; then
  # Debian's python3 splits venv and ensurepip out.
  apt-get update -qq && apt-get install -y -qq python3-venv >/dev/null
fi
if [[ ! -x "$venv/bin/python" ]]; then
  "$py" -m venv "$venv"
fi
pip() { "$venv/bin/python" -m pip --disable-pip-version-check "$@"; }
pip install --quiet -r python/requirements.txt

# One release build: the wheel a user installs, tested here as it is.
rm -rf "$wheels"
"$venv/bin/maturin" build --release --quiet -m python/Cargo.toml --interpreter "$venv/bin/python" --out "$wheels"
wheel=$(ls "$wheels"/hrla-*-abi3-*.whl)
pip install --quiet --force-reinstall --no-deps "$wheel"

"$venv/bin/python" -m pytest python/tests -q -p no:cacheprovider "$@"

# The annotations and stubs, as a user's type checker reads them.
(cd python && "$venv/bin/python" -m mypy --strict --no-incremental hrla examples/scipy_user.py)

# The wheel in a fresh virtualenv, with no Rust toolchain to fall back on.
fresh="$target/wheel-venv"
rm -rf "$fresh"
"$py" -m venv "$fresh"
numpy=$(grep '^numpy==' python/requirements.txt)
# pip's own settings (an index, a certificate) pass; nothing else does.
mapfile -t pip_env < <(env | grep '^PIP_' || true)
env -i HOME="$HOME" PATH="$fresh/bin:/usr/bin:/bin" "${pip_env[@]}" bash -euo pipefail -c '
  if command -v cargo || command -v rustc; then echo "a Rust toolchain is on PATH" >&2; exit 1; fi
  python -m pip --disable-pip-version-check install --quiet "$1" "$2"
  cd /
  python -c "
import hrla, numpy as np
res = hrla.minimize(lambda x: float(np.sum((x - 0.5) ** 2)), [(-2, 2)] * 3, rng=1, maxfun=5_000)
assert res.success and res.fun < 1e-10, res
print(\"wheel\", hrla.__version__, \"in a fresh virtualenv: f =\", res.fun, \"after\", res.nfev, \"calls\")
"' _ "$numpy" "$wheel"
