#!/usr/bin/env bash
# The firmware example (examples/firmware/qemu) on an emulated Cortex-M3: builds it
# for thumbv7m-none-eabi in every variant, runs each under QEMU's
# lm3s6965evb, asserts that its result lines equal, byte for byte, those of
# the same computation on the host (examples/firmware/shared), and prints the
# footprint table of the README. Installs qemu-system-arm,
# binutils-arm-none-eabi (Debian) and the rustup target when missing.
# Called by scripts/test.sh.
set -euo pipefail
cd "$(dirname "$0")/.."
root=$PWD

step() { printf '\n== %s\n' "$*"; }

step "firmware tools: qemu-system-arm, arm-none-eabi-size, thumbv7m-none-eabi"
missing=()
command -v qemu-system-arm >/dev/null || missing+=(qemu-system-arm)
command -v arm-none-eabi-size >/dev/null || missing+=(binutils-arm-none-eabi)
if ((${#missing[@]})); then
  sudo=""
  [ "$(id -u)" -eq 0 ] || sudo=sudo
  $sudo apt-get update -qq
  # No recommends: they pull in a desktop's worth of display libraries that
  # -nographic never uses.
  DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y -qq --no-install-recommends "${missing[@]}"
fi
rustup target list --installed | grep -qx thumbv7m-none-eabi || rustup target add thumbv7m-none-eabi

# The firmware is its own workspace; share the root's target directory so
# that its host-side build scripts are not rebuilt in a second place.
target_dir=${CARGO_TARGET_DIR:-$root/target}
# $HRLA_FIRMWARE_OUT when scripts/test.sh sets it: test-web.sh then compares
# the wasm build's report with the QEMU output left there.
out=${HRLA_FIRMWARE_OUT:-$target_dir/firmware-check}
mkdir -p "$out"

step "firmware crate: format and lints (its own workspace)"
(cd examples/firmware/qemu && cargo fmt -- --check &&
  cargo clippy --quiet --release --target-dir "$target_dir" --all-targets --features fmt,micromath -- -D warnings &&
  RUSTDOCFLAGS="-D warnings" cargo doc --quiet --no-deps --target-dir "$target_dir")

run_qemu() {
  # Always under timeout: without the semihosting flag QEMU never exits.
  # -icount shift=0 makes one guest instruction take 1 ns of virtual time,
  # so the firmware's SysTick counts instructions.
  timeout 120 qemu-system-arm -cpu cortex-m3 -machine lm3s6965evb -nographic \
    -semihosting-config enable=on,target=native -icount shift=0 -kernel "$1"
}

section() { # section SIZE_A_OUTPUT NAME -> bytes (0 when absent)
  awk -v s="$2" '$1 == s { print $2; found = 1 } END { if (!found) print 0 }' <<<"$1"
}

table="| build | flash: text | flash: rodata | flash total | static RAM (data + bss) | peak stack | instructions per run |
|---|---:|---:|---:|---:|---:|---:|"

checks=0
for fp in f32 f64; do
  for extra in "" micromath fmt; do
    features=$fp${extra:+,$extra}
    name=$fp${extra:++$extra}
    step "firmware $name: build, run under QEMU, compare with the host"
    # From its own directory: cargo reads .cargo/config.toml (target, linker
    # script) from the working directory, not from --manifest-path.
    (cd examples/firmware/qemu && cargo build --quiet --release --target-dir "$target_dir" \
      --no-default-features --features "$features")
    elf=$out/hrla-firmware-$fp${extra:+-$extra}.elf
    cp "$target_dir/thumbv7m-none-eabi/release/hrla-firmware" "$elf"

    if ! run_qemu "$elf" >"$out/$name.qemu.txt" 2>"$out/$name.qemu.err"; then
      echo "error: the firmware ($name) failed under QEMU:" >&2
      cat "$out/$name.qemu.txt" "$out/$name.qemu.err" >&2
      exit 1
    fi
    cat "$out/$name.qemu.txt"

    host_features=""
    [ "$extra" = micromath ] && host_features=micromath
    cargo run --quiet --release -p hrla-embedded ${host_features:+--features $host_features} \
      --bin hrla-embedded-host -- "$fp" >"$out/$name.host.txt"
    grep -v '^#' "$out/$name.qemu.txt" >"$out/$name.qemu-results.txt" || true
    if [ "$(wc -l <"$out/$name.host.txt")" -ne 4 ]; then
      echo "error: the host printed no result for $fp" >&2
      exit 1
    fi
    if ! diff -u "$out/$name.host.txt" "$out/$name.qemu-results.txt"; then
      echo "error: firmware ($name, under QEMU) and host disagree" >&2
      exit 1
    fi
    echo "ok: firmware $name == host, bit for bit"
    checks=$((checks + 1))

    sizes=$(arm-none-eabi-size -A "$elf")
    vt=$(section "$sizes" .vector_table)
    text=$(section "$sizes" .text)
    rodata=$(section "$sizes" .rodata)
    data=$(section "$sizes" .data)
    bss=$(section "$sizes" .bss)
    uninit=$(section "$sizes" .uninit)
    stack=$(awk '$2 == "stack.peak" { print $3 }' "$out/$name.qemu.txt")
    insns=$(awk -v k="$fp" '$2 == k && $3 == "instructions" { print $4 }' "$out/$name.qemu.txt")
    if [ -z "$stack" ] || [ -z "$insns" ]; then
      echo "error: the firmware ($name) printed no stack or instruction count" >&2
      exit 1
    fi
    # Budgets, so that "small" stays true: the README quotes the table.
    # Static RAM holds the 16 chains (a static in the firmware: 1.1 KiB in
    # f32, 1.8 KiB in f64), the stack the optimiser that borrows them.
    flash=$((vt + text + rodata + data))
    budget_flash=32768
    [ "$extra" = fmt ] && budget_flash=49152
    if ((flash > budget_flash || data + bss + uninit > 2048 || stack > 6144)); then
      echo "error: firmware $name over budget: flash $flash > $budget_flash," \
        "static RAM $((data + bss + uninit)) > 2048 or stack $stack > 6144 bytes" >&2
      exit 1
    fi
    table+="
| $name | $((vt + text)) | $rodata | $((vt + text + rodata + data)) | $((data + bss + uninit)) | $stack | $insns |"
  done
done

step "host tests of the firmware's computation with micromath (without: in cargo test --workspace)"
cargo test --quiet -p hrla-embedded --features micromath --tests

step "micromath leaves f64 alone"
diff "$out/f64.host.txt" "$out/f64+micromath.host.txt"
echo "ok: f64 results identical with and without micromath"
checks=$((checks + 1))

step "the largest symbols in flash (f32, f64)"
for fp in f32 f64; do
  echo "-- $fp"
  arm-none-eabi-nm -S --size-sort -C "$out/hrla-firmware-$fp.elf" | tail -n 12
done

step "footprint (bytes; flash total = text + rodata + data image; text includes the 1 KiB vector table)"
echo "$table" | tee "$out/footprint.md"

# Every failure above exits at once, so reaching here means all passed.
echo
echo "firmware: $checks passed, 0 failed"
