#!/usr/bin/env bash
# The firmware example (examples/firmware/qemu) on three emulated cores: a
# Cortex-M3 (thumbv7m-none-eabi on QEMU's lm3s6965evb), a Cortex-M4F with
# its FPU (thumbv7em-none-eabihf on mps2-an386) and an RV32IMAC
# (riscv32imac-unknown-none-elf on virt). Builds every variant, runs each
# under QEMU, asserts that its result lines equal, byte for byte, those of
# the same computation on the host (examples/firmware/shared), checks the
# budgets, checks that docs/EMBEDDED.md quotes the firmware's guide code
# word for word, and prints the footprint table of the README and
# docs/EMBEDDED.md (also left in target/firmware-check/footprint.md).
# Installs qemu-system-arm, qemu-system-misc (RISC-V) and binutils
# (Debian) and the rustup targets when missing.
# Called by scripts/test.sh.
set -euo pipefail
cd "$(dirname "$0")/.."
root=$PWD

step() { printf '\n== %s\n' "$*"; }

# core -> rustup target, QEMU command (the ELF appended).
declare -A TARGET=(
  [cortex-m3]=thumbv7m-none-eabi
  [cortex-m4f]=thumbv7em-none-eabihf
  [riscv32]=riscv32imac-unknown-none-elf
)
# -icount shift=0: one guest instruction is 1 ns of virtual time, so the
# firmware's clock counts instructions, the same on every run.
qemu_common="-nographic -semihosting-config enable=on,target=native -icount shift=0 -kernel"
declare -A QEMU=(
  [cortex-m3]="qemu-system-arm -cpu cortex-m3 -machine lm3s6965evb $qemu_common"
  [cortex-m4f]="qemu-system-arm -cpu cortex-m4 -machine mps2-an386 $qemu_common"
  [riscv32]="qemu-system-riscv32 -machine virt -bios none $qemu_common"
)
CORES="cortex-m3 cortex-m4f riscv32"

step "firmware tools: qemu-system-arm, qemu-system-riscv32, readelf, nm, rustup targets"
missing=()
command -v qemu-system-arm >/dev/null || missing+=(qemu-system-arm)
command -v qemu-system-riscv32 >/dev/null || missing+=(qemu-system-misc)
# The host's binutils read the three cores' ELF files (generic ELF32).
command -v readelf >/dev/null && command -v nm >/dev/null || missing+=(binutils)
if ((${#missing[@]})); then
  sudo=""
  [ "$(id -u)" -eq 0 ] || sudo=sudo
  $sudo apt-get update -qq
  # No recommends: they pull in a desktop's worth of display libraries that
  # -nographic never uses.
  DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y -qq --no-install-recommends "${missing[@]}"
fi
installed=$(rustup target list --installed)
for core in $CORES; do
  grep -qx "${TARGET[$core]}" <<<"$installed" || rustup target add "${TARGET[$core]}"
done

# The firmware is its own workspace; share the root's target directory so
# that its host-side build scripts are not rebuilt in a second place.
target_dir=${CARGO_TARGET_DIR:-$root/target}
# $HRLA_FIRMWARE_OUT when scripts/test.sh sets it: test-web.sh then compares
# the wasm build's report with the QEMU outputs left there.
out=${HRLA_FIRMWARE_OUT:-$target_dir/firmware-check}
mkdir -p "$out"

step "firmware crate: format and lints (its own workspace), on every core"
(cd examples/firmware/qemu && cargo fmt -- --check)
for core in $CORES; do
  (cd examples/firmware/qemu &&
    cargo clippy --quiet --release --target "${TARGET[$core]}" --target-dir "$target_dir" \
      --all-targets --features fmt,micromath -- -D warnings &&
    cargo clippy --quiet --release --target "${TARGET[$core]}" --target-dir "$target_dir" \
      --all-targets --no-default-features --features f64,xoshiro256 -- -D warnings &&
    RUSTDOCFLAGS="-D warnings" cargo doc --quiet --no-deps --target "${TARGET[$core]}" \
      --target-dir "$target_dir")
done

checks=0

step "docs/EMBEDDED.md quotes the firmware's guide code word for word"
between() { # FILE BEGIN END: the lines strictly between the two marker lines
  awk -v b="$2" -v e="$3" 'index($0, e) { on = 0 } on { print } index($0, b) { on = 1 }' "$1"
}
between examples/firmware/qemu/src/main.rs "// guide: begin" "// guide: end" >"$out/guide.code.rs"
between docs/EMBEDDED.md "<!-- guide: begin -->" "<!-- guide: end -->" |
  sed '1{/^```rust$/d}; ${/^```$/d}' >"$out/guide.doc.rs"
if [ ! -s "$out/guide.code.rs" ] || ! diff -u "$out/guide.code.rs" "$out/guide.doc.rs"; then
  echo "error: the guide in docs/EMBEDDED.md is not the code between the guide markers" \
    "of examples/firmware/qemu/src/main.rs" >&2
  exit 1
fi
echo "ok: the guide is the firmware's code ($(wc -l <"$out/guide.code.rs") lines)"
checks=$((checks + 1))

diagnostic() { # diagnostic FILE LABEL... -> the value of "# LABEL... value"
  local file=$1
  shift
  awk -v k="# $*" 'substr($0, 1, length(k) + 1) == k " " { print $NF }' "$file"
}

table="| core | build | flash | static RAM | peak stack | RAM in all | instructions per chain-step | worst step (instructions) | steps over 84 000 |
|---|---|---:|---:|---:|---:|---:|---:|---:|"

# Budgets, so that "small" stays true: the README quotes the table. The
# Cortex-M4F's f32 build with the 32-bit generator has the goals: 24 KiB of
# flash, 3 KiB of RAM with the stack, 2 000 instructions per chain-step.
budget() { # budget CORE VARIANT -> "flash ram chain-step"
  local core=$1 variant=$2 flash=32768 ram=4096 insns
  case "$core/${variant%%+*}" in
    cortex-m4f/f32) insns=2000 ;;
    cortex-m4f/f64) insns=16000 ;;
    */f32) insns=10000 ;;
    *) insns=18000 ;;
  esac
  # RV32IMAC's soft-float routines and RVC code take more flash than Thumb-2.
  [ "$core" = riscv32 ] && flash=40960
  case "$variant" in *fmt*) flash=49152 ;; esac
  [ "$core/$variant" = cortex-m4f/f32 ] && flash=24576 ram=3072
  echo "$flash $ram $insns"
}

