#!/usr/bin/env bash
# Interleaved in-process A/B of Optimizer::step: this tree's kernel (new)
# against the kernel of a base commit (base), both linked into one binary.
#   bench/ab/run.sh <base-commit> [pairs]
# AB_CASES=substring picks cases; AB_RUSTFLAGS (default -C target-cpu=native)
# builds for another instruction set, e.g. "-C target-cpu=x86-64-v3".
# Prints, per case, the median ns per coordinate-step of each side and the
# median of the per-pair ratios new/base (see docs/PERFORMANCE.md, Noise).
set -euo pipefail
cd "$(dirname "$0")/../.."
base=${1:?base commit}
rm -rf target/ab-base
mkdir -p target/ab-base
git archive "$base" core | tar -x -C target/ab-base
# The base kernel as its own one-crate workspace, renamed so that both
# kernels fit in one lockfile.
git show "$base:Cargo.toml" \
  | sed -e 's/^members = .*/members = ["core"]/' -e '/^exclude = /d' > target/ab-base/Cargo.toml
sed -i 's/^name = "hrla"$/name = "hrla-base"/' target/ab-base/core/Cargo.toml
cd bench/ab
RUSTFLAGS="${AB_RUSTFLAGS:--C target-cpu=native}" cargo run --quiet --release --target-dir ../../target/ab -- "${2:-60}"
