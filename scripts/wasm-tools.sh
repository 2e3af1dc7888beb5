# Sourced by serve.sh, build-pkg.sh and test-web.sh: installs what the wasm
# build needs (skipping what is present) and builds it.

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

# The flags of every wasm32 build here, set whole so that no RUSTFLAGS of
# the caller changes the bytes: the committed web/pkg/ must be what any
# checkout builds. Workspace paths reach the wasm (panic locations) relative
# already; the registry's are absolute under CARGO_HOME, which differs
# between machines, so they are remapped to a fixed prefix. Encoded (fields
# separated by 0x1f) so that a CARGO_HOME with spaces stays one argument.
wasm_cargo() {
  local home=${CARGO_HOME:-$HOME/.cargo}
  CARGO_ENCODED_RUSTFLAGS="--remap-path-prefix=$home=/cargo" cargo "$@"
}

# build_wasm_into WEB_DIR [NODE_DIR]: release build of hrla-wasm, then
# wasm-bindgen --target web into WEB_DIR (and --target nodejs into NODE_DIR).
build_wasm_into() {
  wasm_cargo build --release --target wasm32-unknown-unknown -p hrla-wasm
  local wasm="$TARGET_DIR/wasm32-unknown-unknown/release/hrla_wasm.wasm"
  rm -rf "$1"
  # The name section only serves debuggers: a third of the file.
  wasm-bindgen --target web --remove-name-section --remove-producers-section \
    --out-dir "$1" "$wasm"
  if [ -n "${2:-}" ]; then
    wasm-bindgen --target nodejs --out-dir "$2" "$wasm"
  fi
}

# build_wasm [NODE_DIR]: web/pkg/ rebuilt from the sources, with the stamp
# that lets serve.sh serve it without Rust (scripts/pkg-stamp.mjs); with
# NODE_DIR, also a --target nodejs build there.
build_wasm() {
  # Hashed before the build: a source edited during it leaves a stamp that
  # does not match, so the next serve.sh rebuilds rather than serving a
  # package older than its stamp.
  local sources
  sources=$(node scripts/pkg-stamp.mjs sources)
  # Built beside web/pkg/ and swapped in whole: a failed build leaves the
  # old package, and no file of an older build lingers.
  build_wasm_into web/.pkg-new "${1:-}"
  node scripts/pkg-stamp.mjs write web/.pkg-new "$sources"
  rm -rf web/pkg
  mv web/.pkg-new web/pkg
  local f
  for f in web/pkg/hrla_wasm_bg.wasm web/pkg/hrla_wasm.js; do
    echo "$f: $(wc -c <"$f") bytes, $(gzip -9c "$f" | wc -c) gzip -9"
  done
}

# build_embedded_wasm DIR [FEATURES]: the firmware example's computation
# (crate hrla-embedded-wasm, test-only: never in web/pkg) for Node, into DIR.
# Bound before the next build overwrites the .wasm (the file name does not
# depend on the features).
build_embedded_wasm() {
  wasm_cargo build --quiet --release --target wasm32-unknown-unknown -p hrla-embedded-wasm \
    ${2:+--features "$2"}
  wasm-bindgen --target nodejs --out-dir "$1" \
    "$TARGET_DIR/wasm32-unknown-unknown/release/hrla_embedded_wasm.wasm"
}
