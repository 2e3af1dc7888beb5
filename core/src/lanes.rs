//! What the target's float vectors are, for code that works in blocks of
//! coordinates which the compiler vectorises. Results never depend on these
//! choices: every block width sums in the same lanes, so the bits are the
//! same on every target.

/// Lanes of one 128-bit vector of `F` (SSE2, NEON, wasm SIMD128), the unit
/// the compiler vectorises; small, so that padding a short tail wastes
/// little.
pub(crate) const fn lanes<F>() -> usize {
    16 / core::mem::size_of::<F>()
}

/// Whether the target has 256-bit float vectors (AVX): blocks of two
/// [`lanes`] vectors.
pub(crate) const WIDE: bool = cfg!(target_feature = "avx");

/// Whether the target has 128-bit float vectors for blocks of [`lanes`]
/// coordinates; without them (Cortex-M, RISC-V, plain wasm32) a block is one
/// coordinate.
pub(crate) const VECTORS: bool = cfg!(any(
    target_arch = "x86_64",
    target_arch = "aarch64",
    target_feature = "sse2",
    target_feature = "simd128",
    all(target_arch = "arm", target_feature = "neon")
));
