# Sourced by serve.sh and test-web.sh: installs what the wasm build needs
# (skipping what is present) and builds it.

# Where cargo puts its output (honours CARGO_TARGET_DIR, like cargo).
TARGET_DIR=${CARGO_TARGET_DIR:-target}

ensure_wasm_target() {
  rustup target list --installed | grep -qx wasm32-unknown-unknown \
    || rustup target add wasm32-unknown-unknown
}

# wasm-bindgen-cli must match the wasm-bindgen crate exactly (the generated
# glue and the custom section format change between versions), so the
# version is read from Cargo.lock.
wasm_bindgen_version() {
  awk '/^name = "wasm-bindgen"$/ { getline; gsub(/version = |"/, ""); print; exit }' Cargo.lock
}

ensure_wasm_bindgen() {
  local want have
  want=$(wasm_bindgen_version)
  if [ -z "$want" ]; then
    echo "error: no wasm-bindgen in Cargo.lock" >&2
    return 1
  fi
  have=$(wasm-bindgen --version 2>/dev/null | awk '{ print $2 }') || true
  if [ "$have" = "$want" ]; then
    return 0
  fi
  echo "installing wasm-bindgen-cli $want into ~/.cargo/bin (takes about 4 minutes, once)"
  # Not --locked: with it, resolution fails on a dependency version that
  # this machine's registry mirror lacks.
  cargo install wasm-bindgen-cli --version "$want"
}

# build_wasm: release build, then wasm-bindgen --target web into web/pkg/.
# With an argument DIR, also a --target nodejs build into DIR.
build_wasm() {
  cargo build --release --target wasm32-unknown-unknown -p hrla-wasm
  local wasm="$TARGET_DIR/wasm32-unknown-unknown/release/hrla_wasm.wasm"
  # The name section only serves debuggers: a third of the file.
  wasm-bindgen --target web --remove-name-section --remove-producers-section \
    --out-dir web/pkg "$wasm"
  if [ -n "${1:-}" ]; then
    wasm-bindgen --target nodejs --out-dir "$1" "$wasm"
  fi
}

# build_embedded_wasm DIR [FEATURES]: the firmware example's computation
# (crate hrla-embedded-wasm, test-only: never in web/pkg) for Node, into DIR.
# Bound before the next build overwrites the .wasm (the file name does not
# depend on the features).
build_embedded_wasm() {
  cargo build --quiet --release --target wasm32-unknown-unknown -p hrla-embedded-wasm \
    ${2:+--features "$2"}
  wasm-bindgen --target nodejs --out-dir "$1" \
    "$TARGET_DIR/wasm32-unknown-unknown/release/hrla_embedded_wasm.wasm"
}
