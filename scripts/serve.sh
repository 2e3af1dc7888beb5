#!/usr/bin/env bash
# Serves the demo page on 127.0.0.1. Port: $PORT, default 8000 (another free
# one if that is taken).
#
# web/pkg/ (the wasm wrapper, built by wasm-bindgen) is committed with a stamp
# of the sources it was built from: when they are unchanged, the page is
# served at once and Node is all this needs. When they have changed, it
# rebuilds web/pkg/ first, as scripts/build-pkg.sh does (installing the
# rustup target and wasm-bindgen-cli when missing).
set -euo pipefail
cd "$(dirname "$0")/.."

if ! command -v node >/dev/null; then
  echo "error: serving the page needs Node.js: install it, then run scripts/serve.sh again." \
    "(Rebuilding web/pkg/ after a source change, scripts/build-pkg.sh, needs it too.)" >&2
  exit 1
fi

if why=$(node scripts/pkg-stamp.mjs check 2>&1); then
  echo "web/pkg/ matches the sources: serving it as committed"
else
  echo "web/pkg/ needs a rebuild: $why"
  if ! command -v cargo >/dev/null; then
    echo "error: rebuilding web/pkg/ needs Rust (cargo and rustup, https://rustup.rs): install it," \
      "then run scripts/build-pkg.sh (or scripts/serve.sh again, which runs the same build)." >&2
    exit 1
  fi
  source scripts/wasm-tools.sh
  ensure_wasm_target
  ensure_wasm_bindgen
  build_wasm
  echo "web/pkg/ rebuilt; commit it with the sources (scripts/build-pkg.sh rebuilds it alone)"
fi
exec node scripts/static-server.mjs web "${PORT:-8000}"
