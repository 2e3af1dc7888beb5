#!/usr/bin/env bash
# GPU mode of the peer harness: JAX's HRLA step beside hrla-gpu, on one
# device, in one run (see README.md, "GPU mode").
#
#   bench/peers/gpu.sh [--chains 1e4,1e5,1e6,1e7] [-K STEPS] [--repeats N]
#                      [--dtypes float32,float64] [--prng threefry2x32|rbg]
#                      [--arithmetic ieee,fused]
#
# JAX runs on its default device: with JAX_PLATFORM=cuda, gpu.sh installs
# requirements-gpu.txt (jax[cuda12]) and JAX runs on the GPU; otherwise
# requirements.txt (jax[cpu]). PIP_ARGS passes options to pip (for an
# offline machine: PIP_ARGS="--no-index --find-links DIR"). hrla-gpu's
# benchmark is built with cargo's bench profile.
set -euo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
repo="$(cd "$here/../.." && pwd)"
venv="$here/.venv"
py="${PYTHON:-python3}"
requirements="$here/requirements.txt"
if [[ "${JAX_PLATFORM:-}" == cuda ]]; then
    venv="$here/.venv-cuda"
    requirements="$here/requirements-gpu.txt"
fi

if [[ ! -x "$venv/bin/python" ]]; then
    "$py" -m venv "$venv"
fi
# shellcheck disable=SC2086
"$venv/bin/python" -m pip install --quiet --disable-pip-version-check ${PIP_ARGS:-} -r "$requirements"

# wgpu's Vulkan backend warns without it; harmless, but noisy.
export XDG_RUNTIME_DIR="${XDG_RUNTIME_DIR:-/tmp}"
bin="$(cd "$repo" && cargo bench -p hrla-gpu --bench throughput --no-run --message-format=json 2>/dev/null \
    | "$py" -c 'import json, sys
for line in sys.stdin:
    m = json.loads(line)
    if m.get("reason") == "compiler-artifact" and m.get("executable") and m["target"]["name"] == "throughput":
        print(m["executable"])')"
if [[ -z "$bin" ]]; then
    echo "gpu.sh: cannot build hrla-gpu's throughput benchmark (cargo bench -p hrla-gpu --bench throughput --no-run)" >&2
    exit 1
fi
echo "uptime: $(uptime)"
cd "$here"
exec "$venv/bin/python" "$here/gpu.py" --hrla-gpu "$bin" "$@"