# The variants: every core runs f32 and f64 with each generator; the
# Cortex-M3 also with micromath and with core::fmt (their effect on flash),
# the Cortex-M4F with micromath in f32 (what it saves of the flash goal).
variants_of() {
  echo "f32 f64 f32+xoshiro256 f64+xoshiro256"
  case "$1" in
    cortex-m3) echo "f32+micromath f64+micromath f32+fmt f64+fmt" ;;
    cortex-m4f) echo "f32+micromath" ;;
  esac
}

for core in $CORES; do
  target=${TARGET[$core]}
  for variant in $(variants_of "$core"); do
    fp=${variant%%+*}
    extras=${variant#"$fp"}
    features=$fp${extras//+/,}
    name=$core.$variant
    step "firmware $name: build, run under QEMU, compare with the host"
    # From its own directory: cargo reads .cargo/config.toml from the
    # working directory, not from --manifest-path.
    (cd examples/firmware/qemu && cargo build --quiet --release --target "$target" \
      --target-dir "$target_dir" --no-default-features --features "$features")
    elf=$out/hrla-firmware-$name.elf
    cp "$target_dir/$target/release/hrla-firmware" "$elf"

    # Always under timeout: without semihosting QEMU never exits.
    # shellcheck disable=SC2086
    if ! timeout 120 ${QEMU[$core]} "$elf" >"$out/$name.qemu.txt" 2>"$out/$name.qemu.err"; then
      echo "error: the firmware ($name) failed under QEMU:" >&2
      cat "$out/$name.qemu.txt" "$out/$name.qemu.err" >&2
      exit 1
    fi
    cat "$out/$name.qemu.txt"

    rng=xoshiro128
    host_features=""
    case "$variant" in *xoshiro256*) rng=xoshiro256 ;; esac
    case "$variant" in *micromath*) host_features=micromath ;; esac
    host=$out/$fp${host_features:++$host_features}.$rng.host.txt
    cargo run --quiet --release -p hrla-embedded ${host_features:+--features $host_features} \
      --bin hrla-embedded-host -- --rng "$rng" "$fp" >"$host"
    grep -v '^#' "$out/$name.qemu.txt" >"$out/$name.qemu-results.txt" || true
    if [ "$(wc -l <"$host")" -ne 4 ]; then
      echo "error: the host printed no result for $fp" >&2
      exit 1
    fi
    if ! diff -u "$host" "$out/$name.qemu-results.txt"; then
      echo "error: firmware ($name, under QEMU) and host disagree" >&2
      exit 1
    fi
    echo "ok: firmware $name == host, bit for bit"
    checks=$((checks + 1))

    # Flash: every allocated section with contents (code, tables, the
    # .data image); static RAM: every allocated, writable one but the
    # stack and heap that riscv-rt reserves as sections.
    flash=0 static=0
    while read -r sec type size flags; do
      if [[ $flags == *A* && $type == PROGBITS ]]; then
        flash=$((flash + 16#$size))
      fi
      if [[ $flags == *A* && $flags == *W* && $sec != .stack && $sec != .heap ]]; then
        static=$((static + 16#$size))
      fi
    done < <(readelf -SW "$elf" | sed -n 's/^ *\[ *[0-9]*\] //p' | awk '{ print $1, $2, $5, $7 }')
    stack=$(diagnostic "$out/$name.qemu.txt" stack.peak)
    per_step=$(diagnostic "$out/$name.qemu.txt" "$fp" chain-step.instructions)
    worst=$(diagnostic "$out/$name.qemu.txt" "$fp" step.worst)
    overruns=$(diagnostic "$out/$name.qemu.txt" "$fp" budget.overruns)
    if [ -z "$stack" ] || [ -z "$per_step" ] || [ -z "$worst" ] || [ -z "$overruns" ]; then
      echo "error: the firmware ($name) printed no stack or instruction count" >&2
      exit 1
    fi
    read -r budget_flash budget_ram budget_insns <<<"$(budget "$core" "$variant")"
    if ((flash > budget_flash || static + stack > budget_ram || per_step > budget_insns)); then
      echo "error: firmware $name over budget: flash $flash (budget $budget_flash)," \
        "RAM with the stack $((static + stack)) ($budget_ram)," \
        "instructions per chain-step $per_step ($budget_insns)" >&2
      exit 1
    fi
    echo "ok: within budget (flash $flash <= $budget_flash, RAM $((static + stack)) <= $budget_ram," \
      "$per_step <= $budget_insns instructions per chain-step)"
    checks=$((checks + 1))
    table+="
| $core | $variant | $flash | $static | $stack | $((static + stack)) | $per_step | $worst | $overruns |"
  done
done

step "the counts are deterministic: a second run of each core's f32 build prints the same"
for core in $CORES; do
  # shellcheck disable=SC2086
  timeout 120 ${QEMU[$core]} "$out/hrla-firmware-$core.f32.elf" 2>/dev/null >"$out/$core.f32.again.txt"
  if ! diff "$out/$core.f32.qemu.txt" "$out/$core.f32.again.txt"; then
    echo "error: a second run of $core.f32 printed other counts" >&2
    exit 1
  fi
  echo "ok: $core: the same instructions, stack and results on a second run"
  checks=$((checks + 1))
done

step "host tests of the firmware's computation with micromath (without: in cargo test --workspace)"
cargo test --quiet -p hrla-embedded --features micromath --tests

step "micromath leaves f64 alone"
diff "$out/f64.xoshiro128.host.txt" "$out/f64+micromath.xoshiro128.host.txt"
echo "ok: f64 results identical with and without micromath"
checks=$((checks + 1))

step "the largest symbols in flash (Cortex-M4F f32, RISC-V f32)"
for name in cortex-m4f.f32 riscv32.f32; do
  echo "-- $name"
  nm -S --size-sort -C "$out/hrla-firmware-$name.elf" | tail -n 12
done

step "footprint (bytes; flash = text, with the vector table, + rodata + the .data image; static RAM = data + bss; RAM in all = static RAM + peak stack)"
echo "$table" | tee "$out/footprint.md"

# Every failure above exits at once, so reaching here means all passed.
echo
echo "firmware: $checks passed, 0 failed"
