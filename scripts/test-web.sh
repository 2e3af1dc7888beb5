#!/usr/bin/env bash
# The wasm wrapper and the demo page: bit-identity of the wasm build (in
# Node) with the native build, and the page in Debian's Chromium; and the
# firmware example's computation in wasm, bit-identical to the host's (and
# to the firmware's under QEMU when $HRLA_FIRMWARE_OUT names a firmware run,
# as scripts/test.sh arranges; without it, a WARNING says what was skipped).
# Installs what is missing: the rustup target, wasm-bindgen-cli, chromium,
# playwright-core (npm ci from the committed lock file).
# The page tests run on the committed web/pkg/, after web/tests/pkg.test.mjs
# has checked it against a fresh build (in target/web-tests/pkg-web/).
# Artefacts: build outputs in target/web-tests/, screenshots (desktop,
# phone, compare mode, each landscape) in target/web-screenshots/.
set -euo pipefail
cd "$(dirname "$0")/.."
source scripts/wasm-tools.sh

export HRLA_WEB_OUT="$PWD/$TARGET_DIR/web-tests"
case "$TARGET_DIR" in /*) HRLA_WEB_OUT="$TARGET_DIR/web-tests" ;; esac
mkdir -p "$HRLA_WEB_OUT"
export HRLA_WEB_SHOTS="$PWD/$TARGET_DIR/web-screenshots"
case "$TARGET_DIR" in /*) HRLA_WEB_SHOTS="$TARGET_DIR/web-screenshots" ;; esac

ensure_wasm_target
ensure_wasm_bindgen
# A fresh build beside the committed web/pkg/, not over it: pkg.test.mjs
# asserts that the two are the same bytes, and the page tests then run on
# the committed package, the one serve.sh serves.
build_wasm_into "$HRLA_WEB_OUT/pkg-web" "$HRLA_WEB_OUT/pkg-node"
for f in hrla_wasm_bg.wasm hrla_wasm.js; do
  echo "web/pkg/$f: $(wc -c <"web/pkg/$f") bytes, $(gzip -9c "web/pkg/$f" | wc -c) gzip -9"
done

# The native side of the bit-identity test.
cargo run --quiet -p hrla-wasm --example trace -- wasm/tests/trace-cases.txt \
  >"$HRLA_WEB_OUT/native-trace.txt"

# The firmware example's computation in wasm, without and with micromath, and
# the host's report of each variant (the variant names of test-firmware.sh), for
# web/tests/embedded.test.mjs. It also compares with the firmware's output
# under QEMU when $HRLA_FIRMWARE_OUT names it (scripts/test.sh does).
build_embedded_wasm "$HRLA_WEB_OUT/embedded-node"
build_embedded_wasm "$HRLA_WEB_OUT/embedded-node-micromath" micromath
mkdir -p "$HRLA_WEB_OUT/embedded"
for fp in f32 f64; do
  for features in "" micromath; do
    cargo run --quiet --release -p hrla-embedded ${features:+--features $features} \
      --bin hrla-embedded-host -- "$fp" >"$HRLA_WEB_OUT/embedded/$fp${features:++$features}.host.txt"
  done
  cargo run --quiet --release -p hrla-embedded --bin hrla-embedded-host -- --rng xoshiro256 "$fp" \
    >"$HRLA_WEB_OUT/embedded/$fp+xoshiro256.host.txt"
done

if [ ! -x /usr/bin/chromium ]; then
  echo "installing Debian's chromium (about a minute)"
  export DEBIAN_FRONTEND=noninteractive
  apt-get update -qq
  # A half-configured package left by an earlier run would block the install.
  apt-get install -y -qq chromium || { apt-get -y -qq --fix-broken install && apt-get install -y -qq chromium; }
fi

# Always: npm ci installs exactly the lock file (one package, a second or two).
(cd web/tests && npm ci --no-audit --no-fund)

# Without the firmware's output, embedded.test.mjs skips its QEMU
# comparisons: say so before the run and again at the end, where it is seen.
firmware_warning() {
  [ -n "${HRLA_FIRMWARE_OUT:-}" ] && return 0
  echo "WARNING: HRLA_FIRMWARE_OUT is not set: the 15 comparisons of the wasm build with the" \
    "firmware under QEMU (embedded <variant> on <core>: 'wasm in Node == firmware under QEMU')" \
    "are SKIPPED, since there is no fresh firmware output to compare with." \
    "To run them: scripts/test.sh (does both), or scripts/test-firmware.sh then" \
    "HRLA_FIRMWARE_OUT=$TARGET_DIR/firmware-check scripts/test-web.sh" >&2
}
firmware_warning
# A stale web/pkg/ fails every page test in its own way: say the one cause
# first and stop.
node --test web/tests/pkg.test.mjs
status=0
node --test $(ls web/tests/*.test.mjs | grep -vx web/tests/pkg.test.mjs) wasm/tests/*.test.mjs || status=$?
firmware_warning
exit "$status"
