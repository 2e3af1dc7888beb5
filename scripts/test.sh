#!/usr/bin/env bash
# Every test of the project, from a fresh machine: installs what it needs.
# Called by .ci/run; the README's test command.
set -euo pipefail
cd "$(dirname "$0")/.."

step() { printf '\n== %s\n' "$*"; }

# Every test runner's output also goes to LOG, so that the last line can sum
# up the whole run (cargo prints one "test result" line per test binary).
LOG=$(mktemp)
trap 'rm -f "$LOG"' EXIT

EMBEDDED_TARGETS="thumbv7em-none-eabihf riscv32imac-unknown-none-elf wasm32-unknown-unknown"

step "toolchain components and targets"
rustup component add rustfmt clippy >/dev/null 2>&1 || true
installed=$(rustup target list --installed)
for t in $EMBEDDED_TARGETS; do
  grep -qx "$t" <<<"$installed" || rustup target add "$t"
done

step "format, lints, docs"
cargo fmt --all -- --check
cargo clippy --workspace --all-targets -- -D warnings
RUSTDOCFLAGS="-D warnings" cargo doc --workspace --no-deps --quiet

step "the kernel builds no_std, without alloc, for every embedded target"
for t in $EMBEDDED_TARGETS; do
  for features in "" "micromath"; do
    echo "hrla --target $t ${features:+--features $features}"
    cargo build --quiet -p hrla --release --target "$t" ${features:+--features "$features"}
  done
  # A successful build does not prove it: look for std/alloc in the feature graph.
  if cargo tree -p hrla -e features,no-dev --target "$t" --features micromath \
      | grep -E 'feature "(std|alloc)"'; then
    echo "error: std or alloc is enabled in hrla's dependency graph for $t" >&2
    exit 1
  fi
done

step "a software Vulkan (lavapipe) for the GPU backend's tests"
# hrla-gpu's tests run on whatever adapter wgpu finds and fail, loudly, when
# there is none: without a GPU, Mesa's lavapipe and the Vulkan loader.
vulkan_packages="mesa-vulkan-drivers libvulkan1"
if ! dpkg -s $vulkan_packages >/dev/null 2>&1; then
  apt-get update -qq
  DEBIAN_FRONTEND=noninteractive apt-get install -y -qq $vulkan_packages >/dev/null
fi
# The Vulkan loader warns without a runtime directory.
export XDG_RUNTIME_DIR="${XDG_RUNTIME_DIR:-$(mktemp -d)}"

step "host tests (unit, doc, statistical, optimiser, property)"
cargo test --workspace 2>&1 | tee -a "$LOG"

# Where test-firmware.sh leaves the firmware's output under QEMU, for
# test-web.sh to compare the wasm build of the same computation with it.
export HRLA_FIRMWARE_OUT
HRLA_FIRMWARE_OUT=$(realpath -m "${CARGO_TARGET_DIR:-target}")/firmware-check

step "firmware: Algorithm 1 on an emulated Cortex-M3, Cortex-M4F and RISC-V core, bit-identical to the host"
./scripts/test-firmware.sh 2>&1 | tee -a "$LOG"

step "wasm wrapper and demo page (bit-identity in Node, the page in Chromium), firmware computation in wasm"
./scripts/test-web.sh 2>&1 | tee -a "$LOG"

step "Python package: the abi3 wheel built from source, pytest on it (bit-identity with the Rust crate), mypy, the wheel in a fresh virtualenv"
./scripts/test-python.sh 2>&1 | tee -a "$LOG"

# cargo prints "test result: ok. N passed; M failed; K ignored; ...", node's
# TAP reporter "# pass N", "# fail M" and "# skipped K", the firmware script
# its own "firmware: N passed, M failed" (its QEMU comparisons are not cargo
# tests), pytest "N failed, M passed, K skipped in T s" (only the counts it
# has; errors count as failed). Ignored and skipped tests both count as
# skipped.
awk '/^test result:/ { p += $4; f += $6; s += $8 }
     /^# pass / { p += $3 }
     /^# fail / { f += $3 }
     /^# skipped / { s += $3 }
     /^firmware: [0-9]+ passed, [0-9]+ failed$/ { p += $2; f += $4 }
     /^=* *[0-9]+ (passed|failed|skipped|errors?)/ && / in [0-9.]+s/ {
       for (i = 1; i < NF; i++) {
         w = $(i + 1); sub(/,$/, "", w)
         if (w == "passed") p += $i
         else if (w == "failed" || w == "error" || w == "errors") f += $i
         else if (w == "skipped") s += $i
       }
     }
     END { printf "\nsummary: %d passed, %d failed, %d skipped\n", p, f, s }' "$LOG"
