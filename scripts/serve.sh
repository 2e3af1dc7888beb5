#!/usr/bin/env bash
# Builds the wasm wrapper into web/pkg/ (installing the rustup target and
# wasm-bindgen-cli when missing) and serves the demo page on 127.0.0.1.
# Port: $PORT, default 8000 (another free one if that is taken).
set -euo pipefail
cd "$(dirname "$0")/.."
source scripts/wasm-tools.sh

ensure_wasm_target
ensure_wasm_bindgen
build_wasm
exec node scripts/static-server.mjs web "${PORT:-8000}"
