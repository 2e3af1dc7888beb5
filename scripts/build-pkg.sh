#!/usr/bin/env bash
# Rebuilds the committed web/pkg/ (the wasm wrapper for the page) and its
# stamp from the sources: run it after changing them (core/, dyn/, gpu/,
# wasm/, Cargo.toml, Cargo.lock; scripts/pkg-stamp.mjs lists exactly what
# counts), then commit web/pkg/. scripts/test-web.sh fails while the
# committed package is not what this builds. Installs the rustup target and
# wasm-bindgen-cli when missing.
set -euo pipefail
cd "$(dirname "$0")/.."
source scripts/wasm-tools.sh

ensure_wasm_target
ensure_wasm_bindgen
build_wasm
